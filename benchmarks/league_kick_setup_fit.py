"""Fit the 2D body's kick set-up to the league kick's: ``kick_prep_time`` of a profile.

A league kick (``teamenv.league.kick``) is not a motion that starts where the team asks: the
robot walks to the kick spot, the network hands the walk over to the kick's own walker, and
the strike waits for a swing of the kicking foot, so the ball lies within the team's kick
reach for a while before the foot meets it. ``teamenv.league.replay.kick_setups`` measures
that **set-up time** in any replay, league or teamenv: from the row the kicker last came
within the profile's ``kick_reach`` of the ball (and stayed there, upright, in play) to the
kick's contact row.

In teamenv the set-up is the team's own time to ask (it asks within 0.95 of the reach, lined
up) plus a cycle's latency plus ``kick_prep_time``, during which the body stands still; so
teamenv's set-up is not ``kick_prep_time`` itself, and the team's part (holding the ball,
turning to line up) is in both worlds' numbers. ``fit`` therefore plays the pairings of the
league replays again in teamenv (the study's env options, as ``league_fall_fit``; one match
per pairing of ``seconds``, on tuning seeds) for each ``kick_prep_time`` of a grid, measures
the same set-up times there, and takes the ``kick_prep_time`` at which teamenv's median
set-up time equals the league's (linear between the two grid points that bracket it; the
median, because both worlds have a tail of robots that stand by the ball without kicking,
which a mean over a few dozen kicks follows more than the body). Used by
``benchmarks/calibrate_t1_league.py --fit-kick-setup``::

    python benchmarks/calibrate_t1_league.py --skip-walk --skip-getup \\
        --replays study/league_replays --fit-kick-setup --fit-matches 10

``python benchmarks/league_kick_setup_fit.py --replays DIR --profile A.json B.json`` plays the
pairings under each profile and prints kicks, shots, goals and ball progress per match (both
teams) and the set-up time, against the league's per-match values scaled to the same length.
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import league_fall_fit  # noqa: E402  (the sibling script: pairings, teamenv replays of them)

#: kick_prep_time values (s) tried by default (each at most t1_league's kick_duration)
GRID: tuple[float, ...] = (0.5, 0.9, 1.3)
SEED0 = league_fall_fit.SEED0
#: per-match statistics compared (both teams together; teamenv.analytics.stats)
MATCH_KEYS = ("kicks", "shots", "goals", "ball_progress_m")


def setup_statistics(replays: Sequence[Any], reach: float) -> dict[str, Any]:
    """``kick_setup_summary`` of every kick in ``replays`` at ``reach`` (m)."""
    from teamenv.league.replay import kick_setup_summary, kick_setups

    return kick_setup_summary([s for r in replays for s in kick_setups(r, reach)])


def per_match(replays: Sequence[Any]) -> dict[str, float]:
    """Mean per match of ``MATCH_KEYS`` (both teams together) over ``replays``, and the
    matches' mean length in seconds of play (rows after the kick-off)."""
    from teamenv.analytics.stats import match_stats

    rows = []
    for replay in replays:
        teams = match_stats(replay).teams
        rows.append({k: float(sum(getattr(t, k) for t in teams)) for k in MATCH_KEYS})
    seconds = [float(np.count_nonzero(r.play_mode != 0)) * float(r.metadata["cycle_s"])
               for r in replays]
    return {k: round(float(np.mean([r[k] for r in rows])), 3) for k in MATCH_KEYS} | {
        "matches": len(rows), "seconds": round(float(np.mean(seconds)), 1)}


def scaled(values: dict[str, float], seconds: float) -> dict[str, float]:
    """``per_match`` values scaled from their matches' length to ``seconds``."""
    f = seconds / values["seconds"]
    return {k: round(values[k] * f, 3) for k in MATCH_KEYS} | {"seconds": seconds}


