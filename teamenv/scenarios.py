"""Scenarios: named starting situations (who stands where, the ball, the play mode) and how
each ends, for ``parallel_env(scenario=...)``.

Every scenario is told from the left team's side: the left team attacks the goal at +x, the
right team defends it. Spots are given relative to the goals and touchlines, so a scenario
plays on any field preset; ``Scenario.field`` is the preset used when the caller names none.
Placement is deterministic per ``reset(seed)``: each player is moved by a small uniform jitter
drawn from a generator of its own (a child of the episode's seed), so the env's other random
draws are the same as without a scenario.
"""

from __future__ import annotations

import dataclasses  # dataclasses.field: a Scenario has a field named "field"
import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from paramkit.checks import check_fields, non_negative, positive
from teamenv.errors import ConfigError
from teamenv.field import FieldSpec
from teamenv.sim.playmode import PlayMode

if TYPE_CHECKING:  # the env passes its Simulation and CycleReport in
    from teamenv.sim.simulation import CycleReport, Simulation

#: Conditions that end (terminate) a scenario episode, checked in this order after each step.
#: ``goal``: either team scored. ``ball_out``: the ball left the pitch without a goal (the
#: referee called a kick-in, corner or goal kick). ``defender_possession``: a right (defending)
#: player was the last to touch the ball (a touch, block or kick all count). ``game_over``: the
#: match ended (both halves played).
END_CONDITIONS = ("goal", "ball_out", "defender_possession", "game_over")
#: The reason a scenario episode is truncated: its ``max_duration_s`` of game time ran out.
TIME_LIMIT = "time_limit"

#: Distance (m) from the centre of a player to the centre of the ball it starts with, straight
#: ahead: within the T1 profile's kick reach (0.35 m), just clear of its body (0.2 m radius).
BALL_AT_FEET_M = 0.3


@dataclass(frozen=True)
class Spot:
    """A pose, given relative to the pitch (metres, radians, world frame: the left team attacks
    the goal at +x, +y is to the attackers' left).

    ``goal_distance``: metres from the goal line the left team attacks (x = length/2 - d), or
    from the left team's own goal line when ``own_goal`` (x = -length/2 + d). ``y``: metres
    from the centre line of the pitch, or inward from the +y touchline when ``from_touchline``
    (y = width/2 - y). ``heading``: 0 faces the attacked goal, pi faces the left team's goal.
    """

    goal_distance: float
    y: float = 0.0
    heading: float = 0.0
    own_goal: bool = False
    from_touchline: bool = False

    def pose(self, field: FieldSpec) -> tuple[float, float, float]:
        """(x, y, heading) in the world frame of ``field``."""
        x = (-field.half_length + self.goal_distance) if self.own_goal \
            else (field.half_length - self.goal_distance)
        y = field.half_width - self.y if self.from_touchline else self.y
        return x, y, self.heading


@dataclass(frozen=True)
class Scenario:
    """A starting situation and its end conditions.

    Attributes:
        name: the value of the env option ``scenario=``.
        description: one sentence, for tables and error messages.
        field: the field preset used when the caller names no ``field``.
        team_sizes: players on the pitch (left, right); None: a normal match, any team size.
            With a larger ``team_size`` the extra players (the highest uniform numbers) are
            benched: they stand outside the pitch, take no actions and are not agents.
        left, right: start spots of the players on the pitch, uniform number order (None: the
            referee's kick-off formation).
        ball: the ball's spot (None: the centre spot, or at the feet of ``ball_with``).
        ball_with: index into ``left`` of the player who starts with the ball at its feet
            (``BALL_AT_FEET_M`` in front of it, after its jitter), or None.
        play_mode: the play mode the episode starts in (a ``PlayMode`` name).
        end_on: the ``END_CONDITIONS`` that terminate the episode.
        max_duration_s: game time (s) after which the episode is truncated, None for none.
        player_jitter_m, heading_jitter_rad: each player's start pose is moved by a uniform
            draw in +-these (x, y and heading separately).
        ball_jitter_m: the same for a ball placed by ``ball`` (a set play's ball stays on its
            spot: 0).
    """

    name: str
    description: str
    field: str | None
    team_sizes: tuple[int, int] | None = dataclasses.field(metadata=non_negative())
    left: tuple[Spot, ...] | None
    right: tuple[Spot, ...] | None
    ball: Spot | None
    ball_with: int | None = dataclasses.field(metadata=non_negative())
    play_mode: str
    end_on: frozenset[str]
    max_duration_s: float | None = dataclasses.field(metadata=positive())
    player_jitter_m: float = dataclasses.field(default=0.25, metadata=non_negative())
    heading_jitter_rad: float = dataclasses.field(default=0.1, metadata=non_negative())
    ball_jitter_m: float = dataclasses.field(default=0.0, metadata=non_negative())

    def __post_init__(self) -> None:
        check_fields(self, ConfigError)
        unknown = sorted(set(self.end_on) - set(END_CONDITIONS))
        if unknown:
            raise ConfigError(f"scenario {self.name!r}: end_on: unknown condition(s) {unknown}; "
                              f"known are {list(END_CONDITIONS)}")
        if self.play_mode not in PlayMode.__members__:
            raise ConfigError(f"scenario {self.name!r}: play_mode: unknown {self.play_mode!r}")
        if self.team_sizes is not None:
            sizes = (len(self.left or ()), len(self.right or ()))
            if sizes != tuple(self.team_sizes):
                raise ConfigError(f"scenario {self.name!r}: team_sizes {self.team_sizes} but "
                                  f"{sizes} spots given")

    def min_team_size(self) -> int:
        """The smallest env ``team_size`` that holds this scenario's players (0: any)."""
        return 0 if self.team_sizes is None else max(1, *self.team_sizes)


