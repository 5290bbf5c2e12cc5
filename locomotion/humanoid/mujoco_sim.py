"""Native MuJoCo rollouts of the T1 under joint PD (fast reference for the brax measurements)."""

from __future__ import annotations

import numpy as np

from ._deps import require
from .t1 import T1Model

__all__ = ["settle_mujoco", "push_rollout_mujoco"]


def _pd(t1: T1Model, data, q_ref: np.ndarray) -> None:
    q = data.qpos[t1.act_qadr]
    qd = data.qvel[t1.act_dadr]
    data.ctrl[:] = np.clip(t1.kp * (q_ref - q) - t1.kd * qd, -t1.tau_max, t1.tau_max)


def settle_mujoco(t1: T1Model, settle_s: float = 0.5):
    """Stand the T1 in its stance under PD for ``settle_s`` seconds; returns mujoco.MjData."""
    mujoco = require("mujoco")
    data = mujoco.MjData(t1.model)
    data.qpos[:] = t1.q_stance
    q_ref = t1.q_stance[t1.act_qadr]
    for _ in range(int(round(settle_s / t1.model.opt.timestep))):
        _pd(t1, data, q_ref)
        mujoco.mj_step(t1.model, data)
    return data


def push_rollout_mujoco(
    t1: T1Model,
    pushes: np.ndarray,
    sim_s: float = 2.0,
    settle_s: float = 0.5,
    record_every: int = 5,
) -> tuple[np.ndarray, np.ndarray]:
    """Push a settled standing T1 and record the torso height.

    Args:
        t1: the model; pushes: (k, 2) world-frame velocity changes (m/s) added to the root at
            t = 0 (the robot faces +x, so +x is a forward push, +y a push to its left);
        sim_s: simulated time after the push (s); settle_s: standing time before it (s);
        record_every: physics steps between samples.

    Returns:
        times (m,) s after the push, and torso heights (k, m) in m.
    """
    mujoco = require("mujoco")
    base = settle_mujoco(t1, settle_s)
    q_ref = t1.q_stance[t1.act_qadr]
    n_steps = int(round(sim_s / t1.model.opt.timestep))
    heights = []
    for push in np.asarray(pushes, dtype=float):
        data = mujoco.MjData(t1.model)
        data.qpos[:] = base.qpos
        data.qvel[:] = base.qvel
        data.qvel[0:2] += push
        h = []
        for i in range(n_steps):
            _pd(t1, data, q_ref)
            mujoco.mj_step(t1.model, data)
            if (i + 1) % record_every == 0:
                h.append(data.qpos[2])
        heights.append(h)
    times = (np.arange(len(heights[0])) + 1) * record_every * t1.model.opt.timestep
    return times, np.array(heights)
