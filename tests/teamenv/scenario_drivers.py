"""Hand-written controllers that drive a scenario's attacker, for the scenario and reward tests."""

from __future__ import annotations

import math

import numpy as np

from teamenv.observation import team_frame


def _wrap(angle: float) -> float:
    return (angle + math.pi) % (2 * math.pi) - math.pi


def go_and_kick(obs, target: tuple[float, float], reach: float = 0.3) -> dict:
    """Walk to the ball and kick it (full power) towards ``target`` (team frame, metres)."""
    view = team_frame(obs)
    to_ball = view.ball - view.position
    if math.hypot(*to_ball) <= reach:
        aim = math.atan2(target[1] - view.ball[1], target[0] - view.ball[0])
        return {"walk": np.zeros(3, np.float32),
                "kick": np.array([1.0, _wrap(aim - view.heading)], np.float32)}
    turn = _wrap(math.atan2(to_ball[1], to_ball[0]) - view.heading)
    c, s = math.cos(view.heading), math.sin(view.heading)
    ahead, left = c * to_ball[0] + s * to_ball[1], -s * to_ball[0] + c * to_ball[1]
    return {"walk": np.array([math.copysign(1.0, ahead), np.clip(left, -0.4, 0.4),
                              np.clip(2.0 * turn, -1.5, 1.5)], np.float32)}


def play_out(env, seed: int, target: tuple[float, float], agent: str = "left_1",
             max_steps: int = 3000):
    """Reset ``env`` with ``seed`` and let ``agent`` go and kick towards ``target`` (the other
    caller agents idle) until the episode ends. Returns the summed rewards per agent and the
    last step's (terminations, truncations, infos)."""
    obs, _ = env.reset(seed=seed)
    totals: dict[str, float] = dict.fromkeys(env.agents, 0.0)
    last = None
    for _ in range(max_steps):
        actions = {a: {} for a in env.agents}
        actions[agent] = go_and_kick(obs[agent], target)
        obs, rewards, terms, truncs, infos = env.step(actions)
        for a, r in rewards.items():
            totals[a] += r
        last = (terms, truncs, infos)
        if not env.agents:
            return totals, last
    raise AssertionError(f"episode did not end in {max_steps} steps")
