"""Scene builders for the strategy tests of the full team: world models from arrays, and real
envs with bodies placed by hand.

Positions are in the team frame of the left side (it attacks +x, its goal at x = -length/2),
which is also the world frame for the left side before half time.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

import locomotion
import teamenv
from strategy.behaviours.skills import Skills
from strategy.perception.worldmodel import WorldModel
from teamenv.capabilities import body_capabilities
from teamenv.field import FieldSpec, field_preset
from teamenv.sim.playmode import PlayMode

PROFILE = locomotion.load_profile("t1_mj")
BODY = body_capabilities(PROFILE)
LOW = np.asarray(PROFILE.command_low, dtype=np.float64)
HIGH = np.asarray(PROFILE.command_high, dtype=np.float64)
BODY_RADIUS = float(PROFILE.body_radius)


def skills(field: str | FieldSpec = "simspark", **kwargs: Any) -> Skills:
    """The behaviours' body facts for the env's default locomotion profile."""
    return Skills(field_preset(field), BODY, **kwargs)


def world(position: Sequence[float] = (0.0, 0.0), heading: float = 0.0,
          ball: Sequence[float] = (1.0, 0.0), teammates: Sequence[Sequence[float]] = (),
          opponents: Sequence[Sequence[float]] = (), me: int = 0,
          field: str | FieldSpec = "simspark", play_mode: PlayMode = PlayMode.PlayOn,
          ball_velocity: Sequence[float] = (0.0, 0.0), team_size: int | None = None,
          fallen_mates: Sequence[int] = (), time_s: float = 10.0, half: int = 1,
          heard: tuple[str, ...] = ()) -> WorldModel:
    """A hand-built ``WorldModel``: agent ``me`` at ``position``; ``teammates`` are the other
    present teammates (in index order, skipping ``me``); rows beyond them are absent."""
    spec = field_preset(field)
    n_mates = len(teammates) + 1
    n = max(team_size or 0, n_mates, len(opponents), 1)
    mates = np.zeros((n, 2))
    present = np.zeros(n, dtype=bool)
    others = iter(teammates)
    for k in range(n_mates):
        mates[k] = position if k == me else next(others)
        present[k] = True
    mates_fallen = np.zeros(n, dtype=bool)
    for k in fallen_mates:
        mates_fallen[k] = True
    opps = np.zeros((n, 2))
    opps_present = np.zeros(n, dtype=bool)
    for k, p in enumerate(opponents):
        opps[k] = p
        opps_present[k] = True
    return WorldModel(
        me=me, position=np.asarray(position, dtype=np.float64), heading=float(heading),
        velocity=np.zeros(2), fallen=False, ball=np.asarray(ball, dtype=np.float64),
        ball_velocity=np.asarray(ball_velocity, dtype=np.float64), teammates=mates,
        teammates_present=present, teammates_fallen=mates_fallen, opponents=opps,
        opponents_present=opps_present, opponents_fallen=np.zeros(n, dtype=bool),
        play_mode=play_mode, time_s=time_s, half=half, score=(0, 0), heard=heard,
        field=spec)


# -- real envs --------------------------------------------------------------------------------
def make_env(field: str = "simspark", team_size: int = 1, left: str | None = None,
             right: str | None = None, seed: int = 0, **kwargs: Any):
    """A reset ``teamenv`` env (Dict forms, state observations) and its first observations."""
    env = teamenv.parallel_env(field=field, team_size=team_size, left=left, right=right,
                               **kwargs)
    obs, _ = env.reset(seed=seed)
    return env, obs


def place(env, players: dict[int, Sequence[float]] | None = None,
          ball: Sequence[float] | None = None, mode: PlayMode | None = None) -> None:
    """Place bodies (world frame: player index -> (x, y, heading)) and the ball, and set the
    referee's play mode (held for 0 cycles: the referee goes on from there)."""
    world_ = env.sim.world
    for i, pose in (players or {}).items():
        world_.place_player(int(i), float(pose[0]), float(pose[1]), float(pose[2]))
    if ball is not None:
        world_.place_ball(float(ball[0]), float(ball[1]))
    if mode is not None:
        ref = env.sim.referee
        ref.mode = mode
        ref.mode_cycles = 0
        if ball is not None:
            ref.set_play_spot = (float(ball[0]), float(ball[1]))


def idle_actions(env) -> dict[str, dict[str, Any]]:
    return {a: {"walk": np.zeros(3)} for a in env.agents}


def ball_xy(env) -> np.ndarray:
    return env.sim.world.ball_state()[:2].copy()


def poses(env) -> np.ndarray:
    return env.sim.world.player_poses().copy()
