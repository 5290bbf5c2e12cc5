"""Fit the expected-goals model (teamenv/analytics/xg_model.json) on seeded simulated play.

    python benchmarks/xg_fit.py --replay-dir /tmp/xg --matches 24 -j 2
    python benchmarks/xg_fit.py --replay-dir /tmp/xg --write     # fit what is there, ship it

Data (seeds from ``--first-seed``, 6000: never used for tuning or evaluation):

``--matches`` matches of 2 x ``--half-time`` s (default 120) on ``--field`` (default
``simspark``: its 30 m pitch gives more kicks at goal per cycle than ``mj7v7``), 5 v 5, cycling
through the pairings full:chaser, full:full, chaser:full, full:silent. Each is recorded as a
replay in ``--replay-dir`` (a replay already there is reused, so runs add up). Every kick on frame (``MatchEvents.attempts``) is one example: features distance to
the goal's centre, opening angle between the posts, opponents in the shot cone; label: the
kick ended in a goal. The fit is scikit-learn's ``LogisticRegression`` (L2, C = 1, lbfgs);
the script prints the coefficients, the 5-fold cross-validated log loss and ROC AUC against
the base rate, and with ``--write`` stores the model with how it was fitted.
"""

from __future__ import annotations

import argparse
import os
import time
from collections.abc import Sequence
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

MATCH_PAIRINGS = (("full", "chaser"), ("full", "full"), ("chaser", "full"), ("full", "silent"))


def match_job(job: tuple[str, int, int, float, str]) -> str:
    """Play match ``k`` of the fit's data and write its replay (skipped when it exists)."""
    from teamenv.match import play_match

    replay_dir, k, first_seed, half_time, field = job
    seed = first_seed + k
    left, right = MATCH_PAIRINGS[k % len(MATCH_PAIRINGS)]
    path = Path(replay_dir) / f"{left}-{right}-{seed}.npz"
    if not path.exists():
        tmp = path.with_suffix(".tmp.npz")
        play_match(left, right, seed, {"field": field, "team_size": 5,
                                       "half_time_s": half_time}, replay_path=tmp)
        os.replace(tmp, path)
    return str(path)


def attempts_of(paths: Sequence[str]) -> tuple[np.ndarray, np.ndarray]:
    """Features and goal labels of every kick on frame in the replays."""
    from teamenv.analytics.events import match_events
    from teamenv.analytics.xg import kick_features
    from teamenv.replay import load_replay

    xs, ys = [], []
    for p in sorted(paths):
        attempts = match_events(load_replay(p)).attempts
        xs.append(kick_features(attempts))
        ys.extend(k.outcome == "goal" for k in attempts)
    return np.concatenate(xs) if xs else np.zeros((0, 3)), np.asarray(ys, bool)


def main(argv: Sequence[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--replay-dir", type=Path, required=True)
    parser.add_argument("--matches", type=int, default=0, help="matches to have recorded")
    parser.add_argument("--half-time", type=float, default=120.0)
    parser.add_argument("--field", default="simspark")
    parser.add_argument("--first-seed", type=int, default=6000)
    parser.add_argument("-j", "--jobs", type=int, default=2)
    parser.add_argument("--write", action="store_true",
                        help="write the fitted model to teamenv/analytics/xg_model.json")
    args = parser.parse_args(argv)
    args.replay_dir.mkdir(parents=True, exist_ok=True)
    start = time.perf_counter()
    with ProcessPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        list(pool.map(match_job, [(str(args.replay_dir), k, args.first_seed, args.half_time,
                                   args.field) for k in range(args.matches)]))
    paths = [str(p) for p in args.replay_dir.glob("*.npz") if not p.name.endswith(".tmp.npz")]
    x, y = attempts_of(paths)
    print(f"{len(paths)} replays, {len(y)} kicks on frame, {int(y.sum())} goals; played in "
          f"{time.perf_counter() - start:.0f} s")
    from sklearn.linear_model import LogisticRegression
    from sklearn.model_selection import StratifiedKFold, cross_validate

    from teamenv.analytics.xg import FEATURES, MODEL_PATH, fit_xg

    folds = min(5, int(y.sum()), int((~y).sum()))
    cv = {}
    if folds >= 2:
        scores = cross_validate(LogisticRegression(C=1.0, max_iter=1000), x, y,
                                cv=StratifiedKFold(folds, shuffle=True, random_state=0),
                                scoring=("neg_log_loss", "roc_auc"))
        base = float(y.mean())
        base_loss = -(base * np.log(base) + (1 - base) * np.log(1 - base))
        cv = {"folds": folds, "log_loss": float(-scores["test_neg_log_loss"].mean()),
              "base_rate_log_loss": float(base_loss),
              "roc_auc": float(scores["test_roc_auc"].mean())}
        print(f"{folds}-fold CV: log loss {cv['log_loss']:.3f} (base rate "
              f"{base_loss:.3f}), ROC AUC {cv['roc_auc']:.3f}")
    fitted = {
        "data": (f"{len(y)} kicks on frame ({int(y.sum())} goals) from {len(paths)} matches "
                 f"({args.field} 5 v 5, 2 x {args.half_time:g} s, pairings "
                 f"{', '.join(a + ':' + b for a, b in MATCH_PAIRINGS)} in turn, seeds "
                 f"{args.first_seed}..{args.first_seed + len(paths) - 1})"),
        "cross_validation": cv,
        "command": f"python benchmarks/xg_fit.py --replay-dir DIR --matches {len(paths)} "
                   f"--first-seed {args.first_seed} --half-time {args.half_time:g} --write",
    }
    model = fit_xg(x, y, fitted=fitted)
    for name, coef in zip(FEATURES, model.coefficients, strict=True):
        print(f"  {name:12s} {coef:+.4f}")
    print(f"  intercept    {model.intercept:+.4f}")
    for d in (2.0, 4.0, 6.0, 10.0, 15.0, 20.0):
        from teamenv.analytics.geometry import goal_distance_angle

        _, angle = goal_distance_angle((15.0 - d, 0.0), 1.0, 15.0, 1.05)  # simspark
        p0, p1 = model.probability(np.array([[d, angle, 0], [d, angle, 1]]))
        print(f"  frontal kick from {d:4.1f} m: xG {p0:.3f} (one blocker: {p1:.3f})")
    if args.write:
        print(f"wrote {model.save(MODEL_PATH)}")


if __name__ == "__main__":
    main()
