"""A match on the league server: start it, join both sides, beam, kick off, play a set length
of game time with the named strategy plugins, record the result in the tournament database,
stop everything.

Each side is a team spec (``chaser``, ``full:communicate=false``, ``pkg.mod:Class``), built
with ``teamenv.teams.make_team`` exactly as the env builds it for ``observation_mode="vision"``,
``vision="mj"``, ``channel="mj"`` on ``mj7v7`` (the ``TeamContext`` says so), reset with the
seed the env would give it, and called once per server cycle with every agent's observation
from ``VisionObservationBuilder`` (the env's Dict layout). Its actions are checked by the env's
own action parser (the same errors) and sent through ``RequestEncoder``: walk through the
chosen walk controller (``WALKERS``: the league's reference walking network by default, or our
LIPM walker), a kick as a walk through the ball, beam (only in BeforeKickOff and after a goal,
as in the env; refused otherwise) and say (``mj`` channel text).
"""

from __future__ import annotations

import base64
import re
import time
from collections import deque
from collections.abc import Callable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from paramkit.checks import check_fields, in_range, one_of, positive
from teamenv.actions import ActionParser
from teamenv.env import team_seeds
from teamenv.errors import ActionError, ConfigError, TeamFault
from teamenv.match import Goal, MatchOptions, MatchResult
from teamenv.observation_mode import ObservationMode
from teamenv.sim.simulation import Commands
from teamenv.teams import TeamContext, make_team, team_version
from teamenv.teams import team_context as env_team_context
from teamenv.tournament.spec import parse_team_spec

from .adapter import Request, RequestEncoder
from .command_ramp import CommandRamp
from .controller import CYCLE_S, LocomotionController, WalkerController
from .errors import LeagueError
from .observation import SAID_MEMORY_CYCLES, VisionObservationBuilder
from .perception import Perception
from .server import LeagueServer, ServerOptions
from .team_client import TeamClient, join_teams

#: players of the ``ssim`` rules (7 v 7 on fifa7vs7)
MAX_TEAM_SIZE = 7
#: our field preset of the server's ``fifa7vs7``
FIELD = "mj7v7"
#: the body the teams plan with on the server (``TeamContext.body``): ``t1_league``, what the
#: league client's T1 really does there (its walk, kick and get-up measured on the server's
#: physics by ``benchmarks/calibrate_t1_league.py``), so a team asks for the kicks and walks
#: its robots have
LOCOMOTION_PROFILE = "t1_league"


def _ramp(options: LeagueMatchOptions) -> CommandRamp | None:
    """A robot's command ramp: the accelerations of the body the teams plan with."""
    from locomotion import load_profile

    return CommandRamp.from_profile(load_profile(LOCOMOTION_PROFILE)) if options.ramp else None


def _network_walker() -> LocomotionController:
    from .network_walk import NetworkWalkController

    return NetworkWalkController()


#: the walk controllers a league match can give its robots, by name: ``network`` (the league's
#: reference walking network through ``NETWORK_ENVELOPE``: 1.23 m/s forward and 1.9 rad/s
#: turning on LocalServer, never down walking straight, turning or in place in the comparison
#: of docs/league.md, where ours fell in 1 of 10 start poses and in 7 of 10 switching runs) is
#: the default, as the faster one that stays up; ``lipm`` is our LIPM walker
#: (``LEAGUE_ENVELOPE``, 0.55 m/s)
WALKERS: dict[str, Callable[[], LocomotionController]] = {
    "network": _network_walker,
    "lipm": WalkerController,
}
DEFAULT_WALKER = "network"


