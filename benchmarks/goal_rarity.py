# Over 500 lines because it is one self-contained measurement: the counting rules
# (MatchCounter) are read against the definitions in the docstring below, next to the runner
# and the report that use them.
"""Why goals are rare: kicks, shots, possession, ball travel and dead time, per side and match.

    python benchmarks/goal_rarity.py                       # full:chaser, chaser:chaser, full:silent
    python benchmarks/goal_rarity.py --pairings full:chaser --matches 8 -j 2 --json out.json
    python benchmarks/goal_rarity.py --field simspark --team-size 11 --pairings full:chaser
    python benchmarks/goal_rarity.py --combine a.json b.json --json all.json   # pool runs

Each pairing plays ``--matches`` seeded matches (seeds ``--first-seed``, +1, ...; sides
alternate: the first team plays left on even offsets, right on odd ones) of 2 x ``--half-time``
seconds through ``teamenv.parallel_env`` with both sides built-in teams, stepping
``env.step({})``. From what the env reports every cycle (``env.last_report.kicks`` and
``.referee``, ``env.sim.world.touches``, the ball's state, the referee's play mode, time and
attack directions) ``MatchCounter`` counts, per side:

- kicks (count, mean commanded distance, mean distance the ball actually travelled until the
  next touch, stop or whistle) and dribble touches (a player's contact with the ball that is
  not a kick, counted once per run of consecutive cycles);
- on-frame kicks (the kick's world direction crosses the opponent goal line between the posts)
  and shots (on frame and the crossing no further than the kick's distance + ``reach_margin``);
  each kick's outcome: goal, out (goal kick / corner / kick-in), blocked (an opponent touched or
  kicked it first), teammate (a teammate touched it first), self (the kicker reached it again),
  stopped (the ball came to rest untouched), half (the half ended); a kick an opponent blocked
  before the ball had gone 1 m was blocked at the foot;
- possession (the team that touched last): changes, where the losing side lost it (its own
  defensive / middle / attacking third), in open play or at a restart;
- ball travel per match, time the ball spends in each third (seen from the side), time in play
  (PlayOn) against dead ball (kick-offs, set plays, goal pauses), set plays by kind;
- goals, of them the opponents' own goals, goals that end a shot, and the time from such a
  shot to the goal.

The table shows the mean per match with a 95 % t interval over matches (the point itself when
every match gave the same value). ``--json`` writes every match's numbers and the summaries.
"""

from __future__ import annotations

import argparse
import json
import math
import time
from collections.abc import Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from teamenv.analytics.geometry import THIRDS, goal_line_crossing, third_index

PAIRINGS = "full:chaser,chaser:chaser,full:silent"
OUTCOMES = ("goal", "out", "blocked", "teammate", "self", "stopped", "half", "open")
#: the kicker's own contacts in the kick's first cycles are the kick itself, not a re-touch
KICK_GRACE_CYCLES = 5
STOPPED_SPEED = 0.05  # m/s: a ball slower than this has come to rest
DEAD_KINDS = {"kickoff": ("KickOff", "BeforeKickOff"), "goal_pause": ("Goal",),
              "kickin": ("KickIn",), "corner_goalkick": ("CornerKick", "GoalKick")}
AT_FOOT_M = 1.0  # a kick blocked before the ball travelled this far was blocked at the foot
TELEPORT_M = 1.0  # a one-cycle ball move longer than this is a placement, not travel


@dataclass
class Cycle:
    """What the counter needs from one cycle (after the env stepped)."""

    kicks: Sequence[tuple[int, float, float]]  # (player, distance m, world direction rad)
    touches: Sequence[int]  # players whose body touched the ball this cycle (physics)
    events: Sequence[Any]  # RefereeEvent-like: .kind, .team, .time_s, .play_mode, .player
    ball: Sequence[float]  # x, y, vx, vy after the cycle
    mode: str  # the play mode's name after the cycle
    time_s: float  # game time after the cycle
    attack_sign: Sequence[float]  # (left, right): +1 attacks +x


@dataclass
class _Kick:
    player: int
    team: int
    cycle: int
    time_s: float
    start: tuple[float, float]
    distance: float
    direction: float
    on_frame: bool
    shot: bool
    goal_distance: float  # metres from the kick spot to where its line crosses the goal line
    travel: float = 0.0


