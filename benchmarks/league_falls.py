"""Falls in league matches on LocalServer, from their replays, with what each robot was doing.

    python benchmarks/league_falls.py --seeds 100201:100204 --seconds 40          # ramp on and off
    python benchmarks/league_falls.py --seeds 100201:100202 --ramp on --json out.json
    python benchmarks/league_falls.py --left chaser --right static --team-size 1 --seconds 120 \
        --ramp off --seeds 100201:100211                # one robot kicking on its own

Plays ``--left`` v ``--right`` (7 v 7 unless ``--team-size``, ``LocalServer``, the league's
default walk) for every seed, once with the command ramp (``teamenv.league.command_ramp``) and once without, records
each match as a replay and reads its falls with ``teamenv.league.replay.fall_events`` (latched
falls, the nearest other robot 5 cycles before). For each fall it reports what the robot's
encoder did in the cycle it went down (``walk``: the team's walk through the controller;
``approach``: walking to the kick spot on the kick's own walker; ``kick``; ``stand``) and the
walk the team asked for in the second before (``jump``: the requested command moved by more
than the league body's accelerations allow in one cycle, the kind of request the ramp
smooths). The encoder's state is read by wrapping ``RequestEncoder.encode`` for the run (as
``league_match_cost.py`` wraps the parts it times).

Prints falls per match for each setting with the share near another robot (< 1 m) and the
share by state, and the kicks that moved the ball at least ``KICK_M`` (the replay's kicks) and
the goals per match; ``--json`` writes every fall, ``--commands`` every robot's state and
requested walk per cycle (``league_walk_playback.py`` walks them again on a lone robot).
"""

from __future__ import annotations

import argparse
import json
import tempfile
import time
from collections import Counter, defaultdict
from contextlib import contextmanager
from pathlib import Path

NEAR_M = 1.0
#: a kick in the replay that moved the ball this far (m) counts as a kick (not a touch)
KICK_M = 1.0
LOOKBACK_CYCLES = 50


@contextmanager
def _recording(log: dict[str, list]):
    """Record, per agent, each cycle's encoder state and requested walk."""
    from teamenv.league import adapter

    original = adapter.RequestEncoder.encode

    def encode(self, request, perception):
        playing = self._motion
        message = original(self, request, perception)
        motion = playing or self._motion
        if motion is not None and motion is self.get_up:
            state = "get_up"
        elif motion is not None and motion is self.kick:
            state = "kick"
        elif request.beam is not None:
            state = "beam"
        elif self.kick is not None and self._walking is self.kick.walker \
                and self._walking is not self.controller:
            state = "approach"
        elif not any(request.walk) and request.kick is None:
            state = "stand"
        else:
            state = "walk"
        log[self.who].append((state, tuple(float(v) for v in request.walk)))
        return message

    adapter.RequestEncoder.encode = encode
    try:
        yield
    finally:
        adapter.RequestEncoder.encode = original


def _jumped(walks: list[tuple[float, float, float]], accel, cycle_s: float) -> bool:
    limit = [a * cycle_s for a in accel]
    return any(any(abs(b - a) > lim + 1e-9 for a, b, lim in zip(w0, w1, limit, strict=True))
               for w0, w1 in zip(walks, walks[1:], strict=False))


def play(left: str, right: str, seed: int, seconds: float, ramp: bool, workdir: Path,
         team_size: int = 7) -> dict:
    from locomotion import load_profile
    from teamenv.league.controller import CYCLE_S
    from teamenv.league.match import LOCOMOTION_PROFILE, LeagueMatchOptions, play_league_match
    from teamenv.league.replay import fall_events
    from teamenv.replay import load_replay

    accel = [float(a) for a in load_profile(LOCOMOTION_PROFILE).accel]
    log: dict[str, list] = defaultdict(list)
    path = workdir / f"{left}-{right}-{seed}-{'ramp' if ramp else 'noramp'}.npz"
    start = time.process_time()
    with _recording(log):
        result = play_league_match(left, right, LeagueMatchOptions(
            team_size=team_size, game_s=seconds, server="local", ramp=ramp), seed=seed,
            replay_path=path)
    cpu = time.process_time() - start
    replay = load_replay(path)
    # player index (left team first, by uniform number) -> the agent's name in the log
    agents = []
    for team_prefix in _team_prefixes(log):
        agents += [f"{team_prefix}_{u}" for u in range(1, team_size + 1)]
    falls = []
    for event in fall_events(replay):
        # replay row r is recorded after the encoders' call r + 1 (the first is the beam)
        history = log[agents[event.player]][max(0, event.row + 1 - LOOKBACK_CYCLES):event.row + 2]
        walks = [w for s, w in history if s == "walk"]
        falls.append({"row": event.row, "time_s": round(event.row * CYCLE_S, 2),
                      "agent": agents[event.player], "nearest_m": round(event.nearest_m, 3),
                      "state": history[-1][0] if history else "unknown",
                      "jump": _jumped(walks, accel, CYCLE_S)})
    return {"left": left, "right": right, "seed": seed, "seconds": seconds, "ramp": ramp,
            "score": list(result.score), "cpu_s": round(cpu, 1), "falls": falls,
            "commands": {who: [[state, *walk] for state, walk in log[who]] for who in agents},
            "team_size": team_size,
            "kicks": 0 if replay.kick_distance is None
            else int((replay.kick_distance >= KICK_M).sum())}


