"""The cost of the sighting windows' clustering alone (``cluster_objects``), on recorded calls.

Plays a seeded vision match (``full`` against itself, 7 v 7 ``mj7v7``, ``mj`` vision by
default), records the arguments of every ``cluster_objects`` call (the agents' own sighting
windows and the heard reports), then times ``cluster_objects`` on those arguments (process
CPU per call, best of ``--repeats``). The same calls every repeat, so two commits compare on
equal work: run each tree's copy with ``PYTHONPATH`` pointing at that tree.

Usage:
    python benchmarks/cluster_speed.py [--cycles 1500] [--seed 100201] [--repeats 5]
"""

from __future__ import annotations

import argparse
import time
from typing import Any

import numpy as np

import strategy.perception.clustering as clustering
import strategy.perception.filtering as filtering
import strategy.perception.team_sightings as team_sightings
import teamenv


def record(cycles: int, seed: int, field: str, team_size: int, vision: str) -> list[tuple]:
    """The arguments of every ``cluster_objects`` call in ``cycles`` cycles of the match."""
    calls: list[tuple] = []
    real = clustering.cluster_objects

    def recording(*args: Any) -> dict:
        calls.append(tuple(np.array(a) if isinstance(a, np.ndarray) else a for a in args))
        return real(*args)

    filtering.cluster_objects = team_sightings.cluster_objects = recording
    try:
        env = teamenv.parallel_env(left="full", right="full", field=field, team_size=team_size,
                                   observation_mode="vision", vision=vision)
        env.reset(seed=seed)
        for _ in range(cycles):
            env.step({})
        env.close()
    finally:
        filtering.cluster_objects = team_sightings.cluster_objects = real
    return calls


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cycles", type=int, default=1500)
    parser.add_argument("--seed", type=int, default=100_201)
    parser.add_argument("--field", default="mj7v7")
    parser.add_argument("--team-size", type=int, default=7)
    parser.add_argument("--vision", default="mj")
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args(argv)
    calls = record(args.cycles, args.seed, args.field, args.team_size, args.vision)
    if not calls:
        raise SystemExit("cluster_speed: the match made no cluster_objects call")
    for call in calls[:20]:  # compile and warm up
        clustering.cluster_objects(*call)
    runs = []
    for _ in range(args.repeats):
        start = time.process_time()
        for call in calls:
            clustering.cluster_objects(*call)
        runs.append(1e6 * (time.process_time() - start) / len(calls))
    points = np.median([len(call[0]) for call in calls])
    print(f"{clustering.__file__}: {len(calls)} calls in {args.cycles} cycles, median "
          f"{points:.0f} sightings a call")
    print("process CPU per call: " + ", ".join(f"{v:.0f}" for v in runs)
          + f" us (best {min(runs):.0f})")


if __name__ == "__main__":
    main()