@dataclass
class SideStats:
    kicks: int = 0
    kick_distance_sum: float = 0.0
    kick_travel_sum: float = 0.0
    kicks_resolved: int = 0
    dribble_touches: int = 0
    attacking_third_kicks: int = 0
    on_frame: int = 0
    on_frame_short: int = 0  # on frame but the kick's distance falls short of the goal line
    shots: int = 0
    shot_distance_sum: float = 0.0  # distance to the goal line along the shot
    shot_travel_sum: float = 0.0  # how far shots went before their outcome
    shots_blocked_by_keeper: int = 0  # blocked by the opponents' player 1 (index 0: the goalie)
    kick_outcomes: dict[str, int] = field(default_factory=lambda: dict.fromkeys(OUTCOMES, 0))
    blocked_at_foot: int = 0  # kicks an opponent blocked before the ball had gone 1 m
    shot_outcomes: dict[str, int] = field(default_factory=lambda: dict.fromkeys(OUTCOMES, 0))
    goals: int = 0
    own_goals: int = 0  # goals this side scored into its own goal (last touch its own)
    goals_from_shots: int = 0
    shot_to_goal_s_sum: float = 0.0
    possession_cycles: int = 0  # PlayOn cycles with this side's last touch
    possession_gains: int = 0
    possession_losses: dict[str, int] = field(default_factory=lambda: dict.fromkeys(THIRDS, 0))
    losses_open_play: int = 0
    losses_restart: int = 0
    ball_third_cycles: dict[str, int] = field(default_factory=lambda: dict.fromkeys(THIRDS, 0))
    set_plays: dict[str, int] = field(default_factory=dict)  # awarded to this side, by kind
    drop_balls: int = 0  # this side's set plays nobody took in time