@dataclass(frozen=True)
class LeagueMatchOptions:
    """team_size: players per side (1-7); game_s: game time to play (s, one half); rules:
    the server's rule book; kick_off: the side that kicks off; server: "real" (rcssservermj,
    a child process, over TCP) or "local" (``LocalServer``: the same simulation, referee and
    protocol code in this process, no sockets; seeded, so the same seed replays a match);
    walker: the robots' walk controller, a name in ``WALKERS``; ramp: walk requests change
    no faster than the ``LOCOMOTION_PROFILE`` body's accelerations
    (``teamenv.league.command_ramp``; off by default: it did not reduce falls, see
    docs/league.md)."""

    team_size: int = field(default=MAX_TEAM_SIZE, metadata=in_range(1, MAX_TEAM_SIZE))
    game_s: float = field(default=30.0, metadata=positive())
    rules: str = "ssim"
    kick_off: str = field(default="Left", metadata=one_of("Left", "Right"))
    server: str = field(default="real", metadata=one_of("real", "local"))
    walker: str = field(default=DEFAULT_WALKER, metadata=one_of(*sorted(WALKERS)))
    ramp: bool = False

    def __post_init__(self) -> None:
        check_fields(self, ConfigError)

    def match_options(self) -> MatchOptions:
        """The env's options for the same match (what the database stores)."""
        return MatchOptions(field=FIELD, team_size=self.team_size, half_time_s=self.game_s,
                            halves=1, observation_mode="vision", channel="mj",
                            locomotion_profile=LOCOMOTION_PROFILE, vision="mj")


def server_team_name(label: str, other: str | None = None) -> str:
    """A name the server accepts (letters, digits, ``_``), distinct from ``other``."""
    name = re.sub(r"[^A-Za-z0-9_]", "_", label)[:16] or "team"
    return name + "_R" if other is not None and name == other else name


#: cycles the teams play in BeforeKickOff before the kick-off (the env's ``before_kickoff_s``)
BEFORE_KICK_OFF_CYCLES = 10


def start_poses(team_size: int) -> list[tuple[float, float, float]]:
    """The env's start poses of one team (team frame: own half, facing +x), by uniform order."""
    from locomotion import load_profile
    from teamenv.config import PhysicsConfig, RulesConfig
    from teamenv.field import field_preset
    from teamenv.sim.referee import Referee

    referee = Referee(field_preset(FIELD), RulesConfig(), team_size, CYCLE_S,
                      float(load_profile(LOCOMOTION_PROFILE).body_radius),
                      PhysicsConfig().ball_radius)
    return [tuple(float(v) for v in pose) for pose in referee.start_positions(0)]


def team_context(side: str, team_size: int) -> TeamContext:
    """What a team is told: the env's context for ``vision`` mode, ``mj`` profile and channel,
    on ``mj7v7`` (the body of the ``t1_league`` profile, the env's ball drag), under the
    server's double-touch rule."""
    from locomotion import load_profile
    from teamenv.config import PhysicsConfig
    from teamenv.field import field_preset

    return env_team_context(side, team_size, field_preset(FIELD),
                            load_profile(LOCOMOTION_PROFILE), PhysicsConfig(), "mj",
                            ObservationMode.build("vision", "mj"), double_touch=True)


