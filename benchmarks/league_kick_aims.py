"""Where league kicks were asked to go, and where the ball went, from one LocalServer match.

    python benchmarks/league_kick_aims.py --left full --right chaser --seed 100331 --seconds 120

Plays one match (7 v 7 unless ``--team-size``, the league's default walk, through
``league_falls.play``) while recording, for every robot of the left team and every cycle, the
team's kick request (power, direction in the body frame) and the torso's yaw, so that each
request's direction is known in the world frame. Then, for every ball contact of a left robot
that moved the ball at least ``league_falls.KICK_M`` (the replay's kicks), it prints the
world direction of that robot's last kick request before the contact, the direction the ball
went, the direction from the ball to the centre of the goal the team attacks, and whether the
robot's kick motion played (``kick``) or it walked through the ball (``walk``, ``approach``).
Then the kick requests that never became a kick: runs of cycles with a request that ended
without the motion starting, and how long they lasted. Last, for a left team of the ``full``
family (``strategy.teams.player.decide_team``), the seconds of play in which the left robot
nearest the ball was doing each behaviour of its control request (``shoot``, ``pass``,
``clear``, ``dribble``, ``intercept``, ...). This is how the drift of the ball
to the wing in ``full``'s 7 v 7 league matches was read (docs/league.md).
"""

from __future__ import annotations

import argparse
import math
import sys
import tempfile
from collections import defaultdict
from contextlib import contextmanager
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import league_falls  # noqa: E402  (the sibling script)

#: a contact counts as answering a kick request made at most this long before it (s)
REQUEST_WINDOW_S = 4.0


@contextmanager
def _recording_kicks(requests: dict[str, list]):
    """Record, per agent and cycle, (kick request or None, torso yaw)."""
    from teamenv.league import adapter
    from teamenv.league.controller import torso_pose

    original = adapter.RequestEncoder.encode

    def encode(self, request, perception):
        try:
            yaw = float(torso_pose(perception)[2])
        except Exception:  # no torso in this perception (e.g. before the first beam)
            yaw = math.nan
        requests[self.who].append((None if request.kick is None else
                                   tuple(float(v) for v in request.kick), yaw))
        return original(self, request, perception)

    adapter.RequestEncoder.encode = encode
    try:
        yield
    finally:
        adapter.RequestEncoder.encode = original


@contextmanager
def _recording_behaviours(behaviours: dict[int, list]):
    """Record, per uniform number of a ``full``-family team, (game time, behaviour) of each
    control request its players decide (the left team's, when only one side is such a team)."""
    from strategy.teams import full

    original = full.decide_team

    def decide_team(players, wms):
        requests = original(players, wms)
        for player, wm, request in zip(players, wms, requests, strict=True):
            behaviours[player.me + 1].append((float(wm.time_s), request.behaviour))
        return requests

    full.decide_team = decide_team
    try:
        yield
    finally:
        full.decide_team = original


def behaviour_seconds(match: dict, behaviours: dict[int, list], replay) -> dict[str, float]:
    """Seconds of PlayOn in which the left robot nearest the ball did each behaviour (its
    last decision at or before that moment)."""
    from teamenv.league.controller import CYCLE_S
    from teamenv.sim.playmode import PlayMode

    n = match["team_size"]
    times = {u: np.array([t for t, _ in log]) for u, log in behaviours.items()}
    seconds: dict[str, float] = defaultdict(float)
    for row in range(len(replay.ball)):
        if int(replay.play_mode[row]) != int(PlayMode.PlayOn):
            continue
        d = np.hypot(*(replay.players[row, :n, :2] - replay.ball[row, :2]).T)
        unum = int(d.argmin()) + 1
        if unum not in times or not len(times[unum]):
            continue
        k = int(np.searchsorted(times[unum], replay.time_s[row], side="right")) - 1
        name = behaviours[unum][k][1] if k >= 0 else "none"
        if replay.fallen is not None and replay.fallen[row, unum - 1]:
            name = "(down)"
        seconds[name or "none"] += CYCLE_S
    return dict(sorted(seconds.items(), key=lambda kv: -kv[1]))


def _deg(angle: float) -> float:
    return math.degrees(math.remainder(angle, 2 * math.pi))


