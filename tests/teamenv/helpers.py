"""Test helpers: build an env and put the world into hand-made situations."""

from __future__ import annotations

import hashlib

import numpy as np

import teamenv
from teamenv.sim.playmode import PlayMode


def make_env(team_size: int = 2, **kwargs) -> teamenv.SoccerParallelEnv:
    env = teamenv.parallel_env(team_size=team_size, **kwargs)
    env.reset(seed=0)
    return env


def episode_digest(env, seed: int) -> str:
    """SHA-256 of every cycle's full state of the episode ``env`` plays from ``reset(seed)``
    with no actions from the caller (both sides are teams)."""
    env.reset(seed=seed)
    h = hashlib.sha256()
    while not env.episode_over:
        env.step({})
        h.update(env.state().tobytes())
    return h.hexdigest()


def idle(env) -> dict:
    return {a: {} for a in env.agents}


def step_until(env, predicate, max_steps: int = 2000, actions=None):
    for _ in range(max_steps):
        env.step(actions(env) if actions else idle(env))
        if predicate(env):
            return env
    raise AssertionError("condition not reached")


def play_on(env) -> None:
    """Skip to PlayOn with every player parked far from the ball, near its own goal line."""
    ref = env.sim.referee
    step_until(env, lambda e: e.sim.referee.mode.kind == "KickOff")
    ref.mode = PlayMode.PlayOn
    ref.mode_cycles = 0
    park_players(env)


def park_players(env, x_frac: float = 0.8) -> None:
    f, n = env.field, env.team_size
    for i in range(2 * n):
        team = i // n
        x = -env.sim.referee.attack_sign[team] * f.half_length * x_frac
        y = -f.half_width * 0.8 + (i % n) * 0.6
        env.sim.world.place_player(i, x, y, 0.0)


def roll_ball(env, x, y, vx, vy) -> None:
    env.sim.world.place_ball(x, y, vx, vy)


def mode(env) -> PlayMode:
    return env.sim.referee.mode


def ball_xy(env) -> np.ndarray:
    return env.sim.world.ball_state()[:2]