@dataclass
class LeagueSide:
    """One side of a league match: its team plugin and what turns perceptions into the
    plugin's observations and its actions into effectors."""

    label: str
    side: str
    server_name: str
    team: Any
    builder: VisionObservationBuilder
    parser: ActionParser
    encoders: dict[int, RequestEncoder] = field(default_factory=dict)
    #: what each agent said in the last ``SAID_MEMORY_CYCLES`` cycles (newest last)
    said: dict[int, deque] = field(default_factory=dict)
    #: each agent's request of the last cycle (the replay recorder reads kicks and says)
    requests: dict[int, Request] = field(default_factory=dict)
    time_s: float = 0.0

    #: one walking-network pass per cycle for this side's robots (``batch_walks``)
    walk_batches: list = field(default_factory=list)

    @property
    def agents(self) -> tuple[str, ...]:
        return self.builder.agents

    def batch_walks(self) -> None:
        """Give this side's walking-network controllers one pass per cycle
        (``teamenv.league.network_batch``: the same bits as one pass per robot): those of the
        same network share a ``WalkBatch``; ``act`` and ``resolved`` fill their messages in."""
        from .network_batch import WalkBatch
        from .network_walk import NetworkWalkController

        batches: dict[int, WalkBatch] = {}
        for encoder in self.encoders.values():
            controller = encoder.controller
            if isinstance(controller, NetworkWalkController) and controller.batch is None:
                net = controller.network
                controller.batch = batches.setdefault(id(net), WalkBatch(net))
        self.walk_batches = list(batches.values())

    def resolved(self, messages: dict[int, str]) -> dict[int, str]:
        """``messages`` with the walk batches' passes run and filled in."""
        for batch in self.walk_batches:
            messages = batch.resolve(messages)
        return messages

    def fault(self, reason: str, detail: str) -> TeamFault:
        return TeamFault(self.side, reason, f"team {self.label!r} (agents "
                         f"{', '.join(self.agents)}): {detail}")

    def act(self, perceptions: dict[int, Perception],
            on_act: Callable[[str, dict, Any], None] | None = None) -> dict[int, str]:
        """This cycle's effector message of every agent: observations -> ``team.act`` ->
        the env's action checks -> effectors."""
        try:
            return self._act(perceptions, on_act)
        except BaseException:
            for batch in self.walk_batches:   # this cycle's pending passes are not sent
                batch.discard()
            raise

    def _act(self, perceptions: dict[int, Perception],
             on_act: Callable[[str, dict, Any], None] | None) -> dict[int, str]:
        observations = self.builder.observe_team(perceptions, self.said)
        game = next(iter(perceptions.values())).game
        start = time.perf_counter()
        try:
            actions = self.team.act(observations)
        except Exception as exc:  # the plugin's bug, named as such
            raise self.fault("raised", f"act() raised at game time {game.time:.2f} s: "
                                       f"{type(exc).__name__}: {exc}") from exc
        self.time_s += time.perf_counter() - start
        if on_act is not None:
            on_act(self.side, observations, actions)
        if not isinstance(actions, Mapping):
            raise self.fault("invalid_action", f"act() returned {type(actions).__name__}, "
                             "expected a dict keyed by agent name")
        extra = [a for a in actions if a not in observations]
        if extra:
            raise self.fault("invalid_action", f"act() returned actions for {extra}, which it "
                             "does not drive")
        given = [a for a in self.agents if a in actions]   # a missing agent idles
        cmd = Commands.idle(len(self.agents))
        rows = [self.agents.index(a) for a in given]
        try:
            self.parser.fill(cmd, rows, given, [actions[a] for a in given], {})
        except ActionError as exc:  # names the agent, field and value
            raise self.fault("invalid_action", str(exc)) from exc
        beam_ok = game.play_mode == "BeforeKickOff" or game.play_mode.startswith("Goal_")
        out = {}
        for unum, p in perceptions.items():
            k = unum - 1
            beam = tuple(float(v) for v in cmd.beam[k]) \
                if cmd.beam_request[k] and beam_ok else None
            kick = (float(cmd.kick_power[k]), float(cmd.kick_dir[k])) \
                if cmd.kick_power[k] > 0 else None
            request = Request(walk=tuple(float(v) for v in cmd.walk[k]), kick=kick, beam=beam,
                              say=cmd.say[k] or None)
            message = self.encoders[unum].encode(request, p)
            self.requests[unum] = request
            if beam is not None:
                self.builder.note_beam(unum)
            out[unum] = message
            self.said.setdefault(unum, deque(maxlen=SAID_MEMORY_CYCLES)).append(cmd.say[k])
        return self.resolved(out)


