"""Benchmark: tournament matches per minute at -j 1 and -j 2, and the database cost per match.

Plays a round robin of the registered (built-in) teams three ways — in-process serially (no
pool, no database: the baseline), and through ``run_tournament`` with the process pool at
``-j 1`` and ``-j 2`` — then times writing matches into SQLite on its own (synchronous=FULL
and NORMAL). Usage::

    .venv/bin/python benchmarks/tournament_throughput.py [--team-size 11] [--half-time 20]
        [--games 3] [--writes 500]
"""

from __future__ import annotations

import argparse
import os
import resource
import tempfile
import time
from dataclasses import replace
from pathlib import Path

from teamenv.match import MatchOptions
from teamenv.teams import registered_teams
from teamenv.tournament import ResultStore, round_robin, run_tournament
from teamenv.tournament.backends import execute_task


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--team-size", type=int, default=11)
    parser.add_argument("--half-time", type=float, default=20.0, help="seconds per half")
    parser.add_argument("--games", type=int, default=3, help="seeded rounds per pairing")
    parser.add_argument("--writes", type=int, default=500, help="matches in the DB-only test")
    args = parser.parse_args()

    teams = sorted(registered_teams())
    options = MatchOptions(team_size=args.team_size, half_time_s=args.half_time)
    t = round_robin("bench", teams, games_per_pairing=args.games, options=options)
    tasks = t.schedule()
    print(f"round robin of {teams}: {len(tasks)} matches, {args.team_size} v {args.team_size}, "
          f"2 x {args.half_time:g} s halves; {os.cpu_count()} CPUs, "
          f"load average {os.getloadavg()[0]:.2f} at start")

    start = time.perf_counter()
    cpu0 = time.process_time()
    results = [execute_task(task) for task in tasks]
    serial = time.perf_counter() - start
    serial_cpu = time.process_time() - cpu0
    per_match = serial / len(tasks)
    print(f"in-process serial (no pool, no DB): {serial:7.1f} s  "
          f"{60 / per_match:6.1f} matches/min  ({per_match:.2f} s/match, "
          f"{serial_cpu / len(tasks):.2f} CPU-s/match)")

    rates = {}
    with tempfile.TemporaryDirectory() as tmp:
        for jobs in (1, 2):
            before = resource.getrusage(resource.RUSAGE_CHILDREN)
            s = run_tournament(replace(t, name=f"bench-j{jobs}"), Path(tmp) / f"j{jobs}.sqlite",
                               jobs=jobs, progress=False)
            after = resource.getrusage(resource.RUSAGE_CHILDREN)  # workers are reaped by now
            cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
            assert s.complete, s.describe()
            rates[jobs] = s.matches_per_minute
            print(f"run_tournament -j {jobs}:              {s.wall_s:7.1f} s  "
                  f"{s.matches_per_minute:6.1f} matches/min  (DB writes "
                  f"{1e3 * s.db_write_s / s.played:.2f} ms/match in the parent; workers used "
                  f"{cpu:.1f} CPU-s = {cpu / s.wall_s:.2f} cores busy on average)")
        print(f"scaling -j 2 / -j 1: {rates[2] / rates[1]:.2f}x  "
              f"(-j 1 vs in-process: {rates[1] * per_match / 60:.2f}x)")

        for sync in ("FULL", "NORMAL"):
            with ResultStore(Path(tmp) / f"w-{sync}.sqlite", synchronous=sync) as store:
                big = round_robin("writes", [f"{teams[0]}:n={k}" for k in range(40)],
                                  games_per_pairing=1, options=options)
                tid = store.create_tournament(big, {})
                sched = big.schedule()[: args.writes]
                start = time.perf_counter()
                for k, task in enumerate(sched):
                    store.record_match(tid, task, results[k % len(results)])
                write = (time.perf_counter() - start) / len(sched)
                start = time.perf_counter()
                store.matches(tid)
                read = time.perf_counter() - start
            print(f"DB write, synchronous={sync:6s}: {1e3 * write:6.3f} ms/match "
                  f"({100 * write / per_match:.3f}% of a {per_match:.2f} s match); "
                  f"reading {len(sched)} matches back: {1e3 * read:.1f} ms")


if __name__ == "__main__":
    main()
