"""Play one match between two team plugins and summarise it (score, goals, faults, timing)."""

from __future__ import annotations

import argparse
import json
import signal
import threading
import time
from collections.abc import Iterator, Mapping
from contextlib import contextmanager
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

from teamenv.capabilities import DEFAULT_LOCOMOTION_PROFILE
from teamenv.config import RulesConfig, build_config
from teamenv.env import SIDES, SoccerParallelEnv
from teamenv.errors import TeamFault
from teamenv.match_envs import MatchEnvs, env_key
from teamenv.replay import ReplayRecorder
from teamenv.teams import team_version

FORFEIT_SCORE = 3  # goals awarded to the opponent of a team that forfeits


@dataclass(frozen=True)
class MatchOptions:
    """How a match is played (field preset, team size, half length in seconds, ...).

    ``observation_mode`` is "state" or "vision"; ``vision`` names the vision profile
    ("simspark" or "mj"; None = "simspark") and is given only in vision mode;
    ``double_touch``: the league's double-touch rule (``RulesConfig.double_touch``).
    """

    field: str = "simspark"
    team_size: int | None = None
    half_time_s: float = 300.0
    halves: int = 2
    observation_mode: str = "state"
    channel: str = "simspark"
    locomotion_profile: str = DEFAULT_LOCOMOTION_PROFILE
    vision: str | None = None
    double_touch: bool = False

    @staticmethod
    def add_arguments(parser: argparse.ArgumentParser) -> None:
        """The command-line flags of these options, for every command that plays matches (the
        defaults are this class's, the names listed come from the presets and profile
        registries)."""
        import comms
        import locomotion
        from teamenv.config import VISION_PROFILES
        from teamenv.field import FIELD_PRESETS

        d = MatchOptions()
        parser.add_argument("--field", default=d.field,
                            help=f"field preset: {' | '.join(FIELD_PRESETS)} (default {d.field})")
        parser.add_argument("--team-size", type=int, default=d.team_size,
                            help="players per side, 1-11 (default: the field's own)")
        parser.add_argument("--half-time", type=float, default=d.half_time_s,
                            help=f"length of a half in seconds (default {d.half_time_s:g})")
        parser.add_argument("--halves", type=int, default=d.halves,
                            help=f"halves per match: 1 or 2 (default {d.halves})")
        parser.add_argument("--observation", default=d.observation_mode,
                            choices=("state", "vision"),
                            help="observation mode of the teams: true state or the league's "
                                 f"vision (default {d.observation_mode})")
        parser.add_argument("--vision", default=d.vision,
                            help="vision profile with --observation vision: "
                                 f"{' | '.join(VISION_PROFILES.names())} (default simspark)")
        parser.add_argument("--channel", default=d.channel,
                            help=f"say channel: {' | '.join(comms.PROFILES.names())} "
                                 f"(default {d.channel})")
        parser.add_argument("--locomotion-profile", default=d.locomotion_profile,
                            help="how the bodies move: a shipped profile "
                                 f"({' | '.join(locomotion.PROFILES.names())}) or a JSON "
                                 f"path (default {d.locomotion_profile})")
        parser.add_argument("--double-touch", action="store_true",
                            help="the league's double-touch rule: a set play's taker may not "
                                 "touch the ball again before another player has")

    @classmethod
    def from_arguments(cls, args: argparse.Namespace) -> MatchOptions:
        """The options of parsed ``add_arguments`` flags."""
        return cls(field=args.field, team_size=args.team_size, half_time_s=args.half_time,
                   halves=args.halves, observation_mode=args.observation, channel=args.channel,
                   locomotion_profile=args.locomotion_profile, vision=args.vision,
                   double_touch=args.double_touch)

    @classmethod
    def from_dict(cls, values: Mapping[str, Any]) -> MatchOptions:
        return build_config(cls, values, section="match options")

    def env_kwargs(self) -> dict[str, Any]:
        """The ``SoccerParallelEnv`` keyword arguments that play a match with these options
        (field, team size, rules, observation mode, vision, channel, locomotion profile): the
        one translation of options into an env, for matches, tournaments and the optimizer."""
        return dict(field=self.field, team_size=self.team_size,
                    rules=RulesConfig(half_time_s=self.half_time_s, halves=self.halves,
                                      double_touch=self.double_touch),
                    observation_mode=self.observation_mode, vision=self.vision,
                    channel=self.channel, locomotion_profile=self.locomotion_profile)

    def to_dict(self) -> dict[str, Any]:
        """The options as a dict; ``vision`` only when set and ``double_touch`` only when on,
        so the match keys and stored definitions of tournaments made before the options
        existed stay what they were."""
        out = asdict(self)
        if out["vision"] is None:
            del out["vision"]
        if not out["double_touch"]:
            del out["double_touch"]
        return out