class MatchCounter:
    """Consumes one match's cycles (``add``) and counts per side (0 = left, 1 = right).

    ``half_length``/``half_goal_width``: the pitch; ``team_size``: players 0..N-1 are the left
    side; ``start_ball``: the ball before the first cycle; ``cycle_s``: seconds per cycle;
    ``reach_margin``: how much further than its distance a shot may still count as reaching.
    """

    def __init__(self, half_length: float, half_goal_width: float, team_size: int,
                 start_ball: Sequence[float] = (0.0, 0.0, 0.0, 0.0), cycle_s: float = 0.02,
                 reach_margin: float = 0.5) -> None:
        self.half_length, self.half_goal_width = float(half_length), float(half_goal_width)
        self.team_size, self.cycle_s, self.reach_margin = team_size, cycle_s, reach_margin
        self.sides = (SideStats(), SideStats())
        self.cycles = 0
        self.play_on_cycles = 0
        self.mode_cycles: dict[str, int] = {}
        self.ball_travel = 0.0
        self.possession_changes = 0
        self.possession: int | None = None  # the side that touched last
        self.prev_ball = (float(start_ball[0]), float(start_ball[1]))
        self.prev_mode = "BeforeKickOff"
        self.kick: _Kick | None = None
        self._touching: set[int] = set()
        self._attack_sign: tuple[float, ...] = (1.0, -1.0)

    def team(self, player: int) -> int:
        return int(player) // self.team_size

    # -- geometry ---------------------------------------------------------------------------
    def third(self, x: float, sign: float) -> str:
        """The third of the pitch at ``x`` seen by a side attacking towards ``sign``."""
        return THIRDS[int(third_index(x, sign, self.half_length))]

    def goal_line_crossing(self, start: tuple[float, float], direction: float,
                           sign: float) -> tuple[float, float] | None:
        """(distance along the direction, y) where a ball going ``direction`` from ``start``
        crosses the goal line at ``sign * half_length``; None if it moves away from it."""
        return goal_line_crossing(start, direction, sign, self.half_length)

    # -- the cycle --------------------------------------------------------------------------
    def add(self, cyc: Cycle) -> None:
        self.cycles += 1
        self._attack_sign = tuple(float(v) for v in cyc.attack_sign)
        mode = cyc.mode
        self.mode_cycles[mode] = self.mode_cycles.get(mode, 0) + 1
        bx, by, vx, vy = (float(v) for v in cyc.ball[:4])
        teleport = any(e.kind in ("play_mode", "half_time", "game_over") and
                       (e.kind != "play_mode" or e.play_mode != "PlayOn") for e in cyc.events)
        step = math.hypot(bx - self.prev_ball[0], by - self.prev_ball[1])
        if teleport or step > TELEPORT_M:
            step = 0.0
        self.ball_travel += step
        if self.kick is not None:
            self.kick.travel += step

        restart = self.prev_mode != "PlayOn"
        # 1. kicks (before physics): one ends the running kick, then starts its own
        for player, distance, direction in cyc.kicks:
            t = self.team(player)
            if self.kick is not None:
                self._end_kick(self._touch_outcome(player), cyc.time_s)
            self._touched(player, restart, (bx, by))
            self._start_kick(int(player), t, float(distance), float(direction), cyc.time_s,
                             restart=restart)
        # 2. physics contacts
        kickers = {int(k[0]) for k in cyc.kicks}
        now_touching = set()
        for player in cyc.touches:
            player = int(player)
            now_touching.add(player)
            if player not in self._touching and player not in kickers:
                self.sides[self.team(player)].dribble_touches += 1
            if self.kick is not None and not (
                    player == self.kick.player and
                    self.cycles - self.kick.cycle <= KICK_GRACE_CYCLES):
                self._end_kick(self._touch_outcome(player), cyc.time_s)
            self._touched(player, restart, (bx, by))
        self._touching = now_touching
        # 3. the referee
        for e in cyc.events:
            if e.kind == "goal":
                scorer = int(e.team)
                s = self.sides[scorer]
                s.goals += 1
                if e.player is not None and self.team(e.player) != scorer:
                    self.sides[1 - scorer].own_goals += 1
                if self.kick is not None:
                    if self.kick.team == scorer and self.kick.shot:
                        s.goals_from_shots += 1
                        s.shot_to_goal_s_sum += e.time_s - self.kick.time_s
                    self._end_kick("goal", e.time_s)
            elif e.kind == "play_mode" and e.play_mode:
                kind = e.play_mode.rsplit("_", 1)[0]
                if kind in ("KickIn", "CornerKick", "GoalKick", "KickOff") and e.team is not None:
                    sp = self.sides[int(e.team)].set_plays
                    sp[kind] = sp.get(kind, 0) + 1
                if kind in ("KickIn", "CornerKick", "GoalKick") and self.kick is not None:
                    self._end_kick("out", e.time_s)
            elif e.kind == "drop_ball" and e.team is not None:
                self.sides[int(e.team)].drop_balls += 1
            if e.kind in ("half_time", "game_over") and self.kick is not None:
                self._end_kick("half", e.time_s)
        # 4. a kicked ball that came to rest untouched
        if self.kick is not None and mode == "PlayOn" and math.hypot(vx, vy) < STOPPED_SPEED \
                and self.cycles > self.kick.cycle:
            self._end_kick("stopped", cyc.time_s)
        # 5. time
        if mode == "PlayOn":
            self.play_on_cycles += 1
            for t in (0, 1):
                self.sides[t].ball_third_cycles[self.third(bx, cyc.attack_sign[t])] += 1
            if self.possession is not None:
                self.sides[self.possession].possession_cycles += 1
        self.prev_ball = (bx, by)
        self.prev_mode = mode

    def _touch_outcome(self, player: int) -> str:
        if player == self.kick.player:
            return "self"
        if self.team(player) == self.kick.team:
            return "teammate"
        if self.kick.shot and player % self.team_size == 0:
            self.sides[self.kick.team].shots_blocked_by_keeper += 1
        return "blocked"

    def _touched(self, player: int, restart: bool, ball: tuple[float, float]) -> None:
        t = self.team(player)
        if self.possession is not None and self.possession != t:
            self.possession_changes += 1
            loser = self.sides[self.possession]
            sign = self._attack_sign[self.possession]
            loser.possession_losses[self.third(ball[0], sign)] += 1
            if restart:
                loser.losses_restart += 1
            else:
                loser.losses_open_play += 1
            self.sides[t].possession_gains += 1
        self.possession = t

    def _start_kick(self, player: int, team: int, distance: float, direction: float,
                    time_s: float, restart: bool) -> None:
        sign = self._attack_sign[team]
        start = self.prev_ball  # the ball where it lay when the foot met it
        s = self.sides[team]
        s.kicks += 1
        s.kick_distance_sum += distance
        if self.third(start[0], sign) == "attacking":
            s.attacking_third_kicks += 1
        cross = self.goal_line_crossing(start, direction, sign)
        on_frame = cross is not None and abs(cross[1]) < self.half_goal_width
        reach = cross[0] if cross is not None else math.inf
        shot = on_frame and reach <= distance + self.reach_margin
        if on_frame:
            s.on_frame += 1
            if not shot:
                s.on_frame_short += 1
        if shot:
            s.shots += 1
            s.shot_distance_sum += reach
        self.kick = _Kick(player, team, self.cycles, time_s, start, distance, direction,
                          on_frame, shot, reach)

    def _end_kick(self, outcome: str, time_s: float) -> None:
        k, self.kick = self.kick, None
        s = self.sides[k.team]
        s.kick_outcomes[outcome] += 1
        if outcome == "blocked" and k.travel < AT_FOOT_M:
            s.blocked_at_foot += 1
        s.kicks_resolved += 1
        s.kick_travel_sum += k.travel
        if k.shot:
            s.shot_outcomes[outcome] += 1
            s.shot_travel_sum += k.travel

    def finish(self) -> None:
        """Close a kick still running at the end of the match."""
        if self.kick is not None:
            k, self.kick = self.kick, None
            s = self.sides[k.team]
            s.kick_outcomes["open"] += 1
            s.kicks_resolved += 1
            s.kick_travel_sum += k.travel
            if k.shot:
                s.shot_outcomes["open"] += 1

    # -- results ----------------------------------------------------------------------------
    def side_metrics(self, t: int) -> dict[str, float]:
        """Flat numbers of side ``t`` for one match."""
        s = self.sides[t]
        play_on = max(self.play_on_cycles, 1)
        m: dict[str, float] = {
            "goals": s.goals,
            "opponent_own_goals": self.sides[1 - t].own_goals,  # of this side's goals
            "kicks": s.kicks,
            "kick_distance_mean_m": s.kick_distance_sum / s.kicks if s.kicks else math.nan,
            "kick_travel_mean_m": (s.kick_travel_sum / s.kicks_resolved
                                   if s.kicks_resolved else math.nan),
            "dribble_touches": s.dribble_touches,
            "attacking_third_kicks": s.attacking_third_kicks,
            "on_frame_kicks": s.on_frame,
            "on_frame_short": s.on_frame_short,
            "shots": s.shots,
            "shot_distance_mean_m": s.shot_distance_sum / s.shots if s.shots else math.nan,
            "shot_travel_mean_m": s.shot_travel_sum / s.shots if s.shots else math.nan,
            "shots_blocked_by_keeper": s.shots_blocked_by_keeper,
            "goals_from_shots": s.goals_from_shots,
            "shot_to_goal_s_mean": (s.shot_to_goal_s_sum / s.goals_from_shots
                                    if s.goals_from_shots else math.nan),
            "possession_pct": 100.0 * s.possession_cycles / play_on,
            "possession_losses": sum(s.possession_losses.values()),
            "losses_open_play": s.losses_open_play,
            "losses_restart": s.losses_restart,
            "drop_balls": s.drop_balls,
        }
        for o in OUTCOMES:
            m[f"kicks_{o}"] = s.kick_outcomes[o]
            if o == "blocked":
                m["kicks_blocked_at_foot"] = s.blocked_at_foot
            m[f"shots_{o}"] = s.shot_outcomes[o]
        for third in THIRDS:
            m[f"lost_in_{third}_third"] = s.possession_losses[third]
            m[f"ball_in_{third}_third_pct"] = 100.0 * s.ball_third_cycles[third] / play_on
        for kind in ("KickOff", "KickIn", "CornerKick", "GoalKick"):
            m[f"set_plays_{kind}"] = s.set_plays.get(kind, 0)
        return m

    def match_metrics(self) -> dict[str, float]:
        dt = self.cycle_s
        dead = self.cycles - self.play_on_cycles
        return {
            "goals_total": self.sides[0].goals + self.sides[1].goals,
            "kicks_total": self.sides[0].kicks + self.sides[1].kicks,
            "shots_total": self.sides[0].shots + self.sides[1].shots,
            "possession_changes": self.possession_changes,
            "ball_travel_m": self.ball_travel,
            "play_on_s": self.play_on_cycles * dt,
            "dead_ball_s": dead * dt,
            "dead_ball_pct": 100.0 * dead / max(self.cycles, 1),
            **{f"dead_{kind}_s": dt * sum(v for k, v in self.mode_cycles.items()
                                          if k.rsplit("_", 1)[0] in kinds)
               for kind, kinds in DEAD_KINDS.items()},
            **{f"mode_{k}_s": v * dt for k, v in sorted(self.mode_cycles.items())},
        }


