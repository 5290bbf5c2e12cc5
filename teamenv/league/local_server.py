"""The league server's own simulation run inside this process: a fast, deterministic plant for
tuning and testing locomotion controllers against the server's physics (needs the ``humanoid``
extra).

``LocalServer`` builds rcsssmj's ``SoccerSimulation`` exactly as ``rcssservermj`` does (rule
book ``ssim``, its default field ``fifa7vs7``, the referee), adds players through the same
``add_players`` call, encodes each agent's perceptions with the server's own encoder into the
wire text and parses them with our parser, and parses our effector text with the server's own
action parser. What it leaves out is the network and the threads. What it keeps is the timing
of the server's parallel sync mode (the default, what ``LeagueServer`` runs): each cycle the
server generates the perceptions, then applies the answers to the *previous* perceptions, then
steps 4 x 5 ms; so an answer to the perception of cycle k moves the robot from cycle k+1 to
k+2 — a one-cycle delay every controller on the real server lives with.

**Shortcuts** (``shortcuts=True``, the default): the detours of the wire and of rcsssmj's
per-object Python, about half of a 7 v 7's CPU, are taken the short way, each giving the same
values bit for bit: the perceptions are computed straight from the simulation into ours
(``teamenv.league.local_perceiver``, rcsssmj 0.2.1's arithmetic on whole arrays) instead of
generated as objects, encoded and parsed — or, with another rcsssmj, read from the server's
objects (``teamenv.league.local_perception``); our effector text is read by a quicker reader
for the flat messages our effectors write (``teamenv.league.local_actions``); rcsssmj's motor
command finds each motor's actuators once instead of by name every call
(``teamenv.league.local_motors``). ``shortcuts=False`` runs rcsssmj's own code paths (the
tests compare the two, down to a match's replay).

Tested against the real server (``tests/teamenv/league/test_league_local_server.py``): the same
perceptor kinds, and the same joint trajectory under the same motor commands.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass

import numpy as np

from .errors import LeagueError
from .local_actions import local_action_parser
from .local_motors import CachedMotorCommand
from .local_perceiver import LocalPerceiver, Unhandled, supported
from .local_perception import perception_from_objects, perception_text
from .perception import Perception, parse_perception


@dataclass(frozen=True)
class LocalAgent:
    """The init parameters the simulation reads (rcsssmj's ``PAgentParameter``)."""

    team_name: str
    player_no: int
    model_name: str = "T1"


class LocalServer:
    """rcsssmj's simulation in this process; one ``cycle`` = one server cycle (20 ms).

    ``join(team, unum)`` adds a player (the first team to join plays left); ``cycle(answers)``
    takes every agent's answer to the perceptions returned last time (``(syn)`` if absent),
    applies the answers of the cycle before (the parallel sync mode's delay; ``action_delay=0``
    applies them at once, as the server's ``--sequential`` mode does), steps the world and
    returns each agent's new perception. ``kick_off(side)`` is the monitor's ``(kickOff ...)``.
    ``shortcuts=False`` runs rcsssmj's own perception, action and motor code (the module doc).
    """

    def __init__(self, rules: str = "ssim", field: str | None = None, action_delay: int = 1,
                 seed: int = 0, shortcuts: bool = True) -> None:
        if action_delay not in (0, 1):
            raise LeagueError(f"action_delay must be 0 or 1, not {action_delay!r}")
        from locomotion.humanoid._deps import require

        require("rcsssmj")
        from rcsssmj.games.soccer.server.soccer_action_parser import SoccerActionParser
        from rcsssmj.games.soccer.sim.soccer_referee import SoccerReferee
        from rcsssmj.games.soccer.sim.soccer_sim import SoccerSimulation
        from rcsssmj.games.soccer.soccer_fields import SoccerFieldVersions, create_soccer_field
        from rcsssmj.games.soccer.soccer_rules import SoccerRuleBooks, create_soccer_rule_book
        from rcsssmj.server.perception_encoder import DefaultPerceptionEncoder

        # rcsssmj falls back to a default for an unknown name: check against its own lists
        books = [b.value for b in SoccerRuleBooks if b.value != "unknown"]
        fields = [f.value for f in SoccerFieldVersions if f.value != "unknown"]
        if rules not in books:
            raise LeagueError(f"local server: rules {rules!r} unknown; rcsssmj has {books}")
        if field is not None and field not in fields:
            raise LeagueError(f"local server: field {field!r} unknown; rcsssmj has {fields}")
        book = create_soccer_rule_book(rules)
        pitch = create_soccer_field(field or book.default_field_version.value)
        # rcsssmj draws the say channel's losses from numpy's global generator: it gets its own
        # seeded state here, swapped in around every simulation call (same seed, same match)
        self._np_state = np.random.RandomState(seed).get_state()
        self.sim = SoccerSimulation(field=pitch, rules=book, referee=SoccerReferee())
        if not self.sim.init():
            raise LeagueError("local server: rcsssmj failed to build the world")
        #: the in-process shortcuts (module doc): the same bits as rcsssmj's own paths
        self.shortcuts = bool(shortcuts)
        if self.shortcuts:   # rcsssmj's motor command without its per-call name look-ups
            CachedMotorCommand.install(self.sim)
        #: the perceptions straight from the simulation (rcsssmj 0.2.1 mirrored; else None)
        self._perceiver = LocalPerceiver(self.sim) if self.shortcuts and supported() else None
        # as LeagueServer waits for the first monitor message: a player added before the first
        # simulation step crashes rcsssmj 0.2.1's audio engine
        self._in_own_rng(self.sim.step, [])
        self._parser = local_action_parser() if self.shortcuts else SoccerActionParser()
        self._encoder = DefaultPerceptionEncoder()
        self.action_delay = action_delay
        self._agents: dict[tuple[str, int], object] = {}
        self._pending: dict[tuple[str, int], list] = {}
        self._commands: list = []
        self._answers: dict[tuple[str, int], str] = {}
        self._answered: set[str] = set()
        self.latest: dict[tuple[str, int], Perception] = {}
        self.cycles = 0

    def join(self, team: str, unum: int, model: str = "T1") -> Perception:
        """Add a player; returns its first perception."""
        return self.join_many([(team, unum)], model)[(team, unum)]

    def join_many(self, keys: Iterable[tuple[str, int]], model: str = "T1") -> dict[tuple[str, int], Perception]:
        """Add several players (team, unum) at once, in order; returns their first perceptions.

        One MuJoCo recompile for all of them (rcsssmj's ``add_players`` takes a list), where
        joining one by one recompiles the growing world once per robot: ~1 s of CPU each for
        a 7 v 7. Nothing moves between joins either way (joining does not step the world)."""
        keys = [(str(t), int(u)) for t, u in keys]
        for k, key in enumerate(keys):
            if key in self._agents or key in keys[:k]:
                raise LeagueError(f"local server: {key[0]} {key[1]} has already joined")
        agents = self.sim.add_players([LocalAgent(t, u, model) for t, u in keys])
        for key, agent in zip(keys, agents, strict=True):
            if agent is None:
                raise LeagueError(f"local server: rcsssmj refused {key[0]} {key[1]} ({model}): "
                                  "a third team, a taken number or an unknown model")
            self._agents[key] = agent
        # MuJoCo's recompile leaves the new robots' motor controls uninitialised (any bytes: a
        # huge value MuJoCo zeroes with a warning, or a finite one that drives the joints until
        # the first command arrives): start them at 0, so the same seed plays the same match
        import mujoco

        mj_model = self.sim.mj_model
        prefixes = tuple(agent.agent_id.prefix for agent in agents)
        for i in range(mj_model.nu):
            name = mujoco.mj_id2name(mj_model, mujoco.mjtObj.mjOBJ_ACTUATOR, i) or ""
            if name.startswith(prefixes):
                self.sim.mj_data.ctrl[i] = 0.0
        return self._generate(keys)

    def set_robot_pose(self, team: str, unum: int, position: Iterable[float],
                       quat: Iterable[float] = (1.0, 0.0, 0.0, 0.0),
                       joints: Mapping[str, float] | None = None,
                       velocity: Iterable[float] = (0.0, 0.0, 0.0),
                       angular_velocity: Iterable[float] = (0.0, 0.0, 0.0)) -> None:
        """Put a joined robot's torso at ``position`` (world, m) with orientation ``quat`` (w, x,
        y, z; normalised), its joints at ``joints`` (motor name -> rad; the others 0) and at
        rest, the torso moving with ``velocity`` (m/s, world) and ``angular_velocity`` (rad/s,
        torso frame, as MuJoCo's free joint). The next ``cycle``'s perception shows it. For
        tests and tuning (e.g. a robot that falls): the real server's monitor can only place
        a torso with every joint at 0."""
        import mujoco

        from .t1 import T1_MOTORS

        key = (team, unum)
        agent = self._agents.get(key)
        if agent is None:
            raise LeagueError(f"local server: set_robot_pose: {team} {unum} has not joined")

        def vec(name: str, value: Iterable[float], n: int) -> np.ndarray:
            try:
                v = np.asarray(tuple(value), dtype=float)
            except (TypeError, ValueError):
                raise LeagueError(f"local server: set_robot_pose {name} {value!r} is not "
                                  f"{n} numbers") from None
            if v.shape != (n,) or not np.all(np.isfinite(v)):
                raise LeagueError(f"local server: set_robot_pose {name} {value!r} is not "
                                  f"{n} finite numbers")
            return v

        q = vec("quat", quat, 4)
        if np.linalg.norm(q) < 1e-9:
            raise LeagueError(f"local server: set_robot_pose quat {tuple(quat)!r} has length 0")
        angles = {}
        for motor, angle in (joints or {}).items():
            if motor not in T1_MOTORS:
                raise LeagueError(f"local server: set_robot_pose joint {motor!r} is not a T1 "
                                  f"motor; motors: {list(T1_MOTORS)}")
            angles[T1_MOTORS[motor]] = float(vec(f"joint {motor}", (angle,), 1)[0])
        agent.place_at(tuple(vec("position", position, 3)), tuple(q / np.linalg.norm(q)),
                       vel=tuple(vec("velocity", velocity, 3)),
                       ang_vel=tuple(vec("angular_velocity", angular_velocity, 3)))
        agent.init_joints()
        data = self.sim.mj_data
        for joint, angle in angles.items():
            data.joint(agent.agent_id.prefix + joint).qpos[:] = angle
        # the solver's warm start remembers the robot's past motion: forget it, so that the
        # same pose moves the same way whatever the robot did before
        data.qacc_warmstart[:] = 0.0
        mujoco.mj_forward(self.sim.mj_model, data)

    def _in_own_rng(self, fn, *args):
        outer = np.random.get_state()
        np.random.set_state(self._np_state)
        try:
            return fn(*args)
        finally:
            self._np_state = np.random.get_state()
            np.random.set_state(outer)

    def _generate(self, keys: Iterable[tuple[str, int]]) -> dict[tuple[str, int], Perception]:
        """The perceptions of this cycle (the server's ``generate_perceptions``), of ``keys``.

        With the shortcuts, ``LocalPerceiver`` computes them straight from the simulation;
        where it cannot give the wire's values (``Unhandled``), its draws from the generator
        are undone and the server's own generation runs, read through ``_perceive``."""
        if self._perceiver is not None:
            state = self._np_state
            try:
                by_agent = self._in_own_rng(self._perceiver.perceive)
            except Unhandled:
                self._np_state = state
            else:
                return {key: by_agent[self._agents[key]] for key in keys}
        self._in_own_rng(self.sim.generate_perceptions)
        return {key: self._perceive(key) for key in keys}

    def _perceive(self, key: tuple[str, int]) -> Perception:
        objects = self._agents[key].perceptions
        if self.shortcuts:
            p = perception_from_objects(objects)
            if p is not None:
                return p
        # what the objects cannot give exactly (or asked for): the wire text, parsed
        return parse_perception(perception_text(objects, self._encoder),
                                who=f"agent {key[0]} {key[1]}")

    def kick_off(self, side: str = "Left") -> None:
        from rcsssmj.games.soccer.sim.soccer_commands import KickOffCommand

        sides = {"Left": 0, "Right": 1}
        if side not in sides:
            raise LeagueError(f"local server: kick-off side must be Left or Right, not {side!r}")
        self._commands.append(KickOffCommand(sides[side]))

    def cycle(self, answers: dict[tuple[str, int], str] | None = None) -> dict[tuple[str, int], Perception]:
        answers = answers or {}
        unknown = set(answers) - set(self._agents)
        if unknown:
            raise LeagueError(f"local server: answers for agents that never joined: {sorted(unknown)}")
        parsed = {key: self._parser.parse_action(answers.get(key, "(syn)").encode("ascii"),
                                                 agent.agent_id.prefix)
                  for key, agent in self._agents.items()}
        apply = parsed if self.action_delay == 0 else self._pending
        for key, agent in self._agents.items():
            agent.set_actions(apply.get(key, []))
        self._pending = parsed
        commands, self._commands = self._commands, []
        self._in_own_rng(self.sim.step, commands)
        self.cycles += 1
        self.latest = self._generate(self._agents)
        self._answers = {}
        return dict(self.latest)

    def place_ball(self, x: float, y: float) -> None:
        """Put the ball at rest on the ground at world (x, y) m (a trial's set-up): the next
        ``cycle`` simulates from there (the perceptions of the last cycle still show the old
        place)."""
        x, y = float(x), float(y)
        if not (np.isfinite(x) and np.isfinite(y)):
            raise LeagueError(f"local server: place_ball at ({x!r}, {y!r}) is not a finite point")
        self.sim.ball.drop_at(x, y)

    def ball_position(self) -> tuple[float, float, float]:
        """The ball's world position (m) after the last cycle (ground truth, for trials)."""
        return tuple(float(v) for v in self.sim.ball.xpos)

    # -- the TeamClient interface, for play_league_match ---------------------------------
    def team(self, name: str, unums: Iterable[int]) -> LocalTeam:
        """A ``TeamClient`` look-alike for team ``name``'s agents on this server."""
        return LocalTeam(self, name, tuple(unums))

    def join_teams(self, teams: Iterable[LocalTeam]) -> None:
        """Add every agent (in order: the first team plays left; one recompile for all, see
        ``join_many``), then answer one cycle with ``(syn)``; the next call is each team's
        ``perceive()``."""
        teams = list(teams)
        first = self.join_many([(team.team, u) for team in teams for u in team.unums])
        for team in teams:
            for u in team.unums:
                team.last[u] = first[(team.team, u)]
        self.cycle({})

    def answer(self, team: str, actions: Mapping[int, str]) -> None:
        """One team's answers; the cycle runs once every agent that joined has answered."""
        self._answers.update({(team, u): msg for u, msg in actions.items()})
        self._answered.add(team)
        if self._answered >= {t for t, _ in self._agents}:
            self._answered = set()
            self.cycle(self._answers)


class LocalTeam:
    """One team's agents on a ``LocalServer``, with ``TeamClient``'s calls: ``perceive()``
    returns the perceptions of the last cycle, ``act(actions)`` answers them (``(syn)`` for an
    agent without an action); the server cycles when every team has answered."""

    def __init__(self, server: LocalServer, team: str, unums: tuple[int, ...]) -> None:
        self.server, self.team, self.unums = server, team, unums
        self.last: dict[int, Perception] = {}
        self.cycles = 0

    def who(self, unum: int) -> str:
        return f"agent {self.team}_{unum}"

    def perceive(self) -> dict[int, Perception]:
        self.last = {u: self.server.latest[(self.team, u)] for u in self.unums}
        return dict(self.last)

    def act(self, actions: Mapping[int, str] | None = None) -> None:
        from .team_client import answers

        self.server.answer(self.team, answers(self.team, self.unums, actions))
        self.cycles += 1

    def close(self) -> None:
        """Nothing to close (no sockets)."""