@dataclass(frozen=True)
class Goal:
    time_s: float
    side: str  # the side credited with the goal
    scorer_side: str | None  # side of the last player to touch the ball (differs for own goals)
    scorer_unum: int | None


@dataclass(frozen=True)
class Forfeit:
    side: str
    reason: str  # "raised", "invalid_action", "too_slow", "stalled"
    detail: str
    time_s: float


@dataclass(frozen=True)
class MatchResult:
    seed: int
    left: str
    right: str
    score: tuple[int, int]
    goals: tuple[Goal, ...]
    cycles: int
    wall_s: float
    forfeit: Forfeit | None = None
    team_versions: tuple[str, str] = ("unknown", "unknown")
    team_time_s: tuple[float, float] = (0.0, 0.0)
    options: MatchOptions = field(default_factory=MatchOptions)

    @property
    def official_score(self) -> tuple[int, int]:
        """The score that counts: a forfeiting team loses 0-3 (or by its real margin if worse)."""
        if self.forfeit is None:
            return self.score
        left, right = self.score
        if self.forfeit.side == "left":
            return 0, max(FORFEIT_SCORE, right - left)
        return max(FORFEIT_SCORE, left - right), 0

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)

    def summary(self) -> str:
        left, right = self.score
        lines = [f"{self.left} {left} - {right} {self.right}   (seed {self.seed}, "
                 f"{self.cycles} cycles, {self.wall_s:.1f} s wall, "
                 f"{self.cycles / max(self.wall_s, 1e-9):.0f} cycles/s)"]
        for g in self.goals:
            who = f"{g.scorer_side}_{g.scorer_unum}" if g.scorer_unum else "unknown"
            own = " (own goal)" if g.scorer_side and g.scorer_side != g.side else ""
            lines.append(f"  {g.time_s:7.2f} s  goal {g.side}: {who}{own}")
        if self.forfeit:
            lines.append(f"  FORFEIT {self.forfeit.side} at {self.forfeit.time_s:.2f} s: "
                         f"{self.forfeit.reason}: {self.forfeit.detail}")
        return "\n".join(lines)


class _Stalled(BaseException):
    """Raised inside a team's act() by the stall watchdog (BaseException: teams can't eat it)."""


@contextmanager
def _stall_watchdog(seconds: float | None) -> Iterator[None]:
    """Interrupt a cycle that runs longer than ``seconds`` (main thread, POSIX only)."""
    usable = seconds is not None and hasattr(signal, "setitimer") and \
        threading.current_thread() is threading.main_thread()
    if not usable:
        yield
        return

    def _fire(signum: int, frame: Any) -> None:
        raise _Stalled()

    previous = signal.signal(signal.SIGALRM, _fire)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0.0)
        signal.signal(signal.SIGALRM, previous)


