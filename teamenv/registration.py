"""Gymnasium registrations of the single-agent views (``gymnasium.make("teamenv/...")``).

Entry points are strings, so registering imports nothing but Gymnasium (not the env, nor
PettingZoo or pymunk); it runs on ``import teamenv``.
"""

from __future__ import annotations

import gymnasium

#: Just above a full match with the default rules: two 300 s halves at 50 cycles/s plus the
#: two 0.2 s waits before kick-off are 30,020 cycles. With those rules every episode ends by
#: itself first (GameOver, a scenario's end or time limit); the bound is a safety net, and
#: what trainers read as ``spec.max_episode_steps``. Longer ``rules`` need
#: ``gymnasium.make(..., max_episode_steps=...)``.
MAX_EPISODE_STEPS = 30_100

ENVS = {
    "teamenv/Player-v0": "teamenv.single_agent:PlayerEnv",
    "teamenv/Team-v0": "teamenv.single_agent:TeamEnv",
}


def register_envs() -> None:
    """Register the views with Gymnasium (once; a second call changes nothing)."""
    for env_id, entry_point in ENVS.items():
        if env_id not in gymnasium.registry:
            gymnasium.register(id=env_id, entry_point=entry_point,
                               max_episode_steps=MAX_EPISODE_STEPS)