# -- playing ----------------------------------------------------------------------------------
def cycle_from_env(env) -> Cycle:
    """The counter's view of the cycle the env has just stepped."""
    sim = env.sim
    ref = sim.referee
    return Cycle(kicks=list(env.last_report.kicks), touches=list(sim.world.touches),
                 events=list(env.last_report.referee), ball=sim.world.ball_state(),
                 mode=ref.mode.name, time_s=ref.time_s, attack_sign=tuple(ref.attack_sign))


def play_and_count(left: str, right: str, seed: int, field_name: str, team_size: int,
                   half_time_s: float) -> MatchCounter:
    """Play one seeded match (both sides built-in teams) and count it."""
    import teamenv
    from teamenv.config import RulesConfig
    env = teamenv.parallel_env(left=left, right=right, field=field_name, team_size=team_size,
                               rules=RulesConfig(half_time_s=half_time_s))
    env.reset(seed=seed)
    counter = MatchCounter(env.field.half_length, env.field.half_goal_width, env.team_size,
                           start_ball=env.sim.world.ball_state(), cycle_s=env.physics.cycle_s)
    while not env.episode_over:
        env.step({})
        counter.add(cycle_from_env(env))
    counter.finish()
    return counter


def run_match(job: tuple[str, str, int, bool, str, int, float]) -> dict[str, Any]:
    """One match of team A against team B (A plays right when ``swap``): A's and B's numbers."""
    a, b, seed, swap, field_name, team_size, half_time_s = job
    left, right = (b, a) if swap else (a, b)
    start = time.perf_counter()
    c = play_and_count(left, right, seed, field_name, team_size, half_time_s)
    side_a, side_b = (1, 0) if swap else (0, 1)
    return {"seed": seed, "a_side": "right" if swap else "left",
            "a": c.side_metrics(side_a), "b": c.side_metrics(side_b),
            "match": c.match_metrics(), "wall_s": time.perf_counter() - start}