_FACE_LEFT_GOAL = math.pi
_KEEPER = Spot(0.5, 0.0, _FACE_LEFT_GOAL)

SCENARIOS: dict[str, Scenario] = {s.name: s for s in (
    Scenario(
        name="kickoff",
        description="a full match from the kick-off (any team size), as without a scenario",
        field=None, team_sizes=None, left=None, right=None, ball=None, ball_with=None,
        play_mode="BeforeKickOff", end_on=frozenset({"game_over"}), max_duration_s=None),
    Scenario(
        name="empty_goal",
        description="one attacker with the ball 8 m in front of an empty goal (no keeper)",
        field="simspark", team_sizes=(1, 0), left=(Spot(8.0),), right=(), ball=None,
        ball_with=0, play_mode="PlayOn", end_on=frozenset({"goal", "ball_out"}),
        max_duration_s=20.0),
    Scenario(
        name="one_v_goalie",
        description="one attacker with the ball 8 m from goal against the keeper on its line",
        field="simspark", team_sizes=(1, 1), left=(Spot(8.0),), right=(_KEEPER,), ball=None,
        ball_with=0, play_mode="PlayOn",
        end_on=frozenset({"goal", "ball_out", "defender_possession"}), max_duration_s=20.0),
    Scenario(
        name="one_v_one",
        description="one attacker with the ball 12 m from goal against one defender 5 m "
                    "ahead of it (no keeper)",
        field="simspark", team_sizes=(1, 1), left=(Spot(12.0),),
        right=(Spot(7.0, 0.0, _FACE_LEFT_GOAL),), ball=None, ball_with=0, play_mode="PlayOn",
        end_on=frozenset({"goal", "ball_out", "defender_possession"}), max_duration_s=20.0),
    Scenario(
        name="counter_3v2",
        description="a counter-attack: three attackers (the middle one, left_1, with the ball) "
                    "16 m from goal against two defenders 7 m from goal and the keeper",
        field="simspark", team_sizes=(3, 3),
        left=(Spot(16.0, 0.0), Spot(15.0, 5.0), Spot(15.0, -5.0)),
        right=(_KEEPER, Spot(7.0, 2.0, _FACE_LEFT_GOAL), Spot(7.0, -2.0, _FACE_LEFT_GOAL)),
        ball=None, ball_with=0, play_mode="PlayOn",
        end_on=frozenset({"goal", "ball_out", "defender_possession"}), max_duration_s=30.0),
    Scenario(
        name="keep_away",
        description="keep-away: one player with the ball on the centre spot keeps it from an "
                    "opponent who starts 4 m behind it and chases the ball, for 20 s",
        field="simspark", team_sizes=(1, 1), left=(Spot(15.0),),
        right=(Spot(19.0, 0.0, 0.0),), ball=None, ball_with=0, play_mode="PlayOn",
        end_on=frozenset({"goal", "ball_out", "defender_possession"}), max_duration_s=20.0),
    Scenario(
        name="corner_kick",
        description="a corner kick for the left team from the +y corner of the goal it "
                    "attacks: keeper, taker (left_2) and three attackers in front of goal "
                    "against the keeper and four defenders",
        field="simspark", team_sizes=(5, 5),
        left=(Spot(0.5, 0.0, own_goal=True), Spot(0.6, 0.3, 0.46, from_touchline=True),
              Spot(3.0, 1.0, math.pi / 2), Spot(2.0, -1.0, math.pi / 2),
              Spot(5.0, 0.0, math.pi / 2)),
        right=(_KEEPER, Spot(1.5, 0.8, _FACE_LEFT_GOAL), Spot(2.5, -0.5, _FACE_LEFT_GOAL),
               Spot(4.0, 1.5, _FACE_LEFT_GOAL), Spot(3.5, -2.0, _FACE_LEFT_GOAL)),
        ball=Spot(0.0, 0.0, from_touchline=True), ball_with=None,
        play_mode="CornerKick_Left",
        end_on=frozenset({"goal", "ball_out", "defender_possession"}), max_duration_s=20.0),
)}


