"""Benchmark: tournament throughput (matches per hour) per backend, per-match overhead, start-up.

Plays one round robin of the registered (built-in) teams five ways and checks that all of them
store exactly the same results:

- ``serial``: in-process, one match after another through ``execute_task`` (no pool, no
  database): the baseline; ``serial, new envs`` the same with an env built for every match
  (``execute_task`` keeps a worker's envs between matches: ``teamenv.match_envs``);
- ``process -j 1`` and ``process -j 2``: ``run_tournament`` with the local process pool;
- ``ray x2``: ``run_tournament`` on a local Ray instance with ``num_cpus=2`` (ray.init and
  shutdown included, as the CLI pays them).

For each it prints matches per hour and per minute, the time inside matches (the sum of the
matches' own ``wall_s``: build the env, reset, play), and the per-match overhead::

    overhead per match = (workers x wall time - sum of match wall_s) / matches

i.e. every worker-second not spent inside a match: worker start-up, imports, shipping tasks and
results, database writes, and workers idle at the end (the tail). Worker start-up is also timed
on its own, before anything else runs: a pool of N workers (or ray.init + N Ray workers) until
each worker has imported the teams and can play; the first pool of a process may pay more (the
fork server's own start). ``--repeat`` runs every measurement that many times and keeps the
best (the machine is shared, timings are noisy). Usage::

    OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/tournament_throughput.py \
        [--team-size 11] [--half-time 20] [--halves 2] [--games 1] [--repeat 1] \
        [--teams chaser static ...] [--no-ray] [--writes 200]
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import replace
from pathlib import Path
from typing import Any

from teamenv.match import MatchOptions
from teamenv.teams import registered_teams
from teamenv.tournament import ResultStore, backends, round_robin, run_tournament, validate_specs
from teamenv.tournament.backends import ProcessPoolBackend, execute_task

#: registered teams that cannot play without a config (the policy team loads a weights file)
NEEDS_CONFIG = {"policy"}


def _probe(names: tuple[str, ...]) -> int:
    """What a worker must do before its first match: import teamenv and the teams."""
    import teamenv.match  # noqa: F401
    from teamenv.teams import resolve_team_class

    for name in names:
        resolve_team_class(name)
    return os.getpid()


def pool_start_s(jobs: int, names: tuple[str, ...]) -> float:
    """Seconds from creating the backend's pool of ``jobs`` workers until all of them have
    imported the teams (what the pool pays before its first match)."""
    backend = ProcessPoolBackend(jobs)
    start = time.perf_counter()
    starter = getattr(backend, "start_pool", None)
    if starter is not None:  # the backend's own start (it imports the teams in the workers)
        pool = starter(names)
    else:
        pool = ProcessPoolExecutor(jobs, mp_context=backend.context)
    pids = set()
    while len(pids) < jobs:  # make sure every worker exists and has imported
        pids |= {f.result() for f in [pool.submit(_probe, names) for _ in range(2 * jobs)]}
    elapsed = time.perf_counter() - start
    pool.shutdown()
    return elapsed


def ray_start_s(jobs: int, names: tuple[str, ...]) -> tuple[float, float]:
    """(ray.init seconds, seconds until ``jobs`` Ray workers have imported the teams)."""
    import ray

    from teamenv.tournament.backends import RayBackend
    from teamenv.tournament.ray_cluster import init_ray

    niceness = getattr(RayBackend(num_cpus=jobs), "worker_niceness", None)
    # as the backend starts its local instance (a private one, whatever else runs here)
    config = None if niceness is None else {"worker_niceness": niceness}
    start = time.perf_counter()
    init_ray(None, jobs, local_system_config=config, include_dashboard=False,
             log_to_driver=False, configure_logging=False)
    init = time.perf_counter() - start
    remote = ray.remote(num_cpus=1)(_probe)
    pids: set[int] = set()
    while len(pids) < jobs:
        pids |= set(ray.get([remote.remote(names) for _ in range(2 * jobs)]))
    ready = time.perf_counter() - start
    ray.shutdown()
    return init, ready


def _has_ray() -> bool:
    try:
        import ray  # noqa: F401
    except ImportError:
        return False
    return True


def _rows(db: Path, name: str) -> tuple[list[dict[str, Any]], float]:
    with ResultStore(db) as store:
        tid, _ = store.get_tournament(name)
        records = store.matches(tid)
    return [r.comparable() for r in records], sum(r.wall_s for r in records)


def _serial_rows(tasks: list, results: list) -> list[tuple]:
    return [(t.index, r.score, r.official_score, r.cycles,
             [(round(g.time_s, 6), g.side, g.scorer_side, g.scorer_unum) for g in r.goals],
             (r.forfeit.side, r.forfeit.reason) if r.forfeit else None)
            for t, r in zip(tasks, results, strict=True)]


def _row_key(row: dict[str, Any]) -> tuple:
    official = (row["left_official"], row["right_official"])
    forfeit = (row["forfeit_side"], row["forfeit_reason"]) if row["forfeit_side"] else None
    return (row["idx"], (row["left_score"], row["right_score"]), official, row["cycles"],
            row["goals"], forfeit)


def _line(label: str, n: int, wall: float, match_s: float, workers: int, extra: str = "") -> str:
    overhead = (workers * wall - match_s) / n
    return (f"{label:<16} {wall:7.1f} s  {3600 * n / wall:8.0f} matches/h  "
            f"{60 * n / wall:6.2f} matches/min   in matches {match_s / n:6.3f} s/match, "
            f"overhead {1e3 * overhead:7.1f} ms/match{extra}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--field", default="simspark")
    parser.add_argument("--team-size", type=int, default=11)
    parser.add_argument("--half-time", type=float, default=20.0, help="seconds per half")
    parser.add_argument("--halves", type=int, default=2)
    parser.add_argument("--games", type=int, default=1, help="seeded rounds per pairing")
    parser.add_argument("--teams", nargs="+", default=None,
                        help="team specs (default: every registered team that plays without "
                             "a config; the policy team needs a weights file)")
    parser.add_argument("--repeat", type=int, default=1, help="keep the best of N runs")
    parser.add_argument("--no-ray", action="store_true", help="skip the Ray backend")
    parser.add_argument("--writes", type=int, default=200,
                        help="matches in the database-only test (0: skip it)")
    args = parser.parse_args()

    teams = args.teams or sorted(t for t in registered_teams() if t not in NEEDS_CONFIG)
    options = MatchOptions(field=args.field, team_size=args.team_size, half_time_s=args.half_time,
                           halves=args.halves)
    t = round_robin("bench", teams, games_per_pairing=args.games, options=options)
    tasks = t.schedule()
    n = len(tasks)
    names = tuple(sorted({s.name for s in t.all_teams}))
    print(f"round robin of {teams}: {n} matches, {args.team_size} v {args.team_size}, "
          f"{args.halves} x {args.half_time:g} s halves, best of {args.repeat}; "
          f"{os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.2f} at start")
    validate_specs(t.all_teams, options)  # imports the teams here, as run_tournament does

    print("worker start-up (until every worker has imported the teams; the first pool "
          "of a process, then the best of the next ones):")
    for jobs in (1, 2):
        costs = [pool_start_s(jobs, names) for _ in range(1 + args.repeat)]
        print(f"  process pool -j {jobs}: {costs[0]:.2f} s first, {min(costs[1:]):.2f} s "
              "after")
    if not args.no_ray and _has_ray():
        init, ready = min(ray_start_s(2, names) for _ in range(args.repeat))
        print(f"  ray x2: {ready:.2f} s (ray.init {init:.2f} s)")

    best: dict[str, tuple[float, float, int, str]] = {}
    rows: dict[str, list] = {}

    kept_envs = backends.MATCH_ENVS
    for label, envs in (("serial, new envs", None), ("serial", kept_envs)):
        serial_results: list = []
        backends.MATCH_ENVS = envs  # None: every match builds its env (before envs were kept)
        for _ in range(args.repeat):
            if envs is not None:
                envs.clear()  # each run builds its envs once, as a fresh worker does
            start = time.perf_counter()
            serial_results = [execute_task(task) for task in tasks]
            wall = time.perf_counter() - start
            match_s = sum(r.wall_s for r in serial_results)
            if label not in best or wall < best[label][0]:
                best[label] = (wall, match_s, 1, "")
        rows[label] = _serial_rows(tasks, serial_results)
        print(_line(label, n, *best[label][:3]), flush=True)
    backends.MATCH_ENVS = kept_envs

    runs = [("process -j 1", "process", 1), ("process -j 2", "process", 2)]
    if not args.no_ray:
        try:
            import ray  # noqa: F401
            runs.append(("ray x2", "ray", 2))
        except ImportError:
            print("ray is not installed: skipping the Ray backend")
    with tempfile.TemporaryDirectory() as tmp:
        for label, backend, jobs in runs:
            for k in range(args.repeat):
                name = f"bench-{backend}-{jobs}-{k}"
                db = Path(tmp) / f"{name}.sqlite"
                s = run_tournament(replace(t, name=name), db, backend=backend, jobs=jobs,
                                   progress=False)
                assert s.complete, s.describe()
                got, match_s = _rows(db, name)
                rows[label] = [_row_key(r) for r in got]
                extra = f"  (DB writes {1e3 * s.db_write_s / s.played:.2f} ms/match)"
                if label not in best or s.wall_s < best[label][0]:
                    best[label] = (s.wall_s, match_s, jobs, extra)
            wall, match_s, jobs, extra = best[label]
            print(_line(label, n, wall, match_s, jobs, extra), flush=True)

        serial_rate = n / best["serial"][0]
        print(f"  serial (kept envs): {best['serial, new envs'][0] / best['serial'][0]:.3f}x the "
              "matches/h of serial with an env built for every match")
        for label, *_ in runs:
            print(f"  {label}: {n / best[label][0] / serial_rate:.2f}x serial")
        same = all(rows[label] == rows["serial"] for label in rows)
        print(f"identical results (scores, goals, cycles, forfeits) on every backend: {same}")

        if args.writes:
            for sync in ("FULL", "NORMAL"):
                with ResultStore(Path(tmp) / f"w-{sync}.sqlite", synchronous=sync) as store:
                    big = round_robin("writes", [f"{teams[0]}:n={k}" for k in range(40)],
                                      games_per_pairing=1, options=options)
                    tid = store.create_tournament(big, {})
                    sched = big.schedule()[: args.writes]
                    start = time.perf_counter()
                    for k, task in enumerate(sched):
                        store.record_match(tid, task, serial_results[k % n])
                    write = (time.perf_counter() - start) / len(sched)
                print(f"DB write alone, synchronous={sync:6s}: {1e3 * write:6.3f} ms/match")


if __name__ == "__main__":
    main()
