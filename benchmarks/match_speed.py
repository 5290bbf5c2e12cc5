"""Wall time of a full match, with the share of every phase of the cycle and of each team.

Plays whole matches (default: `simspark` field, 11 v 11, 2 x 300 s = 30,000 cycles, the `full`
team on both sides) through the PettingZoo env, exactly as `teamenv match` does, and prints
the wall time, cycles per second, where the time went (env.timings(): actions, each team,
beam, locomotion, kick, physics, referee, comms, perception, other) and what dominates.

Usage:
    python benchmarks/match_speed.py                        # full vs full, 2 x 300 s
    python benchmarks/match_speed.py --left chaser --right chaser --half-time 60
    python benchmarks/match_speed.py --repeat 3 --json      # best of 3, JSON on stdout
    python benchmarks/match_speed.py --observation vision   # the cost of perception

The target: a full simspark match between two full teams in at most 15 s in state
mode (>= 2,000 cycles/s), as the first step toward 6 s; vision mode at most 2x state mode
(the earlier target was 60 s), on the 2-core development machine. Set
OPENBLAS_NUM_THREADS=1 on a busy machine; timings are noisy there, so take the best of
several repeats (--repeat).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import sys
import time
from typing import Any

import teamenv
from teamenv.config import RulesConfig
from teamenv.env import TIMING_PHASES, SoccerParallelEnv
from teamenv.teams import registered_teams

TARGET_CYCLES_PER_S = 2000.0
"""State mode; vision mode's target is half the state mode's rate."""
DEFAULT_TEAM = "full"
FALLBACK_TEAM = "chaser"
SIM_PHASE_NAMES = {"physics": "physics (pymunk world step + body I/O)",
                   "perception": "perception (observations)",
                   "comms": "comms (say channel delivery)",
                   "actions": "action validation",
                   "other": "other (rewards, infos, bookkeeping)"}


def resolve(name: str, explicit: bool) -> str:
    """The team to play: ``name`` when registered (or a module:Class path); the fallback, with
    a message, when the default team is not registered yet."""
    if ":" in name or name in registered_teams():
        return name
    if explicit:
        sys.exit(f"match_speed: team {name!r} is not registered in the 'teamenv.teams' entry "
                 f"points (registered: {sorted(registered_teams())})")
    print(f"match_speed: team {name!r} is not registered yet (registered: "
          f"{sorted(registered_teams())}); playing {FALLBACK_TEAM!r} instead", file=sys.stderr)
    return FALLBACK_TEAM


def play(left: str, right: str, field: str, team_size: int | None, half_time_s: float,
         seed: int, observation_mode: str = "state", vision: str | None = None
         ) -> dict[str, Any]:
    """One whole match; returns wall time (construction excluded), cycles and timings."""
    start_build = time.perf_counter()
    env = SoccerParallelEnv(field=field, team_size=team_size, left=left, right=right,
                            rules=RulesConfig(half_time_s=half_time_s),
                            observation_mode=observation_mode, vision=vision)
    build_s = time.perf_counter() - start_build
    start, start_cpu = time.perf_counter(), time.process_time()
    env.reset(seed=seed)
    goals = 0
    while not env.episode_over:
        env.step({})
        goals += sum(e.kind == "goal" for e in env.last_report.referee)
    wall = time.perf_counter() - start
    cpu = time.process_time() - start_cpu  # less sensitive than wall time to other processes
    timings = env.timings()
    env.close()
    return {
        "left": left, "right": right, "field": env.field.name, "team_size": env.team_size,
        "half_time_s": half_time_s, "seed": seed, "cycles": env.sim.cycle,
        "observation_mode": observation_mode, "vision": vision,
        "score": list(env.sim.referee.score), "goals": goals,
        "construct_s": build_s, "wall_s": wall, "cpu_s": cpu,
        "cycles_per_s": env.sim.cycle / wall,
        "timings_s": timings,
        "share": {k: v / timings["total"] for k, v in timings.items() if k != "total"},
    }


def report(runs: list[dict[str, Any]]) -> str:
    best = min(runs, key=lambda r: r["wall_s"])
    cycles, wall = best["cycles"], best["wall_s"]
    lines = [
        f"teamenv {teamenv.__version__}, python {platform.python_version()}, "
        f"{platform.machine()}, {os.cpu_count()} CPUs",
        f"{best['left']} vs {best['right']} on {best['field']}, {best['team_size']} v "
        f"{best['team_size']}, 2 x {best['half_time_s']:g} s = {cycles} cycles, seed "
        f"{best['seed']}, score {best['score'][0]}-{best['score'][1]}, observation "
        f"{best['observation_mode']}"
        f"{'' if best['vision'] is None else ' (' + best['vision'] + ')'}",
    ]
    if len(runs) > 1:
        lines.append("wall times of the repeats: " + ", ".join(f"{r['wall_s']:.2f} s"
                                                               for r in runs) + " (best shown)")
    full_cycles = int(round(2 * 300.0 / 0.02))
    target = TARGET_CYCLES_PER_S / (2.0 if best["observation_mode"] == "vision" else 1.0)
    lines += [
        f"wall time {wall:.2f} s ({best['construct_s']:.2f} s to build the env, not counted), "
        f"{best['cycles_per_s']:.0f} cycles/s, {wall / cycles * 1e3:.3f} ms/cycle "
        f"(process CPU {best['cpu_s'] / cycles * 1e3:.3f} ms/cycle)",
        f"{full_cycles} cycles (a 2 x 300 s match) at this rate: "
        f"{full_cycles / best['cycles_per_s']:.1f} s (target for full vs full, simspark "
        f"11 v 11, {best['observation_mode']} mode: <= {full_cycles / target:.0f} s, i.e. >= "
        f"{target:.0f} cycles/s: {'met' if best['cycles_per_s'] >= target else 'NOT met'} here)",
        "where the time goes (env.timings(), per cycle and share of env time):",
    ]
    t = best["timings_s"]
    for phase in TIMING_PHASES:
        name = SIM_PHASE_NAMES.get(phase, phase)
        if phase.startswith("team_"):
            name = f"{phase} ({best[phase.split('_')[1]]} act + reset)"
        lines.append(f"  {name:42s} {t[phase] / cycles * 1e6:9.1f} us  "
                     f"{100 * best['share'][phase]:5.1f} %")
    lines.append(f"  {'total inside reset()/step()':42s} {t['total'] / cycles * 1e6:9.1f} us  "
                 f"{100 * t['total'] / wall:5.1f} % of wall")
    teams = t["team_left"] + t["team_right"]
    env_only = t["total"] - teams
    lines.append(f"teams: {100 * teams / t['total']:.1f} % ({teams / cycles * 1e6:.0f} us/cycle); "
                 f"env without teams: {100 * env_only / t['total']:.1f} % "
                 f"({env_only / cycles * 1e6:.0f} us/cycle)")
    top = max((p for p in TIMING_PHASES), key=lambda p: t[p])
    lines.append(f"dominant phase: {top} ({100 * best['share'][top]:.1f} %)")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--left", default=None, help=f"left team (default {DEFAULT_TEAM})")
    parser.add_argument("--right", default=None, help=f"right team (default {DEFAULT_TEAM})")
    parser.add_argument("--half-time", type=float, default=300.0, help="seconds per half")
    parser.add_argument("--field", default="simspark")
    parser.add_argument("--team-size", type=int, default=None,
                        help="players per side (default: the field's, 11 on simspark)")
    parser.add_argument("--repeat", type=int, default=1, help="matches to play; best is shown")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--observation", default="state", choices=("state", "vision"),
                        help="observation mode (vision: the teams localize and filter)")
    parser.add_argument("--vision", default=None, help="vision profile (simspark or mj)")
    parser.add_argument("--json", action="store_true", help="print JSON instead of a table")
    args = parser.parse_args(argv)
    left = resolve(args.left or DEFAULT_TEAM, explicit=args.left is not None)
    right = resolve(args.right or DEFAULT_TEAM, explicit=args.right is not None)
    runs = [play(left, right, args.field, args.team_size, args.half_time, args.seed,
                 args.observation, args.vision)
            for _ in range(max(1, args.repeat))]
    if args.json:
        best = min(runs, key=lambda r: r["wall_s"])
        top = max(TIMING_PHASES, key=lambda p: best["timings_s"][p])
        print(json.dumps({"best": best, "runs": runs, "dominant_phase": top,
                          "target_cycles_per_s": TARGET_CYCLES_PER_S,
                          "python": platform.python_version(), "cpus": os.cpu_count()},
                         indent=1))
    else:
        print(report(runs))


if __name__ == "__main__":
    main()