def make_side(spec: str, side: str, team_size: int, seed: int,
              other: str | None = None) -> LeagueSide:
    """Build the plugin of team spec ``spec`` for ``side`` and reset it with the env's seed
    for match seed ``seed`` (``other``: the other side's server name, kept distinct)."""
    import comms
    from locomotion import load_profile
    from teamenv.field import field_preset
    parsed = parse_team_spec(spec)
    label = parsed.label
    name = server_team_name(label, other)
    team = make_team(parsed.name, team_context(side, team_size), parsed.config_dict)
    profile = load_profile(LOCOMOTION_PROFILE)
    teams = np.repeat([0, 1], team_size)
    parser = ActionParser(field_preset(FIELD), profile.command_low, profile.command_high,
                          comms.make_channel("mj", 2 * team_size, teams), "dict", True)
    out = LeagueSide(label, side, name, team, VisionObservationBuilder(side, team_size, name),
                     parser)
    try:
        team.reset(team_seeds(seed)[0 if side == "left" else 1])
    except Exception as exc:
        raise out.fault("raised", f"reset() raised: {type(exc).__name__}: {exc}") from exc
    return out


def _replay_inputs(sides: Sequence[LeagueSide], n: int) -> tuple[set[int], np.ndarray]:
    """Who was asked to kick and how many bytes each said, this cycle (left team first)."""
    kicking: set[int] = set()
    said = np.zeros(2 * n, np.uint8)
    for k, s in enumerate(sides):
        for unum, request in s.requests.items():
            i = k * n + unum - 1
            if request.kick is not None:
                kicking.add(i)
            if request.say:
                said[i] = len(base64.b64decode(request.say))
    return kicking, said


@contextmanager
def open_league(options: LeagueMatchOptions, names: Sequence[str], log_dir: str | Path | None,
                seed: int) -> Iterator[tuple[list, Callable, Callable[[str], None]]]:
    """A fresh server for one match: (one client per team name, the join function, kick-off).
    ``options.server`` "real": ``rcssservermj`` as a child process, stopped on leaving;
    "local": ``LocalServer``, the server's own simulation in this process (seeded)."""
    n = options.team_size
    if options.server == "local":
        from .local_server import LocalServer

        local = LocalServer(rules=options.rules, seed=seed)
        yield [local.team(name, range(1, n + 1)) for name in names], local.join_teams, \
            local.kick_off
        return
    with LeagueServer(ServerOptions(rules=options.rules), log_dir=log_dir) as server:
        clients = [TeamClient("127.0.0.1", server.agent_port, name, range(1, n + 1),
                              check_alive=server.check_alive) for name in names]
        try:
            yield clients, join_teams, server.monitor.kick_off
        finally:
            for c in clients:
                c.close()


