"""Team plugins: the protocol a team implements and how a team spec is resolved.

A team drives every agent of one side. Teams are found through the entry-point group
``teamenv.teams`` (the built-in teams register there exactly as a third-party package would)
or named directly as ``package.module:ClassName``. teamenv never imports ``strategy`` by name.
"""

from __future__ import annotations

import importlib
from collections.abc import Mapping
from dataclasses import dataclass, field
from importlib.metadata import entry_points
from typing import Any, Protocol, runtime_checkable

from teamenv.capabilities import BodyCapabilities, body_capabilities, default_body
from teamenv.config import PerceptionConfig, PhysicsConfig
from teamenv.errors import TeamLoadError
from teamenv.field import FieldSpec
from teamenv.observation_mode import STATE_MODE, ObservationMode

ENTRY_POINT_GROUP = "teamenv.teams"
#: The two sides, team 0 first; agent ``{side}_{k}`` is uniform number k of that side.
SIDES = ("left", "right")


@dataclass(frozen=True)
class TeamContext:
    """What a team is told about the match it plays, before the first cycle.

    Attributes:
        side: "left" or "right" (the team's observations are mirrored so it always attacks +x).
        agents: the names of the agents it drives, e.g. ("left_1", ..., "left_11"); index i is
            uniform number i + 1.
        team_size: number of players per side.
        field: the pitch geometry (metres).
        cycle_s: game time per cycle (0.02 s).
        channel: name of the say channel profile ("simspark" or "mj").
        observation_mode: "state" (true state) or "vision".
        seed: the seed of the first episode (each ``reset(seed)`` gives the episode's seed).
        body: what the team's bodies can do (``teamenv.capabilities.BodyCapabilities``: walk
            command range and real speeds, kick reach, kick distance and spread, aim error,
            kick and get-up times), derived from the locomotion profile the env plays; the
            default is the env's default profile. ``walk_low``, ``walk_high`` and
            ``kick_reach`` read it.
        ball_radius: the ball's radius (m).
        ball_linear_drag, ball_rolling_decel: the rolling ball slows by
            ``dv/dt = -ball_linear_drag * v - ball_rolling_decel`` (1/s, m/s²), so a team can
            predict where it stops.
        perception: the camera of ``vision`` mode (``teamenv.PerceptionConfig``: update
            period, cone, noise, camera height...), None in ``state`` mode.
        vision: the vision profile's name ("simspark" or "mj"), None in ``state`` mode.
        landmark_kind: the landmark table the sightings' ``landmarks`` rows follow
            (``teamenv.landmarks.landmarks(field, landmark_kind)``), None in ``state`` mode.
        double_touch: the league's double-touch rule is in force (``RulesConfig.double_touch``,
            always on the league server): a set play's taker may not touch the ball again
            before another player has.
    """

    side: str
    agents: tuple[str, ...]
    team_size: int
    field: FieldSpec
    cycle_s: float
    channel: str
    observation_mode: str
    seed: int
    body: BodyCapabilities = field(default_factory=default_body)
    ball_radius: float = 0.042
    ball_linear_drag: float = 0.4
    ball_rolling_decel: float = 0.3
    perception: PerceptionConfig | None = None
    vision: str | None = None
    landmark_kind: str | None = None
    double_touch: bool = False
    extra: Mapping[str, Any] = field(default_factory=dict)

    @property
    def walk_low(self) -> tuple[float, float, float]:
        """Low bound of the walk command (vx, vy m/s, vturn rad/s) actions must obey."""
        return self.body.walk_low

    @property
    def walk_high(self) -> tuple[float, float, float]:
        """High bound of the walk command (vx, vy m/s, vturn rad/s)."""
        return self.body.walk_high

    @property
    def kick_reach(self) -> float:
        """How close (m, body centre to ball centre) a player must be to kick."""
        return self.body.kick_reach