def _team_prefixes(log: dict[str, list]) -> list[str]:
    """The two teams' agent-name prefixes, left first (the left side acts first, so its
    agents enter the log first; the names are 'agent TEAM_UNUM')."""
    teams = []
    for who in log:
        prefix = who.rsplit("_", 1)[0]
        if prefix not in teams:
            teams.append(prefix)
    return teams


def summary(matches: list[dict]) -> str:
    lines = ["setting   matches  falls/match  kicks/match  goals/match  near (<1 m)  after a jump"
             "  by state"]
    for ramp in (True, False):
        runs = [m for m in matches if m["ramp"] == ramp]
        if not runs:
            continue
        falls = [f for m in runs for f in m["falls"]]
        n = max(len(falls), 1)
        states = Counter(f["state"] for f in falls)
        lines.append(
            f"{'ramp' if ramp else 'no ramp':9s} {len(runs):7d}  {len(falls) / len(runs):11.2f}  "
            f"{sum(m.get('kicks', 0) for m in runs) / len(runs):11.2f}  "
            f"{sum(sum(m['score']) for m in runs) / len(runs):11.2f}  "
            f"{sum(f['nearest_m'] < NEAR_M for f in falls) / n:10.0%}  "
            f"{sum(f['jump'] for f in falls) / n:12.0%}  "
            + ", ".join(f"{k} {v}" for k, v in states.most_common()))
        lines.append("          per match: " + " ".join(
            f"{m['seed']}:{len(m['falls'])}" for m in runs))
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--left", default="full")
    parser.add_argument("--right", default="chaser")
    parser.add_argument("--seeds", default="100201:100204", help="START:STOP (half-open)")
    parser.add_argument("--seconds", type=float, default=40.0)
    parser.add_argument("--team-size", type=int, default=7)
    parser.add_argument("--ramp", choices=("both", "on", "off"), default="both")
    parser.add_argument("--json", type=Path, default=None)
    parser.add_argument("--replay-dir", type=Path, default=None,
                        help="keep the matches' replays here (default: a temporary folder)")
    parser.add_argument("--commands", type=Path, default=None,
                        help="write every robot's state and requested walk per cycle here")
    args = parser.parse_args(argv)
    first, stop = (int(v) for v in args.seeds.split(":"))
    settings = {"both": (True, False), "on": (True,), "off": (False,)}[args.ramp]
    matches = []
    with tempfile.TemporaryDirectory() as tmp:
        workdir = Path(tmp) if args.replay_dir is None else args.replay_dir
        workdir.mkdir(parents=True, exist_ok=True)
        for seed in range(first, stop):
            for ramp in settings:
                m = play(args.left, args.right, seed, args.seconds, ramp, workdir,
                         args.team_size)
                matches.append(m)
                print(f"seed {seed} {'ramp' if ramp else 'no ramp'}: {len(m['falls'])} falls, "
                      f"{m['kicks']} kicks, score {m['score']}, {m['cpu_s']} CPU s", flush=True)
    print(summary(matches))
    if args.commands:
        # every robot's encoder state and requested walk per cycle, for league_walk_playback.py
        args.commands.write_text(json.dumps({"matches": [
            {"seed": m["seed"], "ramp": m["ramp"], "commands": m["commands"]}
            for m in matches]}) + "\n")
    if args.json:
        args.json.write_text(json.dumps({"matches": [
            {k: v for k, v in m.items() if k != "commands"} for m in matches]}, indent=1) + "\n")


if __name__ == "__main__":
    main()