def play_league_match(left: str, right: str, options: LeagueMatchOptions = LeagueMatchOptions(),
                      seed: int = 0, on_cycle: Callable[[float, tuple[int, int]], None] | None = None,
                      log_dir: str | Path | None = None,
                      on_act: Callable[[str, dict, Any], None] | None = None,
                      replay_path: str | Path | None = None) -> MatchResult:
    """Play one match of team specs ``left`` and ``right`` on a fresh server and return its
    result (the server is always stopped, also when a team raises).

    ``on_cycle(game_time_s, score)`` is called every cycle (progress display);
    ``on_act(side, observations, actions)`` after every ``act`` of a team (tests);
    ``replay_path``: record the match there as a teamenv replay (``teamenv.league.replay``;
    needs ``options.server == "local"``, whose simulation the recorder reads)."""
    n = options.team_size
    if replay_path is not None and options.server != "local":
        raise ConfigError("league match: a replay needs server='local' (the recorder reads the "
                          "simulation; the real server's state is not exposed to clients)")
    start = time.monotonic()
    first = make_side(left, "left", n, seed)
    sides = (first, make_side(right, "right", n, seed, first.server_name))
    goals: list[Goal] = []
    cycles = 0
    score = (0, 0)
    with open_league(options, [s.server_name for s in sides], log_dir, seed) as (
            clients, join, kick_off):
        # walkers first: an active agent that does not answer for 5 s is dropped
        for s, c in zip(sides, clients, strict=True):
            s.encoders = {u: RequestEncoder(WALKERS[options.walker](), c.who(u),
                                            ramp=_ramp(options))
                          for u in c.unums}
            s.batch_walks()
        join(clients)
        recorder = None
        if replay_path is not None:
            from .replay import LeagueReplayRecorder

            recorder = LeagueReplayRecorder(clients[0].server, tuple(s.server_name for s in sides),
                                            n, FIELD)
        homes = start_poses(n)
        for s, c in zip(sides, clients, strict=True):   # the env's start poses
            fresh = c.perceive()        # join answered ``last``: read the next one
            c.act(s.resolved({u: s.encoders[u].encode(Request(beam=homes[u - 1]), fresh[u])
                              for u in c.unums}))
            for u in c.unums:
                s.builder.note_beam(u)
        before = 0
        kicked_off = False
        while True:
            percepts = [c.perceive() for c in clients]
            gs = percepts[0][1].game
            new = (gs.score_left, gs.score_right)
            for k, (a, b) in enumerate(zip(score, new, strict=True)):
                goals += [Goal(gs.time, sides[k].side, None, None)] * max(0, b - a)
            score = new
            if on_cycle is not None:
                on_cycle(gs.time, score)
            if kicked_off and gs.time >= options.game_s:
                break
            for s, c, p in zip(sides, clients, percepts, strict=True):
                c.act(s.act(p, on_act))
            if recorder is not None:
                recorder.record(gs, *_replay_inputs(sides, n))
            if kicked_off:
                cycles += 1
            else:
                before += 1
                if before >= BEFORE_KICK_OFF_CYCLES:
                    kick_off(options.kick_off)
                    kicked_off = True
    if recorder is not None:
        recorder.save(replay_path, {"left": first.label, "right": sides[1].label, "seed": seed,
                                    "server": options.server, "walker": options.walker,
                                    "ramp": options.ramp})
    return MatchResult(seed=seed, left=first.label, right=sides[1].label, score=score,
                       goals=tuple(goals), cycles=cycles, wall_s=time.monotonic() - start,
                       team_versions=tuple(team_version(parse_team_spec(s.label).name)
                                           for s in sides),
                       team_time_s=(sides[0].time_s, sides[1].time_s),
                       options=options.match_options())


def check_league_record(db: str | Path, name: str, left: str | None = None,
                        right: str | None = None) -> None:
    """Raise LeagueError when the match cannot be stored: tournament ``name`` in ``db``
    already holds its league match (each league match is the one match of its own
    tournament), or ``left`` and ``right`` are the same team spec (a tournament names each
    team once). Checked before playing."""
    from teamenv.tournament import ResultStore

    if left is not None and right is not None and \
            parse_team_spec(left).label == parse_team_spec(right).label:
        raise LeagueError(f"league match {left} v {right}: a team against itself cannot be "
                          "stored as a tournament (play it without --db)")
    if not Path(db).exists():
        return
    with ResultStore(db) as store:
        found = store.find_tournament(name)
        if found is not None and store.count_matches(found[0]):
            raise LeagueError(f"database {str(db)!r}: tournament {name!r} already holds its "
                              "league match; give each league match its own --name")


def record_league_match(db: str | Path, name: str, result: MatchResult,
                        options: LeagueMatchOptions) -> int:
    """Store ``result`` as the one match of the new tournament ``name`` in ``db``; a LeagueError
    when that tournament already holds a match (nothing is overwritten or dropped)."""
    from teamenv.tournament import ResultStore

    t = round_robin_of(name, result, options)
    with ResultStore(db) as store:
        found = store.find_tournament(name)
        tid = found[0] if found else store.create_tournament(
            t, dict(zip((result.left, result.right), result.team_versions, strict=True)))
        if not store.record_match(tid, t.schedule()[0], result):
            raise LeagueError(f"database {str(db)!r}: tournament {name!r} already holds its "
                              f"league match; {result.left} v {result.right} was not stored "
                              "(give each league match its own --name)")
    return tid


def round_robin_of(name: str, result: MatchResult, options: LeagueMatchOptions):
    """The one-match tournament a league match is stored as."""
    from teamenv.tournament import round_robin

    return round_robin(name, [result.left, result.right], games_per_pairing=1, swap_sides=False,
                       seed=result.seed, options=options.match_options())
