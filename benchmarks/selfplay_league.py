"""The self-play league's demo run: a 3 v 3 team trained against PFSP opponents (the clone of
``chaser``, then PPO; ``--learner ppo``: PPO from scratch, the first run), its rating curve,
and the rated-best snapshot evaluated in full matches on evaluation seeds.

    python benchmarks/selfplay_league.py --max-minutes 32          # train + rate (resumable)
    python benchmarks/selfplay_league.py --evaluate 40             # + 40 evaluation matches
    python benchmarks/selfplay_league.py --smoke                   # seconds: what CI runs
    python benchmarks/selfplay_league.py --learner ppo ...         # the first run's setup

Phases, each resumable by running the command again:

1. the league (``teamenv.selfplay``, the configuration in ``demo_config``) in ``--run-dir``,
   generation after generation until ``--generations`` or until ``--max-minutes`` of wall time
   have passed (checked after each generation; a generation started is finished);
2. the rating curve (``--curve``, a PNG) and the run's record (``--json``: per generation the
   opponents, PFSP probabilities, training outcomes, ratings, wall times);
3. with ``--evaluate N``: the trained snapshot (generation >= 1) with the highest
   Bradley–Terry rating (chosen on the rating matches, whose seeds lie outside the evaluation
   range) plays ``chaser`` and
   ``full`` N matches each on the evaluation seeds (``teamenv.seeds``), sides alternating
   (``teamenv.headtohead``), and the untrained snapshot 0 plays ``chaser`` on the same seeds
   (what training changed), and an imitation run's teacher plays ``chaser`` there too (what
   the clone was taught); the goal difference per match with a 95 % bootstrap interval
   (``scipy.stats.bootstrap``, BCa, over matches); the snapshot file and the per-seed report
   are written to ``--policy`` and ``--report``.
"""

from __future__ import annotations

import argparse
import json
import shutil
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import replace
from pathlib import Path

import numpy as np
from scipy.stats import bootstrap

from teamenv.match import MatchOptions, play_match
from teamenv.seeds import EVALUATION_SEEDS, evaluation_seeds
from teamenv.selfplay.config import LeagueConfig
from teamenv.selfplay.curve import plot_rating_curve
from teamenv.selfplay.league import generation_seed, run_league
from teamenv.selfplay.league_store import LEAGUE_DB, LeagueStore
from teamenv.selfplay.rating import RatingSetup, rating_tournament
from teamenv.selfplay.snapshots import SnapshotPool
from teamenv.selfplay.training_setup import TrainingSetup, option_actions
from teamenv.tournament.spec import parse_team_spec

#: The learners of the demo: "options" (5 v 5 on mj7v7: a network that chooses each field
#: player's open-play option for ``full_options``, cloned from full's own rule, then PPO),
#: "imitation" (3 v 3: PPO warm-started by cloning chaser, ``teamenv.selfplay.imitation``)
#: and "ppo" (3 v 3, from scratch: the first run).
LEARNERS = ("imitation", "ppo", "options")
#: The imitation learner's options beyond PPO's (the teacher and the clone).
IMITATION_OPTIONS = {"teacher": "chaser", "dagger_rounds": 2, "bc_epochs": 30,
                     "bc_log_std": -1.5}


#: The options run's training: 5 v 5 on the league's field (where ``full`` beats ``chaser``,
#: docs/selfplay.md), egocentric slots for every other player and the ball-race columns
#: without the clock and score (the rule it clones reads neither), one network scoring the
#: three open-play options of ``full_options`` every 5 cycles.
OPTIONS_TRAINING = TrainingSetup(field="mj7v7", team_size=5, episode_s=60.0, teammate_slots=4,
                                 opponent_slots=5, actions=option_actions(3),
                                 option_team="full_options", ball_race=True, game_state=False)
#: Its learner: the clone of the rule (three rounds: the rule's own, two DAgger), then PPO at
#: a learning rate that keeps it near the clone.
OPTIONS_LEARNER = {"copies": 4, "n_steps": 256, "batch_size": 512, "n_epochs": 5,
                   "learning_rate": 3e-5, "hidden": 128, "dagger_rounds": 3, "bc_epochs": 80,
                   "bc_log_std": -1.5}