def scenario_names() -> list[str]:
    """The names ``scenario=`` accepts, in registry order."""
    return list(SCENARIOS)


def get_scenario(name: str | Scenario) -> Scenario:
    """The scenario called ``name`` (a ``Scenario`` is returned as it is)."""
    if isinstance(name, Scenario):
        return name
    try:
        return SCENARIOS[name]
    except (KeyError, TypeError):
        raise ConfigError(f"scenario: unknown scenario {name!r}; choose one of "
                          f"{scenario_names()}") from None


def benched_indices(scenario: Scenario, team_size: int) -> list[int]:
    """Player indices (left 0..N-1, right N..2N-1) that a scenario leaves off the pitch."""
    if scenario.team_sizes is None:
        return []
    left, right = scenario.team_sizes
    return [*range(left, team_size), *range(team_size + right, 2 * team_size)]


def bench_pose(field: FieldSpec, team: int, k: int) -> tuple[float, float, float]:
    """Where benched player ``k`` (0-based uniform number) of ``team`` stands: beside the -y
    touchline, in its own half, 1 m apart."""
    sign = -1.0 if team == 0 else 1.0
    return sign * (field.half_length - 1.0 - k), -(field.half_width + 0.75), 0.0


class ScenarioRun:
    """A scenario bound to one env's field and team size: places the start and judges the end."""

    def __init__(self, scenario: Scenario, field: FieldSpec, team_size: int) -> None:
        need = scenario.min_team_size()
        if team_size < need:
            raise ConfigError(f"team_size: scenario {scenario.name!r} needs at least {need} "
                              f"players per side, got {team_size}")
        self.scenario = scenario
        self.field = field
        self.team_size = team_size
        self.benched = benched_indices(scenario, team_size)

    def start(self, sim: Simulation, rng: np.random.Generator) -> None:
        """Put players, ball and referee into the scenario's starting situation. ``sim`` has
        just been reset (kick-off formation, BeforeKickOff)."""
        sc, world, ref, n = self.scenario, sim.world, sim.referee, self.team_size
        if sc.team_sizes is None:  # the normal match: the referee's own kick-off
            return
        jitter, turn = sc.player_jitter_m, sc.heading_jitter_rad
        placed: list[tuple[float, float, float]] = []
        for team, spots in ((0, sc.left or ()), (1, sc.right or ())):
            for k, spot in enumerate(spots):
                x, y, h = spot.pose(self.field)
                dx, dy = rng.uniform(-jitter, jitter, 2) if jitter else (0.0, 0.0)
                dh = rng.uniform(-turn, turn) if turn else 0.0
                pose = (x + dx, y + dy, h + dh)
                world.place_player(team * n + k, *pose)
                placed.append(pose)
        for i in self.benched:
            team, k = divmod(i, n)
            world.place_player(i, *bench_pose(self.field, team, k))
        if sc.ball_with is not None:
            x, y, h = placed[sc.ball_with]
            bx, by = x + BALL_AT_FEET_M * math.cos(h), y + BALL_AT_FEET_M * math.sin(h)
        elif sc.ball is not None:
            bx, by, _ = sc.ball.pose(self.field)
            if sc.ball_jitter_m:
                bx, by = np.array([bx, by]) + rng.uniform(-sc.ball_jitter_m, sc.ball_jitter_m, 2)
        else:
            bx, by = 0.0, 0.0
        world.place_ball(float(bx), float(by))
        ref.mode = PlayMode[sc.play_mode]
        ref.mode_cycles = 0
        ref.set_play_spot = (float(bx), float(by))
        # The attacker who starts with the ball has it: a defender's touch takes it away.
        ref.last_touch = sc.ball_with

    def end_reason(self, sim: Simulation, report: CycleReport) -> str | None:
        """After a step: the first met condition of ``END_CONDITIONS`` in ``end_on``, then
        ``TIME_LIMIT`` when ``max_duration_s`` of game time has passed, else None."""
        sc, ref = self.scenario, sim.referee
        end_on = sc.end_on
        kinds = [event.kind for event in report.referee]
        if "goal" in end_on and "goal" in kinds:
            return "goal"
        if "ball_out" in end_on and ref.mode.kind in ("KickIn", "CornerKick", "GoalKick") and \
                any(e.kind == "play_mode" for e in report.referee):
            return "ball_out"
        if "defender_possession" in end_on and ref.last_touch is not None and \
                ref.last_touch >= self.team_size:
            return "defender_possession"
        if "game_over" in end_on and ref.game_over:
            return "game_over"
        if sc.max_duration_s is not None and \
                sim.cycle * sim.physics.cycle_s >= sc.max_duration_s - 1e-9:
            return TIME_LIMIT
        return None
