"""Agent-steps/s of N independent teamenv processes at once, one env each (the RL setting of a
machine with N free cores: a learner per core), against one process alone, in one run.

Each process steps the in-process runner of ``vector_speed.py`` (11 v 11 by default, every
player a learner, random Box actions drawn before timing, 1000-cycle episodes) for
``--seconds``; the rates are summed. Compare the sum with VMAS's best batch from
``vector_speed.py`` measured on the same quiet machine.

Usage: python benchmarks/vector_speed_processes.py [--processes 2] [--team-size 11] [--seconds 10]
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from vector_speed import TeamenvVector  # noqa: E402  (the sibling script's runner)


def rate(team_size: int, seconds: float) -> tuple[float, float]:
    """(agent-steps/s, agent-steps per CPU-second) of one env stepped for ``seconds``."""
    runner = TeamenvVector(team_size, 1, 0, 1000)
    runner.run(200)  # warm-up: imports, first compilation of the kernels
    start, cpu, steps = time.perf_counter(), time.process_time(), 0
    while time.perf_counter() - start < seconds:
        runner.run(200)
        steps += 200
    agents = 2 * team_size
    return (steps * agents / (time.perf_counter() - start),
            steps * agents / max(time.process_time() - cpu, 1e-9))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--processes", type=int, default=2)
    parser.add_argument("--team-size", type=int, default=11)
    parser.add_argument("--seconds", type=float, default=10.0)
    args = parser.parse_args()
    print(f"{os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.2f} at start")
    with ProcessPoolExecutor(1) as pool:
        alone, alone_cpu = pool.submit(rate, args.team_size, args.seconds).result()
    print(f"1 process alone: {alone:.0f} agent-steps/s ({alone_cpu:.0f} per CPU-second)")
    with ProcessPoolExecutor(args.processes) as pool:
        rates = list(pool.map(rate, [args.team_size] * args.processes,
                              [args.seconds] * args.processes))
    shown = " + ".join(f"{r:.0f}" for r, _ in rates)
    print(f"{args.processes} processes at once: {shown} = {sum(r for r, _ in rates):.0f} "
          f"agent-steps/s ({sum(c for _, c in rates) / len(rates):.0f} per CPU-second each)")


if __name__ == "__main__":
    main()