def mean_ci(values: Sequence[float], confidence: float = 0.95) -> tuple[float, float, float]:
    """(mean, low, high): a t interval over matches (NaNs dropped; one value or all equal:
    the point itself; no value: NaNs)."""
    from scipy.stats import t as student_t
    x = np.asarray([v for v in values if not (isinstance(v, float) and math.isnan(v))],
                   dtype=float)
    if x.size == 0:
        return math.nan, math.nan, math.nan
    mean = float(x.mean())
    if x.size < 2 or np.all(x == x[0]):
        return mean, mean, mean
    half = float(student_t.ppf(0.5 + confidence / 2, x.size - 1) * x.std(ddof=1) / math.sqrt(x.size))
    return mean, mean - half, mean + half


def summarize(matches: list[dict[str, Any]]) -> dict[str, dict[str, list[float]]]:
    out: dict[str, dict[str, list[float]]] = {}
    for part in ("a", "b", "match"):
        keys = list(dict.fromkeys(k for m in matches for k in m[part]))
        # a play mode a match never saw lasted 0 s there; a number a file lacks is unknown
        out[part] = {k: list(mean_ci([m[part].get(k, 0.0 if k.startswith("mode_") else math.nan)
                                      for m in matches])) for k in keys}
    return out


def _fmt(ci: Sequence[float]) -> str:
    mean, low, high = ci
    if math.isnan(mean):
        return "-"
    if low == high:
        return f"{mean:.2f}"
    return f"{mean:.2f} [{low:.2f}, {high:.2f}]"


