"""Role agreement in vision mode: how often all agents of the full team hold the same roles.

    python benchmarks/role_agreement.py                      # 4 seeds, 7 v 7 mj7v7, 2 x 60 s
    python benchmarks/role_agreement.py --seeds 8 --field simspark --team-size 11
    python benchmarks/role_agreement.py --observation state --seeds 2     # the state-mode vote

In ``vision`` mode each agent computes its role vector from its own belief (its localization,
its ball and what teammates said), so the vectors differ. The full team votes on them over the
say channel. This plays the full team against the chaser with voting on and with voting off
(the same team still talking: ``vote=False``), and counts the share of cycles on which every
agent holds the same assignment (its ``team_vector``), over cycles in play and in all cycles.
Target: >= 95 % with voting.

It also counts the cycles in play on which some agent's adopted assignment differs from the
vector it computed itself (what the silent team would follow). In ``state`` mode
(``--observation state``) every agent's own vector is the same, so any such cycle is the vote
lagging behind a change; ``--stale-votes`` plays the full team with
``vote_since_own_change=False`` (counting every vector within the age limit) to compare.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import teamenv


def agreement(seed: int, vote: bool, args: argparse.Namespace) -> tuple[int, ...]:
    """(agreeing cycles, cycles) in play and overall, and the cycles in play on which an
    adopted assignment differs from the agent's own vector, for one match."""
    config = {"vote": vote}
    if args.stale_votes:
        config["vote_since_own_change"] = False
    vision = {"vision": args.vision} if args.observation == "vision" else {}
    env = teamenv.parallel_env(field=args.field, team_size=args.team_size, left="full",
                               right=args.opponent, left_config=config,
                               observation_mode=args.observation, channel=args.channel,
                               rules={"half_time_s": args.half_time}, profile_phases=False,
                               **vision)
    env.reset(seed=seed)
    players = list(env.teams["left"].players.values())
    agree = cycles = agree_play = play = not_own = 0
    while not env.episode_over:
        env.step({})
        decisions = [p.last_decision for p in players]
        vectors = [d.team_vector for d in decisions]
        same = all(np.array_equal(vectors[0], v) for v in vectors[1:])
        agree += same
        cycles += 1
        if env.sim.referee.mode.name == "PlayOn":
            agree_play += same
            play += 1
            not_own += any(not np.array_equal(d.team_vector, d.own_vector) for d in decisions)
    return agree_play, play, agree, cycles, not_own


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=4)
    parser.add_argument("--field", default="mj7v7")
    parser.add_argument("--team-size", type=int, default=7)
    parser.add_argument("--half-time", type=float, default=60.0)
    parser.add_argument("--vision", default="simspark", help="vision profile: simspark or mj")
    parser.add_argument("--channel", default="simspark", help="say channel: simspark or mj")
    parser.add_argument("--opponent", default="chaser")
    parser.add_argument("--observation", default="vision", choices=("vision", "state"))
    parser.add_argument("--stale-votes", action="store_true",
                        help="full team with vote_since_own_change=False")
    parser.add_argument("--first-seed", type=int, default=0)
    args = parser.parse_args()
    print(f"role agreement, full vs {args.opponent}, {args.field} {args.team_size} v "
          f"{args.team_size}, 2 x {args.half_time:g} s, {args.observation} mode"
          f"{f' (vision {args.vision})' if args.observation == 'vision' else ''}, channel "
          f"{args.channel}, seeds {args.first_seed}..{args.first_seed + args.seeds - 1}"
          f"{', stale votes counted' if args.stale_votes else ''}")
    for vote in (True, False):
        start = time.perf_counter()
        totals = np.zeros(5, dtype=np.int64)
        for seed in range(args.first_seed, args.first_seed + args.seeds):
            totals += agreement(seed, vote, args)
        a_play, play, a_all, cycles, not_own = totals
        print(f"  voting {'on ' if vote else 'off'}: all agree on {100 * a_play / play:.1f} % "
              f"of {play} cycles in play, {100 * a_all / cycles:.1f} % of all {cycles} cycles; "
              f"an adopted assignment differs from the agent's own vector on "
              f"{100 * not_own / play:.1f} % of cycles in play "
              f"[{time.perf_counter() - start:.0f} s]", flush=True)


if __name__ == "__main__":
    main()