def with_prep(profile: dict[str, Any], prep: float) -> dict[str, Any]:
    out = json.loads(json.dumps(profile))
    out["parameters"]["kick_prep_time"]["value"] = prep
    return out


def play_profile(profile: dict[str, Any], matches: Sequence[tuple[str, str]], seconds: float,
                 team_size: int, seed0: int, folder: Path) -> list[Any]:
    """teamenv's replays of ``matches`` under ``profile`` (checked by the loader first)."""
    from locomotion.profile import load_profile

    path = folder / "candidate.json"
    path.write_text(json.dumps(profile))
    load_profile(path)   # a bad grid point fails here, named
    return league_fall_fit.play_replays(path, matches, seconds, team_size, seed0, folder)


def crossing(points: Sequence[tuple[float, float]], target: float) -> tuple[float, str]:
    """The x at which the piecewise-linear y(x) through ``points`` (x ascending) reaches
    ``target``, and how it was found; outside the points' range, the nearer end's x."""
    xs, ys = [p[0] for p in points], [p[1] for p in points]
    for (x0, y0), (x1, y1) in zip(points, points[1:], strict=False):
        if min(y0, y1) <= target <= max(y0, y1) and y1 != y0:
            return x0 + (target - y0) * (x1 - x0) / (y1 - y0), \
                f"linear between {x0:g} and {x1:g} s"
    k = int(np.argmin([abs(y - target) for y in ys]))
    return xs[k], f"the grid point nearest (the league's is outside the grid's {min(ys):g}-" \
        f"{max(ys):g} s)"


def fit(profile: dict[str, Any], replays: Sequence[Any], seconds: float = 60.0,
        grid: Sequence[float] = GRID, seed0: int = SEED0, matches: int | None = None,
        source: str = "league replays") -> tuple[dict[str, dict], dict[str, Any]]:
    """``kick_prep_time`` at which teamenv's median kick set-up time, on the pairings of the
    first ``matches`` (None: all) of ``replays``, equals the league's on those replays, as a
    profile entry, and the fit's record (the league's set-up over all ``replays`` and over
    the fitted ones, and every grid point's set-up and per-match statistics)."""
    from teamenv.seeds import TUNING_SEEDS

    reach = float(profile["parameters"]["kick_reach"]["value"])
    duration = float(profile["parameters"]["kick_duration"]["value"])
    league_all = setup_statistics(replays, reach)
    chosen = list(replays[:matches] if matches else replays)
    target = setup_statistics(chosen, reach)
    pairs = league_fall_fit.pairings(chosen)
    if not pairs or not target["n"]:
        raise SystemExit("--fit-kick-setup: no league kicks with a set-up to fit to")
    if any(not 0.0 <= g <= duration for g in grid):
        raise SystemExit(f"--fit-kick-setup: every grid point must lie in [0, kick_duration "
                         f"= {duration:g}] s: {list(grid)}")
    if seed0 not in TUNING_SEEDS or seed0 + len(pairs) - 1 not in TUNING_SEEDS:
        raise SystemExit(f"--fit-seed {seed0}: the fit's {len(pairs)} seeds must be tuning "
                         f"seeds ({TUNING_SEEDS.first}-{TUNING_SEEDS.end - 1})")
    team_size = int(replays[0].metadata["team_size"])
    points = []
    with tempfile.TemporaryDirectory() as tmp:
        for prep in sorted(grid):
            played = play_profile(with_prep(profile, prep), pairs, seconds, team_size, seed0,
                                  Path(tmp))
            setup = setup_statistics(played, reach)
            points.append({"kick_prep_time": prep, "setup": setup, "per_match": per_match(played)})
            print(f"fit: kick_prep_time {prep:g} s: set-up median {setup.get('median_s')} s, "
                  f"mean {setup.get('mean_s')} s, {setup['n']} kicks (league median "
                  f"{target['median_s']} s, mean {target['mean_s']} s)", flush=True)
    usable = [(p["kick_prep_time"], p["setup"]["median_s"]) for p in points
              if p["setup"]["n"]]
    if not usable:
        raise SystemExit("--fit-kick-setup: teamenv kicked in none of the fit's matches")
    value, how = crossing(usable, target["median_s"])
    value = round(min(max(value, 0.0), duration), 2)
    shown = ", ".join(f"{x:g}: {y:g}" for x, y in usable)
    source_text = (
        f"benchmarks/calibrate_t1_league.py --fit-kick-setup: the league kick's set-up time "
        f"(teamenv.league.replay.kick_setups: from the kicker's last arrival within kick_reach "
        f"{reach:g} m of the ball, upright and in play, to the contact) over {league_all['n']} "
        f"kicks of {len(replays)} league matches in {source} is median {league_all['median_s']}"
        f" s, mean {league_all['mean_s']} s (s.d. {league_all['std_s']}); kick_prep_time is "
        f"where teamenv's median set-up time on the pairings of the first {len(chosen)} "
        f"matches ({seconds:g} s each, tuning seeds {seed0}-{seed0 + len(pairs) - 1}) equals "
        f"the league's on those matches ({target['median_s']} s, {target['n']} kicks): "
        f"{how} of the grid (kick_prep_time: teamenv median set-up, s) {shown}")
    params = {"kick_prep_time": {"value": value, "unit": "s", "kind": "measured",
                                 "source": source_text}}
    record = {"league": league_all, "league_fitted": target, "grid": points,
              "seconds": seconds, "seed0": seed0, "matches": [list(m) for m in pairs],
              "source": source, "value": value, "how": how}
    return params, record


