"""What a league match on LocalServer costs, split by part: CPU seconds per game second.

    python benchmarks/league_match_cost.py                       # full v chaser, 7 v 7, 20 s
    python benchmarks/league_match_cost.py --seconds 60 --left full --right full --json out.json

Plays one match with ``teamenv.league.match.play_league_match`` (``server="local"``: rcsssmj's
simulation in this process) and times, in CPU time of this process (``time.process_time``),
each part it passes through: the server's physics step, the server building and encoding the
perceptions (with LocalServer's shortcuts, the default: ``local_perceiver`` computing them
straight into ours, which this part then includes), our perception parser (with the
shortcuts: only where the wire's text must decide), the server's action parser (with the
shortcuts: the quick reader of our flat effector text), our locomotion controllers
(walk, kick, get-up: the request encoders), the observation builder and the team plugins.
Joining (MuJoCo recompiles the world for each robot) is reported apart: it is paid once per
match. The parts are timed by wrapping the functions (a few microseconds each), so "other"
is what is left: the match loop, the referee's bookkeeping, the wrappers themselves.
"""

from __future__ import annotations

import argparse
import json
import time
from collections import defaultdict
from contextlib import ExitStack, contextmanager

TIMES: dict[str, float] = defaultdict(float)
_ACTIVE: list[str] = []


def _timed(part: str, fn):
    """``fn`` that adds its own CPU time (not that of timed callees) to ``TIMES[part]``."""

    def wrapper(*args, **kwargs):
        start = time.process_time()
        _ACTIVE.append(part)
        try:
            return fn(*args, **kwargs)
        finally:
            _ACTIVE.pop()
            spent = time.process_time() - start
            TIMES[part] += spent
            if _ACTIVE:                      # not the caller's own time
                TIMES[_ACTIVE[-1]] -= spent

    return wrapper


@contextmanager
def _patched(owner, name: str, part: str):
    original = getattr(owner, name)
    setattr(owner, name, _timed(part, original))
    try:
        yield
    finally:
        setattr(owner, name, original)


@contextmanager
def _swapped(owner, name: str, replacement):
    original = getattr(owner, name)
    setattr(owner, name, replacement)
    try:
        yield
    finally:
        setattr(owner, name, original)


def measure(left: str, right: str, seconds: float, team_size: int, seed: int) -> dict:
    from rcsssmj.games.soccer.sim.soccer_sim import SoccerSimulation
    from rcsssmj.server.action_parser import DefaultActionParser

    from teamenv.league import local_actions, local_server, match
    from teamenv.league.adapter import RequestEncoder
    from teamenv.league.local_perceiver import LocalPerceiver
    from teamenv.league.network_batch import WalkBatch
    from teamenv.league.observation import VisionObservationBuilder

    TIMES.clear()
    with ExitStack() as stack:
        for owner, name, part in [
            (local_server.LocalServer, "join_teams", "join (once per match)"),
            (SoccerSimulation, "step", "server physics"),
            (SoccerSimulation, "generate_perceptions", "server perceptions"),
            (LocalPerceiver, "perceive", "server perceptions"),
            (local_server.LocalServer, "_perceive", "server perceptions"),
            (local_server, "parse_perception", "our perception parser"),
            (local_server, "perception_from_objects", "our perception parser"),
            (DefaultActionParser, "parse_action", "server action parser"),
            (local_actions, "quick_actions", "server action parser"),
            (RequestEncoder, "encode", "our controllers"),
            (WalkBatch, "flush", "our controllers"),
            (VisionObservationBuilder, "observe_team", "observation builder"),
            (match.LeagueSide, "act", "match loop"),
        ]:
            stack.enter_context(_patched(owner, name, part))
        make_side = match.make_side

        def timed_side(*args, **kwargs):
            side = make_side(*args, **kwargs)
            side.team.act = _timed("team plugins", side.team.act)
            return side

        stack.enter_context(_swapped(match, "make_side", timed_side))
        start_cpu, start_wall = time.process_time(), time.perf_counter()
        options = match.LeagueMatchOptions(team_size=team_size, game_s=seconds, server="local")
        result = match.play_league_match(left, right, options, seed=seed)
        total_cpu = time.process_time() - start_cpu
        wall = time.perf_counter() - start_wall
    game_s = result.cycles * 0.02
    join = TIMES.pop("join (once per match)", 0.0)
    parts = {k: v for k, v in TIMES.items()}
    parts["other"] = total_cpu - join - sum(parts.values())
    per_game_s = {k: v / game_s for k, v in sorted(parts.items(), key=lambda kv: -kv[1])}
    return {"left": left, "right": right, "team_size": team_size, "game_s": game_s,
            "score": result.score, "cpu_s": total_cpu, "wall_s": wall, "join_cpu_s": join,
            "cpu_s_per_game_s": (total_cpu - join) / game_s,
            "cpu_s_per_game_s_with_join": total_cpu / game_s, "parts": per_game_s}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--left", default="full", help="left team spec (default full)")
    parser.add_argument("--right", default="chaser", help="right team spec (default chaser)")
    parser.add_argument("--seconds", type=float, default=20.0, help="game time (s)")
    parser.add_argument("--team-size", type=int, default=7, help="players per side (1-7)")
    parser.add_argument("--seed", type=int, default=0, help="match seed")
    parser.add_argument("--json", default=None, help="also write the numbers here")
    args = parser.parse_args()
    out = measure(args.left, args.right, args.seconds, args.team_size, args.seed)
    print(f"{out['left']} v {out['right']}, {out['team_size']} v {out['team_size']}, "
          f"{out['game_s']:.1f} s of game, score {out['score'][0]}-{out['score'][1]}")
    print(f"join: {out['join_cpu_s']:.1f} CPU s (once per match); match: "
          f"{out['cpu_s_per_game_s']:.2f} CPU s per game s "
          f"({out['cpu_s_per_game_s_with_join']:.2f} with the join); wall {out['wall_s']:.1f} s")
    for part, value in out["parts"].items():
        print(f"  {part:24s} {value:6.3f} CPU s / game s")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(out, f, indent=1)


if __name__ == "__main__":
    main()
