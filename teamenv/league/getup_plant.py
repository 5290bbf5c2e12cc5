"""A fast plant for searching get-up motions: the trial robot's MuJoCo model stepped directly.

``LocalServer.cycle`` spends ~1.8 ms of a 20 ms server cycle on the protocol (encoding the
perceptions as text, parsing them, parsing the motor text) and ~0.2 ms on the physics (4 x 5 ms
MuJoCo steps). ``FastPlant`` keeps the physics and the motor semantics and drops the text:
each cycle it writes every motor's PD command the way rcsssmj's ``ctrl_motor`` does (target
and target velocity into the ``_pos`` / ``_vel`` actuators' controls, the gains into their
``gainprm`` / ``biasprm``; the joint's ``actuatorfrcrange`` clamps the sum) and steps the
world ``n_substeps`` times, with the server's one-cycle delay (a command computed from the
state after cycle k moves the robot from cycle k + 1); the commands carry the motor text's
precision (degrees to 6 significant digits). What it leaves out: the referee, the ball and
the other robots (there are none in a trial) and the perception's rounding of what it reads
(so a trial's torso heights agree with ``getup_trial``'s to the perception's 1 mm; chaotic
moments of a motion can still part ways). A search scores candidates here and checks the
best on ``LocalServer`` (``getup_trial``), which is what the trials measure.

``snapshot()`` / ``restore()`` save and put back the whole simulation state (and the robot's
actuator gains), so one fall, made once on ``LocalServer``, is the start of many candidates.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np

from .getup_trial import TEAM, UNUM
from .t1 import T1_MOTORS


@dataclass(frozen=True)
class Snapshot:
    state: np.ndarray
    gainprm: np.ndarray
    biasprm: np.ndarray


class FastPlant:
    """The trial robot of ``server`` (a ``getup_trial.trial_server()``), stepped without the
    protocol; see the module docstring."""

    def __init__(self, server) -> None:
        import mujoco

        self._mujoco = mujoco
        self.server = server
        self.model, self.data = server.sim.mj_model, server.sim.mj_data
        self.n_substeps = server.sim.n_substeps
        prefix = server._agents[(TEAM, UNUM)].agent_id.prefix
        self.motors = tuple(T1_MOTORS)
        act = self.model.actuator
        self._pos = np.array([act(prefix + m + "_pos").id for m in self.motors])
        self._vel = np.array([act(prefix + m + "_vel").id for m in self.motors])
        self._tau = np.array([act(prefix + m + "_tau").id for m in self.motors])
        self._robot_act = np.concatenate([self._pos, self._vel, self._tau])
        jnt = self.model.joint
        self._qadr = np.array([self.model.jnt_qposadr[jnt(prefix + T1_MOTORS[m]).id]
                               for m in self.motors])
        self._dadr = np.array([self.model.jnt_dofadr[jnt(prefix + T1_MOTORS[m]).id]
                               for m in self.motors])
        self._torso = self.model.site(prefix + "torso").id
        self._torso_body = self.model.body(prefix + "torso").id
        self._feet = [self.model.body(prefix + f"{s}_foot_link").id for s in ("left", "right")]
        self._spec = mujoco.mjtState.mjSTATE_INTEGRATION
        leg_bodies = {self.model.body(prefix + b).id for b in (
            "Hip_Roll_Left", "Shank_Left", "left_foot_link",
            "Hip_Roll_Right", "Shank_Right", "right_foot_link")}
        robot = {b for b in range(self.model.nbody)
                 if (self._mujoco.mj_id2name(self.model, mujoco.mjtObj.mjOBJ_BODY, b)
                     or "").startswith(prefix)}
        self._leg_geoms = {g for g in range(self.model.ngeom)
                           if self.model.geom_bodyid[g] in leg_bodies}
        self._robot_geoms = {g for g in range(self.model.ngeom)
                             if self.model.geom_bodyid[g] in robot}
        self._ground = {g for g in range(self.model.ngeom) if self.model.geom_bodyid[g] == 0}

    def snapshot(self) -> Snapshot:
        size = self._mujoco.mj_stateSize(self.model, self._spec)
        state = np.empty(size)
        self._mujoco.mj_getState(self.model, self.data, state, self._spec)
        return Snapshot(state, self.model.actuator_gainprm[self._robot_act].copy(),
                        self.model.actuator_biasprm[self._robot_act].copy())

    def restore(self, snap: Snapshot) -> None:
        self._mujoco.mj_setState(self.model, self.data, snap.state, self._spec)
        self.model.actuator_gainprm[self._robot_act] = snap.gainprm
        self.model.actuator_biasprm[self._robot_act] = snap.biasprm
        self._mujoco.mj_forward(self.model, self.data)

    def command(self, q: np.ndarray, kp: np.ndarray, kd: np.ndarray,
                dq: np.ndarray | None = None) -> None:
        """Every motor's PD command (arrays in ``self.motors`` order), as ``ctrl_motor``
        does it with the values the motor text carries (``effectors.motor``: degrees and
        gains to 6 significant digits, parsed back by the server)."""
        q, kp, kd = _wire(q, True), _wire(kp, False), _wire(kd, False)
        dq = None if dq is None else _wire(dq, True)
        m, d = self.model, self.data
        d.ctrl[self._tau] = 0.0
        d.ctrl[self._pos] = q
        d.ctrl[self._vel] = 0.0 if dq is None else dq
        m.actuator_gainprm[self._pos, 0] = kp
        m.actuator_biasprm[self._pos, 1] = -kp
        m.actuator_gainprm[self._vel, 0] = kd
        m.actuator_biasprm[self._vel, 2] = -kd

    def step(self) -> None:
        """One server cycle of physics."""
        self._mujoco.mj_step(self.model, self.data, self.n_substeps)

    def joints(self) -> np.ndarray:
        return self.data.qpos[self._qadr].copy()

    def joint_velocities(self) -> np.ndarray:
        return self.data.qvel[self._dadr].copy()

    def torso(self) -> tuple[np.ndarray, np.ndarray]:
        """The torso site's world position and orientation (w, x, y, z), as perceived."""
        pos = self.data.site_xpos[self._torso].copy()
        quat = np.empty(4)
        self._mujoco.mju_mat2Quat(quat, self.data.site_xmat[self._torso])
        return pos, quat

    def com(self) -> np.ndarray:
        """The robot's centre of mass (world)."""
        return self.data.subtree_com[self._torso_body].copy()

    def feet(self) -> list[np.ndarray]:
        return [self.data.xpos[b].copy() for b in self._feet]

    def ground_contacts(self) -> tuple[np.ndarray, bool]:
        """The points (world x, y) where the legs (thighs, calves, feet) touch the ground,
        and whether any other part of the robot (torso, head, arms) touches it."""
        d = self.data
        legs, other = [], False
        for i in range(d.ncon):
            c = d.contact[i]
            g1, g2 = int(c.geom1), int(c.geom2)
            if g2 in self._ground:
                g1, g2 = g2, g1
            if g1 not in self._ground or g2 not in self._robot_geoms:
                continue
            if g2 in self._leg_geoms:
                legs.append(c.pos[:2].copy())
            else:
                other = True
        return np.array(legs).reshape(-1, 2), other

    def run(self, policy: Callable[[int, FastPlant], tuple[np.ndarray, np.ndarray, np.ndarray]],
            cycles: int, watch: Callable[[int, FastPlant], bool | None] | None = None) -> int:
        """``cycles`` server cycles: after cycle k (state seen by ``policy(k, plant)``) the
        command it returns moves the robot from cycle k + 1 on (the server's delay: the first
        cycle runs under the command already in place). ``watch(k, plant)`` after each cycle
        may return True to stop; returns the cycles run."""
        pending = None
        for k in range(cycles):
            if pending is not None:
                self.command(*pending)
            self.step()
            pending = policy(k, self)
            if watch is not None and watch(k, self):
                return k + 1
        return cycles


def _wire(values: np.ndarray, angle: bool) -> np.ndarray:
    """``values`` as they arrive through the motor text (``effectors._fmt``: 6 significant
    digits, angles in degrees, turned back into radians by rcsssmj's action parser)."""
    if angle:
        return np.array([math.radians(float(format(math.degrees(float(v)), ".6g")))
                         for v in values])
    return np.array([float(format(float(v), ".6g")) for v in values])


def motor_arrays(targets: Mapping[str, float], gains: Mapping[str, tuple[float, float]],
                 motors: tuple[str, ...]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(q, kp, kd) arrays in ``motors`` order."""
    return (np.array([targets[m] for m in motors]), np.array([gains[m][0] for m in motors]),
            np.array([gains[m][1] for m in motors]))