def demo_config(smoke: bool, learner: str = "imitation") -> LeagueConfig:
    """The committed run's configuration (``smoke``: a seconds-long version of it)."""
    if learner not in LEARNERS:
        raise ValueError(f"learner {learner!r}: one of {LEARNERS}")
    if smoke:
        extra = {**IMITATION_OPTIONS, "dagger_rounds": 1, "bc_epochs": 2} \
            if learner == "imitation" else \
            {"learning_rate": 3e-5, "dagger_rounds": 1, "bc_epochs": 2} \
            if learner == "options" else {}
        training = TrainingSetup(team_size=3, episode_s=2.0) if learner != "options" else \
            replace(OPTIONS_TRAINING, team_size=3, episode_s=2.0)
        return LeagueConfig(
            seed=0, steps_per_generation=192, builtins=("chaser", "static"),
            training=training,
            rating=RatingSetup(half_time_s=5.0, halves=1, recent=1, n_bootstrap=20),
            learner="imitation" if learner == "options" else learner,
            learner_options={"copies": 1, "n_steps": 64, "batch_size": 64, "n_epochs": 2,
                             **extra})
    if learner == "options":
        return LeagueConfig(
            seed=0, steps_per_generation=40_000, builtins=("chaser", "static", "full"),
            training=OPTIONS_TRAINING,
            rating=RatingSetup(games_per_pairing=1, half_time_s=60.0, halves=2, recent=2),
            learner="imitation", learner_options=OPTIONS_LEARNER)
    if learner == "imitation":
        return LeagueConfig(
            seed=0, steps_per_generation=36_000, builtins=("chaser", "static", "full"),
            training=TrainingSetup(team_size=3, episode_s=60.0),
            rating=RatingSetup(games_per_pairing=1, half_time_s=45.0, halves=2, recent=2),
            learner="imitation",
            learner_options={"copies": 4, "n_steps": 256, "batch_size": 512, "n_epochs": 5,
                             "learning_rate": 3e-5, "hidden": 128, **IMITATION_OPTIONS})
    return LeagueConfig(
        seed=0, steps_per_generation=30_000, builtins=("chaser", "static", "full"),
        training=TrainingSetup(team_size=3, episode_s=60.0),
        rating=RatingSetup(games_per_pairing=1, half_time_s=45.0, halves=2, recent=2),
        learner_options={"copies": 4, "n_steps": 256, "batch_size": 512, "n_epochs": 10})


#: The evaluations (``--evaluate``): the trained snapshot against chaser and full, the
#: untrained one and the teacher against chaser.
EVAL_GAMES = ("learned:chaser", "learned:full", "untrained:chaser", "teacher:chaser")


def goal_difference(scores) -> dict:
    """Mean goal difference per match with its 95 % BCa bootstrap interval over matches."""
    diff = np.array([a - b for a, b in scores], dtype=np.float64)
    mean = float(diff.mean())
    if len(diff) < 2 or np.all(diff == diff[0]):
        low = high = mean
    else:
        res = bootstrap((diff,), np.mean, confidence_level=0.95, n_resamples=4000,
                        method="BCa", random_state=np.random.default_rng(0))
        low, high = float(res.confidence_interval.low), float(res.confidence_interval.high)
    return {"mean": mean, "ci95": [low, high]}


def evaluation_match(task: tuple) -> dict:
    """One evaluation match (``teamenv.headtohead``'s convention: the snapshot on the left
    for even seeds), from the snapshot's side: score, goal times, cycles."""
    team, config, opponent, seed, options = task
    left = seed % 2 == 0
    if left:
        result = play_match(team, opponent, seed, options, left_config=config)
    else:
        result = play_match(opponent, team, seed, options, right_config=config)
    mine = "left" if left else "right"
    score = list(result.score) if left else [result.score[1], result.score[0]]
    return {"seed": seed, "snapshot_left": left, "goals": score,
            "goal_times_s": [[round(g.time_s, 2), "for" if g.side == mine else "against"]
                             for g in result.goals],
            "cycles": result.cycles,
            "forfeit": "" if result.forfeit is None else f"seed {seed}: {result.forfeit}"}