def main(argv: Sequence[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description="kicks, shots, goals, ball progress and the "
                                 "kick set-up time per match of the league replays' pairings "
                                 "played in teamenv under each profile, against the league's")
    ap.add_argument("--replays", required=True, help="a folder of league match replays")
    ap.add_argument("--profile", nargs="+", required=True, help="profile files to play")
    ap.add_argument("--seconds", type=float, default=60.0, help="game time of each match (s)")
    ap.add_argument("--seed", type=int, default=SEED0, help="first (tuning) seed")
    ap.add_argument("--matches", type=int, default=None, help="the first N pairings only")
    ap.add_argument("--json", default=None, help="also write the results here")
    args = ap.parse_args(argv)
    from locomotion.profile import load_profile

    sys.path.insert(0, str(Path(__file__).resolve().parent))
    from calibrate_t1_league import load_replays

    replays = load_replays(Path(args.replays))
    chosen = replays[:args.matches] if args.matches else replays
    pairs = league_fall_fit.pairings(chosen)
    team_size = int(replays[0].metadata["team_size"])
    out: dict[str, Any] = {"replays": str(args.replays), "seconds": args.seconds,
                           "seed0": args.seed, "matches": len(pairs), "profiles": {}}
    league = per_match(chosen)
    out["league"] = {"per_match": league, "scaled": scaled(league, args.seconds)}
    with tempfile.TemporaryDirectory() as tmp:
        for name in args.profile:
            profile = json.loads(Path(name).read_text())
            load_profile(name)
            reach = float(profile["parameters"]["kick_reach"]["value"])
            if "league_setup" not in out:
                out["league_setup"] = setup_statistics(chosen, reach)
            played = play_profile(profile, pairs, args.seconds, team_size, args.seed, Path(tmp))
            out["profiles"][name] = {
                "kick_prep_time": profile["parameters"]["kick_prep_time"]["value"],
                "per_match": per_match(played), "setup": setup_statistics(played, reach)}
            print(name, json.dumps(out["profiles"][name]), flush=True)
    print(f"league ({len(pairs)} matches, scaled to {args.seconds:g} s):",
          json.dumps(out["league"]["scaled"]), "set-up:", json.dumps(out["league_setup"]))
    if args.json:
        Path(args.json).write_text(json.dumps(out, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
