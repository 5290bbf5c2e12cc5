"""A match on the league server: start it, join both sides, beam, kick off, play a set length
of game time, record the result in the tournament database, stop everything.

Players are driven by a stand-in league behaviour (``chase_ball``): each walks (our T1 walker)
towards where it last saw the ball and turns on the spot to look for it when it has not seen
it for a second; a kick is the walk through the ball. The team specs name the sides (and the
rows in the database); connecting the registered strategy plugins to the server is not done
yet (see docs/league.md)."""

from __future__ import annotations

import math
import re
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from teamenv.errors import ConfigError
from teamenv.match import Goal, MatchOptions, MatchResult

from . import effectors
from .adapter import LeagueObservation, Request, RequestEncoder, observe
from .controller import WalkerController
from .server import LeagueServer, ServerOptions
from .t1 import T1_MOTORS
from .team_client import TeamClient, join_teams

#: players of the ``ssim`` rules (7 v 7 on fifa7vs7)
MAX_TEAM_SIZE = 7


@dataclass(frozen=True)
class LeagueMatchOptions:
    """team_size: players per side (1-7); game_s: game time to play (s, one half); rules:
    the server's rule book; kick_off: the side that kicks off."""

    team_size: int = MAX_TEAM_SIZE
    game_s: float = 30.0
    rules: str = "ssim"
    kick_off: str = "Left"

    def __post_init__(self) -> None:
        if not 1 <= self.team_size <= MAX_TEAM_SIZE:
            raise ConfigError(f"league match: team_size {self.team_size} is not in 1..{MAX_TEAM_SIZE}")
        if not self.game_s > 0:
            raise ConfigError(f"league match: game_s {self.game_s} must be > 0")
        if self.kick_off not in ("Left", "Right"):
            raise ConfigError(f"league match: kick_off {self.kick_off!r} is not Left or Right")

    def match_options(self) -> MatchOptions:
        """The env's options for the same match (what the database stores)."""
        return MatchOptions(field="mj7v7", team_size=self.team_size, half_time_s=self.game_s,
                            halves=1, channel="mj")


def server_team_name(label: str, other: str | None = None) -> str:
    """A name the server accepts (letters, digits, ``_``), distinct from ``other``."""
    name = re.sub(r"[^A-Za-z0-9_]", "_", label)[:16] or "team"
    return name + "_R" if other is not None and name == other else name


def home_position(unum: int) -> tuple[float, float, float]:
    """Beam pose (x, y, theta) in the team frame: a line in the own half facing the goal."""
    return (-2.0 - 3.0 * ((unum - 1) // 3), 6.0 * (((unum - 1) % 3) - 1), 0.0)


def chase_ball(obs: LeagueObservation, last_seen: dict) -> Request:
    """Walk towards the ball (last seen), or turn to look for it."""
    if obs.ball is not None:
        last_seen["az"], last_seen["t"] = obs.ball.azimuth, obs.time
    if "t" in last_seen and obs.time - last_seen["t"] < 1.0:
        az = last_seen["az"]
        return Request(walk=(0.3 * max(0.0, math.cos(az)), 0.0, max(-0.8, min(0.8, 1.2 * az))))
    return Request(walk=(0.0, 0.0, 0.6))


def play_league_match(left: str, right: str, options: LeagueMatchOptions = LeagueMatchOptions(),
                      seed: int = 0, on_cycle: Callable[[float, tuple[int, int]], None] | None = None,
                      log_dir: str | Path | None = None) -> MatchResult:
    """Play one match on a fresh server and return its result (the server is always stopped).

    ``on_cycle(game_time_s, score)`` is called every cycle (progress display)."""
    names = (server_team_name(left), )
    names = (names[0], server_team_name(right, names[0]))
    n = options.team_size
    start = time.monotonic()
    goals: list[Goal] = []
    cycles = 0
    with LeagueServer(ServerOptions(rules=options.rules), log_dir=log_dir) as server:
        teams = [TeamClient("127.0.0.1", server.agent_port, name, range(1, n + 1),
                            check_alive=server.check_alive) for name in names]
        try:
            sides = ("left", "right")
            # controllers first: an active agent that does not answer for 5 s is dropped
            encoders = [{u: RequestEncoder(WalkerController(), t.who(u)) for u in t.unums}
                        for t in teams]
            join_teams(teams)
            memory = [{u: {} for u in t.unums} for t in teams]
            hold = effectors.message(*(effectors.motor(m, 0.0, 0.0, 50.0, 1.0) for m in T1_MOTORS))
            # beam everyone home (holding every motor), then kick off
            for k, t in enumerate(teams):
                t.act({u: encoders[k][u].encode(Request(beam=home_position(u)), t.last[u]) + hold
                       for u in t.unums})
            for t in teams:
                t.perceive()
            for t in teams:
                t.act({u: hold for u in t.unums})
            server.monitor.kick_off(options.kick_off)
            score = (0, 0)
            game_t = 0.0
            while True:
                percepts = [t.perceive() for t in teams]
                gs = percepts[0][1].game
                game_t = gs.time
                new = (gs.score_left, gs.score_right)
                for s, (a, b) in enumerate(zip(score, new, strict=True)):
                    goals += [Goal(game_t, sides[s], None, None)] * max(0, b - a)
                score = new
                if on_cycle is not None:
                    on_cycle(game_t, score)
                if game_t >= options.game_s:
                    break
                for k, t in enumerate(teams):
                    acts = {}
                    for u, p in percepts[k].items():
                        obs = observe(p, t.team, sides[k])
                        acts[u] = encoders[k][u].encode(chase_ball(obs, memory[k][u]), p)
                    t.act(acts)
                cycles += 1
        finally:
            for t in teams:
                t.close()
    return MatchResult(seed=seed, left=left, right=right, score=score, goals=tuple(goals),
                       cycles=cycles, wall_s=time.monotonic() - start,
                       team_versions=("league-server", "league-server"),
                       options=options.match_options())


def record_league_match(db: str | Path, name: str, result: MatchResult,
                        options: LeagueMatchOptions) -> int:
    """Store ``result`` as the one match of tournament ``name`` (created if new) in ``db``."""
    from teamenv.tournament import ResultStore, round_robin

    t = round_robin(name, [result.left, result.right], games_per_pairing=1, swap_sides=False,
                    seed=result.seed, options=options.match_options())
    with ResultStore(db) as store:
        found = store.find_tournament(name)
        tid = found[0] if found else store.create_tournament(
            t, {spec.label: "league-server" for spec in t.teams})
        store.record_match(tid, t.schedule()[0], result)
    return tid