def team_context(side: str, team_size: int, field: FieldSpec, profile: Any,
                 physics: PhysicsConfig, channel: str,
                 obs_mode: ObservationMode = STATE_MODE,
                 double_touch: bool = False) -> TeamContext:
    """The context the env gives team ``side``: agents ``{side}_1`` ..., the body's
    capabilities of locomotion ``profile`` (``teamenv.capabilities.body_capabilities``), the
    cycle, ball size and drag of ``physics``, what the agents observe (``obs_mode``: in
    ``vision`` mode its profile name, camera and landmark table) and whether the
    double-touch rule is in force."""
    perception = obs_mode.perception
    return TeamContext(side=side, agents=tuple(f"{side}_{k + 1}" for k in range(team_size)),
                       team_size=team_size, field=field, cycle_s=physics.cycle_s,
                       channel=channel, observation_mode=obs_mode.name, seed=0,
                       body=body_capabilities(profile), ball_radius=physics.ball_radius,
                       ball_linear_drag=physics.ball_linear_drag,
                       ball_rolling_decel=physics.ball_rolling_decel,
                       perception=perception, vision=obs_mode.vision,
                       landmark_kind=perception.landmark_kind if obs_mode.is_vision else None,
                       double_touch=double_touch)


@runtime_checkable
class Team(Protocol):
    """A team plugin. Construct as ``TeamClass(context, **config)``.

    ``act`` receives the Dict-form observation of each of its agents (see
    ``teamenv.parallel_env``'s docstring) and returns a Dict-form action per agent. A team must
    decide each agent's action from that agent's observation alone (and what it heard); the
    env does not enforce this, the team's own tests should.
    """

    def reset(self, seed: int) -> None:
        """Called at the start of every episode, before the first ``act``; all of the team's
        randomness must come from ``seed`` (derived from the match seed)."""

    def act(self, observations: Mapping[str, Mapping[str, Any]]) -> dict[str, dict[str, Any]]:
        """Return one action per agent in ``observations``."""


def registered_teams() -> dict[str, str]:
    """Map of registered team names to their ``module:attr`` target."""
    return {ep.name: ep.value for ep in entry_points(group=ENTRY_POINT_GROUP)}


def resolve_team_class(name: str) -> type:
    """Resolve a registered name (``chaser``) or a ``module:Class`` path to a class."""
    if not isinstance(name, str) or not name:
        raise TeamLoadError(f"team: expected a team name or 'module:Class', got {name!r}")
    matches = [ep for ep in entry_points(group=ENTRY_POINT_GROUP) if ep.name == name]
    if matches:
        try:
            return matches[0].load()
        except Exception as exc:  # the plugin's own import failed: say which one
            raise TeamLoadError(f"team {name!r}: loading {matches[0].value} failed: {exc}") from exc
    if ":" not in name:
        raise TeamLoadError(
            f"team: unknown team {name!r}; registered teams are {sorted(registered_teams())}, "
            "or name a class as 'package.module:ClassName'"
        )
    module_name, _, attr = name.partition(":")
    try:
        module = importlib.import_module(module_name)
    except ImportError as exc:
        raise TeamLoadError(f"team {name!r}: cannot import module {module_name!r}: {exc}") from exc
    try:
        obj = module
        for part in attr.split("."):
            obj = getattr(obj, part)
    except AttributeError:
        raise TeamLoadError(f"team {name!r}: module {module_name!r} has no {attr!r}") from None
    if not callable(obj):
        raise TeamLoadError(f"team {name!r}: {attr!r} is not a class or factory")
    return obj


def make_team(name: str, context: TeamContext, config: Mapping[str, Any] | None = None) -> Team:
    """Build the team ``name`` for ``context`` with keyword ``config``; check it is a Team."""
    cls = resolve_team_class(name)
    try:
        team = cls(context, **dict(config or {}))
    except TypeError as exc:
        raise TeamLoadError(f"team {name!r}: bad config {dict(config or {})!r}: {exc}") from exc
    if not (callable(getattr(team, "act", None)) and callable(getattr(team, "reset", None))):
        raise TeamLoadError(f"team {name!r}: {cls!r} has no act()/reset() methods")
    return team


def team_version(name: str) -> str:
    """A version string for a team spec: its distribution's version for a registered team,
    the module's ``__version__`` for ``module:Class``, else "unknown"."""
    for ep in entry_points(group=ENTRY_POINT_GROUP):
        if ep.name == name:
            dist = getattr(ep, "dist", None)
            return f"{dist.name} {dist.version}" if dist is not None else "unknown"
    module_name = name.partition(":")[0]
    try:
        module = importlib.import_module(module_name)
    except ImportError:
        return "unknown"
    return str(getattr(module, "__version__", "unknown"))