def play_match(
    left: str, right: str, seed: int, options: MatchOptions | Mapping[str, Any] | None = None,
    left_config: Mapping[str, Any] | None = None, right_config: Mapping[str, Any] | None = None,
    cycle_time_budget_s: float | None = None, stall_timeout_s: float | None = 10.0,
    replay_path: str | Path | None = None, *, team_versions: tuple[str, str] | None = None,
    replay_extras: bool = False, envs: MatchEnvs | None = None,
) -> MatchResult:
    """Play a whole match; never raises for a team's fault (the team forfeits instead).

    ``cycle_time_budget_s``: a team whose act() takes longer in any cycle forfeits.
    ``stall_timeout_s``: a cycle that has not finished after this long is interrupted and the
    team that was acting forfeits ("stalled"); None disables the watchdog.
    ``replay_path``: write a replay (.npz) of the match there; ``replay_extras``: with each
    agent's belief and roles (from the teams' optional ``annotations()``).
    ``team_versions``: the (left, right) teams' versions when the caller has looked them up
    already (a tournament worker does it once per team); None looks them up (``team_version``).
    ``envs``: where this process keeps envs between matches (``teamenv.match_envs``): the
    match takes the env built for the same teams, configs, options and budget if there is one,
    and gives it back unless a team faulted or stalled; None builds one and closes it after.
    """
    if options is None:
        options = MatchOptions()
    elif not isinstance(options, MatchOptions):
        options = MatchOptions.from_dict(options)
    start = time.perf_counter()
    env_kwargs = options.env_kwargs()

    def build() -> SoccerParallelEnv:
        return SoccerParallelEnv(left=left, right=right, left_config=left_config,
                                 right_config=right_config,
                                 team_cycle_budget_s=cycle_time_budget_s, **env_kwargs)

    if envs is None:
        key, env = "", build()
    else:
        key = env_key(left, right, left_config, right_config, env_kwargs, cycle_time_budget_s)
        env = envs.take(key, build)
    # a kept env's teams have played before: their act() time is counted from here
    time_before = dict(env.team_time_s)
    recorder = ReplayRecorder(env, replay_extras) if replay_path is not None else None
    forfeit: Forfeit | None = None
    goals: list[Goal] = []
    with _stall_watchdog(stall_timeout_s):
        try:
            env.reset(seed=seed)
            if recorder:
                recorder.record()
            while not env.episode_over:
                if stall_timeout_s is not None and hasattr(signal, "setitimer") and \
                        threading.current_thread() is threading.main_thread():
                    signal.setitimer(signal.ITIMER_REAL, stall_timeout_s)
                env.step({})
                for event in env.last_report.referee:
                    if event.kind == "goal":
                        goals.append(_goal(env, event))
                if recorder:
                    recorder.record()
        except TeamFault as fault:
            forfeit = Forfeit(fault.side, fault.reason, fault.detail, env.sim.referee.time_s)
        except _Stalled:
            side = _acting_side(env)
            forfeit = Forfeit(side, "stalled", f"a cycle ran over {stall_timeout_s} s",
                              env.sim.referee.time_s)
    wall = time.perf_counter() - start
    result = MatchResult(
        seed=seed, left=left, right=right, score=tuple(env.sim.referee.score), goals=tuple(goals),
        cycles=env.sim.cycle, wall_s=wall, forfeit=forfeit,
        team_versions=team_versions or (team_version(left), team_version(right)),
        team_time_s=tuple(env.team_time_s.get(side, 0.0) - time_before.get(side, 0.0)
                          for side in SIDES),
        options=options)
    if recorder:
        recorder.save(replay_path, metadata={
            "left": left, "right": right, "seed": seed, "options": options.to_dict(),
            "left_config": dict(left_config or {}), "right_config": dict(right_config or {}),
            "result": json.loads(json.dumps(result.to_dict(), default=str))})
    if envs is not None and forfeit is None:
        envs.give_back(key, env)
    else:
        env.close()
    return result


def _goal(env: SoccerParallelEnv, event: Any) -> Goal:
    scorer_side = scorer_unum = None
    if event.player is not None:
        scorer_side = SIDES[event.player // env.team_size]
        scorer_unum = event.player % env.team_size + 1
    return Goal(event.time_s, SIDES[event.team], scorer_side, scorer_unum)


def _acting_side(env: SoccerParallelEnv) -> str:
    return getattr(env, "acting_side", None) or "left"