def evaluation_matches(team: str, config: dict, opponent: str, seeds, options: MatchOptions,
                       jobs: int) -> list[dict]:
    """``evaluation_match`` for every seed, on ``jobs`` processes (same results for any)."""
    tasks = [(team, config, opponent, s, options) for s in seeds]
    if jobs > 1:
        with ProcessPoolExecutor(max_workers=jobs) as pool:
            return list(pool.map(evaluation_match, tasks))
    return [evaluation_match(t) for t in tasks]


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--run-dir", type=Path, default=None,
                        help="default runs/selfplay_league (runs/selfplay_league_smoke)")
    parser.add_argument("--generations", type=int, default=12)
    parser.add_argument("--max-minutes", type=float, default=40.0,
                        help="start no new generation after this much wall time")
    parser.add_argument("--jobs", type=int, default=1, help="rating worker processes")
    parser.add_argument("--evaluate", type=int, default=0,
                        help="evaluation matches against chaser and against full (0: none)")
    parser.add_argument("--eval-half-time", type=float, default=45.0)
    parser.add_argument("--eval-games", default=",".join(EVAL_GAMES),
                        help="which evaluations to play, comma-separated, of "
                             f"{','.join(EVAL_GAMES)} (the others already in --report are "
                             "kept: a long evaluation can be split over runs or machines)")
    parser.add_argument("--curve", type=Path, default=None,
                        help="default docs/selfplay_rating_curve.png (smoke: in the run dir)")
    parser.add_argument("--json", type=Path, default=None,
                        help="default benchmarks/results/selfplay_league.json")
    parser.add_argument("--policy", type=Path, default=None,
                        help="default examples/policies/selfplay_3v3.npz")
    parser.add_argument("--report", type=Path, default=None,
                        help="default benchmarks/results/selfplay_evaluation.json")
    parser.add_argument("--learner", choices=LEARNERS, default="imitation",
                        help="imitation (default: cloning chaser, then PPO) or ppo (from "
                             "scratch, the first run); the default paths below name it")
    parser.add_argument("--smoke", action="store_true", help="a tiny run (seconds)")
    args = parser.parse_args(argv)
    smoke = args.smoke
    tag = {"imitation": "_imitation", "options": "_options"}.get(args.learner, "")
    run_dir = args.run_dir or Path(f"runs/selfplay{tag}_league" + ("_smoke" if smoke else ""))
    curve = args.curve or (run_dir / "curve.png" if smoke else
                           Path(f"docs/selfplay{tag}_rating_curve.png"))
    record = args.json or (run_dir / "league.json" if smoke else
                           Path(f"benchmarks/results/selfplay{tag}_league.json"))
    config = demo_config(smoke, args.learner)
    generations = 2 if smoke else args.generations

    start = time.perf_counter()
    resume, done = (run_dir / LEAGUE_DB).is_file(), -1
    if resume:
        with LeagueStore(run_dir / LEAGUE_DB) as store:
            done = store.last_rated()
    for target in range(max(done, 0), generations + 1):
        if target > max(done, 0) and time.perf_counter() - start > 60.0 * args.max_minutes:
            print(f"stopping: {args.max_minutes} min of wall time passed", flush=True)
            break
        run_league(run_dir, target, config, resume=resume, backend="process", jobs=args.jobs)
        resume = True
    league_wall_s = time.perf_counter() - start

    with LeagueStore(run_dir / LEAGUE_DB) as store:
        size = config.training.team_size
        plot_rating_curve(store, curve, title=f"self-play league, {size} v {size} "
                          f"{config.training.field}"
                          f": {store.last_rated()} generations of "
                          f"{config.steps_per_generation} agent-decisions")
        last = store.last_rated()
        final = store.ratings(last)
        rows = [{**r.comparable(), "train_wall_s": r.train_wall_s,
                 "rate_wall_s": r.rate_wall_s,
                 "ratings": store.ratings(r.generation).to_json()}
                for r in store.generations() if r.rated]
    pool = SnapshotPool(run_dir, config.training)
    rating_seeds = sorted({seed for g in range(last + 1) for seed in rating_tournament(
        g, pool.spec(g), config.builtins, [], config.training.field,
        config.training.team_size, config.rating,
        generation_seed(config.seed, g, "rating")).round_seeds()})
    out = {"command": "python benchmarks/selfplay_league.py " + " ".join(
               sys.argv[1:] if argv is None else argv),
           "config": config.to_json(), "generations_rated": last,
           "wall_s_this_call": league_wall_s,
           "league_wall_s": sum(r["train_wall_s"] + r["rate_wall_s"] for r in rows),
           "generations": rows,
           "final_ratings": final.to_json(),
           "rating_tournament_seeds_in_evaluation_range": [
               s for s in rating_seeds if s in EVALUATION_SEEDS]}
    record.parent.mkdir(parents=True, exist_ok=True)
    record.write_text(json.dumps(out, indent=1) + "\n")
    print(f"wrote {curve} and {record}")

    if args.evaluate:
        # the best trained snapshot (generation >= 1; bradley_terry is ordered best first)
        best = next(t for t in final.bradley_terry if t.startswith("gen-") and t != "gen-0000")
        generation = int(best.split("-")[1])
        policy = args.policy or (run_dir / "best.npz" if smoke else
                                 Path(f"examples/policies/selfplay_{size}v{size}{tag}.npz"))
        report_path = args.report or (run_dir / "evaluation.json" if smoke else
                                      Path(f"benchmarks/results/selfplay{tag}_evaluation.json"))
        policy.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(pool.path(generation), policy)
        spec = pool.spec(generation)
        options = MatchOptions(field=config.training.field,
                               team_size=config.training.team_size,
                               half_time_s=args.eval_half_time, halves=2)
        seeds = evaluation_seeds(args.evaluate)
        report = {"snapshot": best, "policy_file": str(policy), "team_spec": spec.name,
                  "rating": final.bradley_terry[best].__dict__, "options": options.to_dict(),
                  "opponents": {}}
        wanted = set(args.eval_games.split(","))
        unknown = wanted - set(EVAL_GAMES)
        if unknown:
            parser.error(f"--eval-games: unknown {sorted(unknown)}; choose from {EVAL_GAMES}")
        if report_path.is_file():  # keep what an earlier run evaluated of the same setup
            earlier = json.loads(report_path.read_text())
            if all(earlier.get(k) == report[k] for k in ("snapshot", "options")):
                report = {**earlier, **{k: v for k, v in report.items() if k != "opponents"}}
        games = [("learned", best, policy, "chaser"), ("learned", best, policy, "full"),
                 ("untrained", "gen-0000", pool.path(0), "chaser")]
        teacher = config.learner_options.get("teacher") or config.training.option_team or None
        if teacher is not None:  # what the clone was taught: the teacher against chaser
            games.append(("teacher", str(teacher), None, "chaser"))
        for role, name, path, opponent in games:
            if f"{role}:{opponent}" not in wanted:
                continue
            t0 = time.perf_counter()
            team, team_config = (spec.name, {"path": str(path)}) if path is not None else (
                parse_team_spec(name).name, parse_team_spec(name).config_dict)
            rows = evaluation_matches(team, team_config, opponent, seeds, options, args.jobs)
            scores = [tuple(row["goals"]) for row in rows]
            wins = sum(a > b for a, b in scores)
            losses = sum(a < b for a, b in scores)
            gd = goal_difference(scores)
            report.setdefault("opponents" if role == "learned" else role, {})[opponent] = {
                "snapshot": name, "matches": len(rows), "seeds": [seeds[0], seeds[-1]],
                "record": {"wins": wins, "draws": len(rows) - wins - losses, "losses": losses},
                "goals": [sum(a for a, _ in scores), sum(b for _, b in scores)],
                "goal_difference_per_match": gd, "per_seed": rows,
                "forfeits": [row["forfeit"] for row in rows if row["forfeit"]],
                "wall_s": time.perf_counter() - t0}
            print(f"{name} vs {opponent}: W{wins} D{len(rows) - wins - losses} L{losses}, "
                  f"goals {sum(a for a, _ in scores)}-{sum(b for _, b in scores)}; goal "
                  f"difference per match {gd['mean']:+.3f} [{gd['ci95'][0]:+.3f}, "
                  f"{gd['ci95'][1]:+.3f}]", flush=True)
            # after every game: a long evaluation stopped part-way keeps what it played
            report_path.parent.mkdir(parents=True, exist_ok=True)
            report_path.write_text(json.dumps(report, indent=1) + "\n")
        print(f"wrote {policy} and {report_path}")


if __name__ == "__main__":
    main()
