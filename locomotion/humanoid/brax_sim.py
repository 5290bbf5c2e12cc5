"""Brax (generalized pipeline) rollouts of the T1 under joint PD, the engine the profile is measured in."""

from __future__ import annotations

from typing import Any

import numpy as np

from ._deps import require
from .t1 import T1Model

__all__ = ["BraxT1", "push_rollout_brax"]


class BraxT1:
    """The T1 as a brax system with two jitted functions: ``init`` and a PD-controlled chunk of
    ``every`` physics steps returning the torso height (jax imported lazily).

    Each is compiled once per object (about a minute each on a 2-core CPU); nothing is written
    to a JAX compile cache. Pushes run one after another (vmap over the generalized pipeline
    was slower on this CPU than sequential single-env rollouts).
    """

    def __init__(self, t1: T1Model, every: int = 5) -> None:
        jax = require("jax")
        jnp = require("jax.numpy")
        mjcf = require("brax.io.mjcf")
        pipeline = require("brax.generalized.pipeline")
        self.jax, self.jnp, self.t1, self.every = jax, jnp, t1, int(every)
        self.sys = mjcf.load_model(t1.model)
        self.dt = float(t1.model.opt.timestep)
        sys = self.sys
        kp, kd, tmax = jnp.asarray(t1.kp), jnp.asarray(t1.kd), jnp.asarray(t1.tau_max)
        qa, da = jnp.asarray(t1.act_qadr), jnp.asarray(t1.act_dadr)
        qref = jnp.asarray(t1.q_stance[t1.act_qadr])

        def step(state, _):
            tau = jnp.clip(kp * (qref - state.q[qa]) - kd * state.qd[da], -tmax, tmax)
            return pipeline.step(sys, state, tau), None

        def chunk(state):
            state = jax.lax.scan(step, state, None, length=self.every)[0]
            return state, state.q[2]

        self._chunk = jax.jit(chunk)

        def step_ref(carry, _):
            state, q_ref, gkp, gkd = carry
            tau = jnp.clip(gkp * (q_ref - state.q[qa]) - gkd * state.qd[da], -tmax, tmax)
            return (pipeline.step(sys, state, tau), q_ref, gkp, gkd), None

        def chunk_ref(state, q_ref, gain):
            carry = (state, q_ref, kp * gain, kd * jnp.sqrt(gain))
            return jax.lax.scan(step_ref, carry, None, length=self.every)[0][0]

        self._chunk_ref = jax.jit(chunk_ref)
        self._init = jax.jit(lambda q, qd: pipeline.init(sys, q, qd))

    def run(self, state: Any, seconds: float) -> tuple[Any, np.ndarray]:
        """Advance ``state`` by ``seconds`` under stance PD; torso heights (m) every chunk."""
        n = max(int(round(seconds / (self.dt * self.every))), 1)
        hs = []
        for _ in range(n):
            state, z = self._chunk(state)
            hs.append(z)
        return state, np.asarray(self.jnp.stack(hs))

    def run_to(self, state: Any, q_ref: np.ndarray, gain: float = 1.0) -> Any:
        """Advance one chunk (``every`` physics steps) with joint targets ``q_ref`` (rad) and
        the PD gains scaled by ``gain``."""
        return self._chunk_ref(state, self.jnp.asarray(q_ref), self.jnp.asarray(float(gain)))

    def settle(self, settle_s: float = 0.5) -> Any:
        """Brax state after standing ``settle_s`` seconds in the stance under PD."""
        state = self._init(self.jnp.asarray(self.t1.q_stance), self.jnp.zeros(self.t1.model.nv))
        return self.run(state, settle_s)[0]

    def push_rollout(
        self, pushes: np.ndarray, sim_s: float = 2.0, settle_s: float = 0.5, settled: Any = None
    ) -> tuple[np.ndarray, np.ndarray]:
        """Same experiment as :func:`~locomotion.humanoid.mujoco_sim.push_rollout_mujoco`.

        Returns times (m,) s after the push and torso heights (k, m) m.
        """
        base = settled if settled is not None else self.settle(settle_s)
        heights = []
        for push in np.asarray(pushes, dtype=float):
            qd = base.qd.at[0:2].add(self.jnp.asarray(push))
            state = self._init(base.q, qd)
            heights.append(self.run(state, sim_s)[1])
        times = (np.arange(len(heights[0])) + 1) * self.every * self.dt
        return times, np.array(heights)


def push_rollout_brax(
    t1: T1Model,
    pushes: np.ndarray,
    sim_s: float = 2.0,
    settle_s: float = 0.5,
    record_every: int = 5,
) -> tuple[np.ndarray, np.ndarray]:
    """Functional form of :meth:`BraxT1.push_rollout` (builds and compiles a fresh BraxT1)."""
    return BraxT1(t1, record_every).push_rollout(pushes, sim_s, settle_s)
