"""Falls in `full` v `full` matches, with and without keeping off teammates' spots.

    python benchmarks/keep_off_falls.py                   # 6 seeds, 7 v 7 on mj7v7, 60 s
    python benchmarks/keep_off_falls.py --seeds 10 --half-time 120

Plays each seed twice: as the team is (``go_to`` stops beside a teammate that holds its
target, ``strategy.behaviours.motion.keep_off_teammates``) and with that step switched off
(walking straight into the spot). Counts every fall (a player's fallen flag rising) and sorts
it by who was nearest when it registered: a teammate within 0.6 m, an opponent within 0.6 m,
or nobody (the locomotion model's own falls: over-fast command changes). Seeds from the tuning
range (this measures a mechanism, not a team's strength).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import strategy.behaviours.motion as motion
import teamenv
from teamenv.seeds import TUNING_SEEDS

NEAR_M = 0.6


def falls(seed: int, keep_off: bool, team_size: int, half_time: float) -> np.ndarray:
    """(3,) falls with a teammate / an opponent / nobody within ``NEAR_M``."""
    original = motion.keep_off_teammates_all
    if not keep_off:
        motion.keep_off_teammates_all = lambda wms, targets, clearance: targets
    try:
        env = teamenv.parallel_env(left="full", right="full", field="mj7v7",
                                   team_size=team_size,
                                   rules={"half_time_s": half_time, "halves": 1},
                                   profile_phases=False)
        env.reset(seed=seed)
        before = env.sim.fallen().copy()
        out = np.zeros(3, dtype=int)
        while not env.episode_over:
            env.step({})
            now = env.sim.fallen()
            xy = env.sim.world.player_poses()[:, :2]
            for i in np.flatnonzero((now > 0) & (before == 0)):
                d = np.hypot(*(xy - xy[i]).T)
                d[i] = np.inf
                j = int(np.argmin(d))
                out[2 if d[j] > NEAR_M else 0 if (j < team_size) == (i < team_size) else 1] += 1
            before = now.copy()
        env.close()
        return out
    finally:
        motion.keep_off_teammates_all = original


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seeds", type=int, default=6)
    parser.add_argument("--offset", type=int, default=1000, help="seeds into the tuning range")
    parser.add_argument("--team-size", type=int, default=7)
    parser.add_argument("--half-time", type=float, default=60.0)
    args = parser.parse_args()
    seeds = TUNING_SEEDS.take(args.seeds, args.offset)
    t0 = time.perf_counter()
    for keep_off in (True, False):
        total = sum(falls(s, keep_off, args.team_size, args.half_time) for s in seeds)
        label = "keep off teammates" if keep_off else "walk straight in  "
        print(f"{label}: falls per match {total.sum() / len(seeds):.1f} (teammate near "
              f"{total[0]}, opponent near {total[1]}, nobody near {total[2]}; "
              f"{len(seeds)} matches)", flush=True)
    print(f"{time.perf_counter() - t0:.0f} s")


if __name__ == "__main__":
    main()