def print_table(a: str, b: str, summary: dict[str, Any], n: int) -> None:
    print(f"\n{a} (A) vs {b} (B): mean per match [95 % t interval], {n} matches")
    width = max(len(k) for k in summary["a"])
    print(f"  {'per side':<{width}}  {'A: ' + a:<28}  {'B: ' + b:<28}")
    for key in summary["a"]:
        print(f"  {key:<{width}}  {_fmt(summary['a'][key]):<28}  {_fmt(summary['b'][key]):<28}")
    print("  per match")
    for key, ci in summary["match"].items():
        print(f"  {key:<{width}}  {_fmt(ci)}")


def combine(paths: Sequence[str], out: str | None) -> None:
    """Summarize the matches of several ``--json`` outputs of the same settings together."""
    reports = [json.load(open(p)) for p in paths]
    keys = ("field", "team_size", "half_time_s")
    first = reports[0]
    if any(tuple(r[k] for k in keys) != tuple(first[k] for k in keys) for r in reports):
        raise SystemExit("--combine: the files' field, team size or half time differ")
    pairs: dict[tuple[str, str], dict[int, dict[str, Any]]] = {}
    for r in reports:
        for p in r["pairings"]:
            got = pairs.setdefault((p["a"], p["b"]), {})
            for m in p["matches"]:
                got.setdefault(m["seed"], m)
    combined: dict[str, Any] = {k: first[k] for k in keys}
    combined.update(combined_from=list(paths), wall_s=sum(r["wall_s"] for r in reports),
                    pairings=[])
    print(f"{first['field']} {first['team_size']} v {first['team_size']}, "
          f"2 x {first['half_time_s']:g} s, combined from {', '.join(paths)}")
    for (a, b), by_seed in pairs.items():
        matches = [by_seed[k] for k in sorted(by_seed)]
        summary = summarize(matches)
        print_table(a, b, summary, len(matches))
        print(f"  seeds {sorted(by_seed)}; scores (A-B): "
              f"{[(m['a']['goals'], m['b']['goals']) for m in matches]}")
        combined["pairings"].append({"a": a, "b": b, "summary": summary, "matches": matches})
    if out:
        with open(out, "w") as fh:
            json.dump(combined, fh, indent=1, default=float)


def main(argv: Sequence[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pairings", default=PAIRINGS, help="a:b,... (default %(default)s)")
    parser.add_argument("--field", default="mj7v7")
    parser.add_argument("--team-size", type=int, default=7)
    parser.add_argument("--half-time", type=float, default=300.0, help="seconds per half")
    parser.add_argument("--matches", type=int, default=4, help="matches per pairing")
    parser.add_argument("--first-seed", type=int, default=5000)
    parser.add_argument("-j", "--jobs", type=int, default=2)
    parser.add_argument("--json", help="write every match's numbers and the summaries here")
    parser.add_argument("--combine", nargs="+", metavar="JSON",
                        help="play nothing: summarize the matches of these --json files together "
                             "(pairings and settings must agree; a match's seed counts once)")
    args = parser.parse_args(argv)
    if args.combine:
        combine(args.combine, args.json)
        return
    pairs = [tuple(p.split(":")) for p in args.pairings.split(",") if p]
    jobs = [(a, b, args.first_seed + k, k % 2 == 1, args.field, args.team_size, args.half_time)
            for a, b in pairs for k in range(args.matches)]
    print(f"{args.field} {args.team_size} v {args.team_size}, 2 x {args.half_time:g} s, "
          f"{args.matches} matches per pairing, seeds {args.first_seed}.."
          f"{args.first_seed + args.matches - 1}, sides alternating", flush=True)
    start = time.perf_counter()
    with ProcessPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        results = list(pool.map(run_match, jobs))
    wall = time.perf_counter() - start
    report: dict[str, Any] = {"field": args.field, "team_size": args.team_size,
                              "half_time_s": args.half_time, "matches": args.matches,
                              "first_seed": args.first_seed, "wall_s": wall, "pairings": []}
    for i, (a, b) in enumerate(pairs):
        matches = results[i * args.matches:(i + 1) * args.matches]
        summary = summarize(matches)
        print_table(a, b, summary, len(matches))
        scores = [(m["a"]["goals"], m["b"]["goals"]) for m in matches]
        print(f"  scores (A-B) by seed: {scores}")
        report["pairings"].append({"a": a, "b": b, "summary": summary, "matches": matches})
    print(f"\n[{wall:.0f} s wall]")
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(report, fh, indent=1, default=float)


if __name__ == "__main__":
    main()