def contacts(match: dict, requests: dict[str, list], replay, field_half_length: float
             ) -> list[dict]:
    """Every left contact of at least KICK_M with the request that preceded it."""
    from teamenv.league.controller import CYCLE_S

    n = match["team_size"]
    agents = list(match["commands"])[:n]
    window = round(REQUEST_WINDOW_S / CYCLE_S)
    out = []
    if replay.kick_cycle is None:
        return out
    for cycle, player, metres, direction in zip(replay.kick_cycle, replay.kick_player,
                                                replay.kick_distance, replay.kick_direction,
                                                strict=True):
        if int(player) >= n or metres < league_falls.KICK_M:
            continue
        who = agents[int(player)]
        log = requests[who]
        states = match["commands"][who]
        asked = None
        for row in range(min(int(cycle) + 1, len(log) - 1), max(-1, int(cycle) - window), -1):
            if log[row][0] is not None and math.isfinite(log[row][1]):
                asked = (row, log[row][0], log[row][1])
                break
        ball = replay.ball[int(cycle)]
        goal = math.atan2(-ball[1], field_half_length - ball[0])
        state = states[min(int(cycle) + 1, len(states) - 1)][0]
        out.append({
            "time_s": round(float(replay.time_s[int(cycle)]), 1), "player": who,
            "metres": round(float(metres), 2), "ball": [round(float(v), 2) for v in ball[:2]],
            "ball_deg": round(_deg(float(direction)), 1), "goal_deg": round(_deg(goal), 1),
            "asked_deg": None if asked is None else round(_deg(asked[2] + asked[1][1]), 1),
            "asked_s_before": None if asked is None else
            round((int(cycle) - asked[0]) * CYCLE_S, 2),
            "state": state})
    return out


def unanswered(match: dict, requests: dict[str, list]) -> list[dict]:
    """Runs of cycles with a kick request whose robot never started its kick motion."""
    from teamenv.league.controller import CYCLE_S

    n = match["team_size"]
    out = []
    for who in list(match["commands"])[:n]:
        log, states = requests[who], match["commands"][who]
        start = None
        kicked = False
        for row, (kick, _) in enumerate(log + [(None, 0.0)]):
            state = states[row][0] if row < len(states) else "walk"
            if kick is not None or (start is not None and state in ("approach", "kick")):
                if start is None:
                    start, kicked = row, False
                kicked = kicked or state == "kick"
                continue
            if start is not None:
                if not kicked:
                    out.append({"player": who, "time_s": round(start * CYCLE_S, 1),
                                "seconds": round((row - start) * CYCLE_S, 1)})
                start = None
    return out


def main(argv: list[str] | None = None) -> None:
    from teamenv.field import field_preset
    from teamenv.league.match import FIELD
    from teamenv.replay import load_replay

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--left", default="full")
    parser.add_argument("--right", default="chaser")
    parser.add_argument("--seed", type=int, default=100331)
    parser.add_argument("--seconds", type=float, default=120.0)
    parser.add_argument("--team-size", type=int, default=7)
    args = parser.parse_args(argv)
    requests: dict[str, list] = defaultdict(list)
    behaviours: dict[int, list] = defaultdict(list)
    with tempfile.TemporaryDirectory() as tmp, _recording_kicks(requests), \
            _recording_behaviours(behaviours):
        match = league_falls.play(args.left, args.right, args.seed, args.seconds, False,
                                  Path(tmp), args.team_size)
        replay = load_replay(next(Path(tmp).glob("*.npz")))
    half_length = field_preset(FIELD).half_length
    print(f"{args.left} v {args.right}, seed {args.seed}: score {match['score']}, "
          f"{match['kicks']} kicks >= {league_falls.KICK_M} m, {match['cpu_s']} CPU s")
    rows = contacts(match, requests, replay, half_length)
    print("time   player      m    ball (x, y)     ball°  asked°  goal°  asked s before  state")
    for r in rows:
        asked = "   -  " if r["asked_deg"] is None else f"{r['asked_deg']:6.1f}"
        before = "  -" if r["asked_s_before"] is None else f"{r['asked_s_before']:5.2f}"
        print(f"{r['time_s']:5.1f}  {r['player']:10s} {r['metres']:5.2f}  "
              f"({r['ball'][0]:6.2f}, {r['ball'][1]:6.2f})  {r['ball_deg']:6.1f}  {asked}  "
              f"{r['goal_deg']:6.1f}  {before}  {r['state']}")
    errors = [abs(math.remainder(math.radians(r["ball_deg"] - r["asked_deg"]), 2 * math.pi))
              for r in rows if r["asked_deg"] is not None]
    off_goal = [abs(math.remainder(math.radians(r["asked_deg"] - r["goal_deg"]), 2 * math.pi))
                for r in rows if r["asked_deg"] is not None]
    if errors:
        print(f"ball v asked: mean |error| {math.degrees(np.mean(errors)):.1f}° over "
              f"{len(errors)} contacts; asked v goal: mean {math.degrees(np.mean(off_goal)):.1f}°")
    gaps = unanswered(match, requests)
    print(f"kick requests never kicked: {len(gaps)}, "
          f"{sum(g['seconds'] for g in gaps):.1f} s in all; longest "
          f"{max((g['seconds'] for g in gaps), default=0.0):.1f} s")
    if behaviours:
        print("seconds of play by the behaviour of the left robot nearest the ball:",
              {k: round(v, 1) for k, v in behaviour_seconds(match, behaviours, replay).items()})


if __name__ == "__main__":
    main()
