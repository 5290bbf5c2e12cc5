"""Role agreement in vision mode: how often all agents of the full team hold the same roles.

    python benchmarks/role_agreement.py                      # 4 seeds, 7 v 7 mj7v7, 2 x 60 s
    python benchmarks/role_agreement.py --seeds 8 --field simspark --team-size 11

In ``vision`` mode each agent computes its role vector from its own belief (its localization,
its ball and what teammates said), so the vectors differ. The full team votes on them over the
say channel. This plays the full team against the chaser with voting on and with voting off
(the same team still talking: ``vote=False``), and counts the share of cycles on which every
agent holds the same assignment (its ``team_vector``), over cycles in play and in all cycles.
Target: >= 95 % with voting.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import teamenv


def agreement(seed: int, vote: bool, args: argparse.Namespace) -> tuple[int, int, int, int]:
    """(agreeing cycles, cycles) in play and overall, for one match."""
    env = teamenv.parallel_env(field=args.field, team_size=args.team_size, left="full",
                               right=args.opponent, left_config={"vote": vote},
                               observation_mode="vision", vision=args.vision,
                               channel=args.channel,
                               rules={"half_time_s": args.half_time}, profile_phases=False)
    env.reset(seed=seed)
    players = list(env.teams["left"].players.values())
    agree = cycles = agree_play = play = 0
    while not env.episode_over:
        env.step({})
        vectors = [p.last_decision.team_vector for p in players]
        same = all(np.array_equal(vectors[0], v) for v in vectors[1:])
        agree += same
        cycles += 1
        if env.sim.referee.mode.name == "PlayOn":
            agree_play += same
            play += 1
    return agree_play, play, agree, cycles


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=4)
    parser.add_argument("--field", default="mj7v7")
    parser.add_argument("--team-size", type=int, default=7)
    parser.add_argument("--half-time", type=float, default=60.0)
    parser.add_argument("--vision", default="simspark", help="vision profile: simspark or mj")
    parser.add_argument("--channel", default="simspark", help="say channel: simspark or mj")
    parser.add_argument("--opponent", default="chaser")
    args = parser.parse_args()
    print(f"role agreement, full vs {args.opponent}, {args.field} {args.team_size} v "
          f"{args.team_size}, 2 x {args.half_time:g} s, vision {args.vision}, channel "
          f"{args.channel}, seeds 0..{args.seeds - 1}")
    for vote in (True, False):
        start = time.perf_counter()
        totals = np.zeros(4, dtype=np.int64)
        for seed in range(args.seeds):
            totals += agreement(seed, vote, args)
        a_play, play, a_all, cycles = totals
        print(f"  voting {'on ' if vote else 'off'}: all agree on {100 * a_play / play:.1f} % "
              f"of {play} cycles in play, {100 * a_all / cycles:.1f} % of all {cycles} cycles "
              f"[{time.perf_counter() - start:.0f} s]", flush=True)


if __name__ == "__main__":
    main()
