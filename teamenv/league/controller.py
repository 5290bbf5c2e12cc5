"""Pluggable locomotion on the league server: a controller turns a walk command into motor
effectors each cycle, from what the robot measures (joints, torso pose and gyro).

``LocomotionController`` is the interface a team may implement with its own walk (e.g. the
league's reference walking network); ``WalkerController`` is ours: the T1 walker of
``locomotion.humanoid.walker`` (3D-LIPM preview control + leg IK + joint PD, closed by the
measured torso attitude and capture point), its joint targets sent as the server's PD motors.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from locomotion.humanoid.walker import WalkParams

from . import effectors
from .errors import LeagueError
from .perception import Perception
from .t1 import T1_MOTORS, joint_sensor

#: the server's cycle (s): one perception and one answer per 20 ms of game time
CYCLE_S = 0.02

#: the walker's parameters for the league server: CMA-ES on the server's own physics
#: (``benchmarks/league_walker_tune.py --generations 20 --workers 2``, stopped after 8
#: generations of 12 candidates), started from the native-MuJoCo defaults with PD gains x 2.0
#: (the defaults' 4.6 x gains, tuned with PD every 2 ms, make the standing legs chatter at
#: 3-6 rad/s under the server's 5 ms steps). Score of the tuning trials (16 at best): 13.62,
#: the native defaults 11.04 (both stay up; the defaults track worse: forward 0.5 -> 0.43 m/s
#: and a 0.23 rad/s turn, in place a 0.21 rad/s turn)
LEAGUE_WALK = WalkParams(
    step_period=0.3236, double_support=0.0614, lateral=0.0971, com_height=0.5321, lift=0.0517,
    torso_lean=0.0736, pd_gain_scale=2.9369, ankle_fb=0.1808, ankle_fd=0.0378, hip_fb=-0.088,
    hip_fd=0.0511, step_fb=0.9616, step_max=0.0785, cp_pos=0.2724, tilt_ik=0.0)


@dataclass(frozen=True)
class WalkEnvelope:
    """The commands a controller walks safely (m/s, m/s, rad/s): a command outside is scaled
    down along its own direction onto the ellipsoid through these half-axes (forward and
    backward differ), so a team asking for 1.5 m/s gets the fastest safe walk that way."""

    vx_forward: float
    vx_backward: float
    vy: float
    turn: float

    def limit(self, command: tuple[float, float, float]) -> tuple[float, float, float]:
        vx, vy, w = (float(c) for c in command)
        ax = self.vx_forward if vx >= 0 else self.vx_backward
        norm = math.sqrt((vx / ax) ** 2 + (vy / self.vy) ** 2 + (w / self.turn) ** 2)
        if norm <= 1.0:
            return vx, vy, w
        return vx / norm, vy / norm, w / norm


#: LEAGUE_WALK's safe commands on the server's physics, with a margin below the largest ones
#: that stayed up for 8 s (``benchmarks/league_walker_tune.py --envelope``: forward 0.5,
#: backward 0.4, sideways 0.2, turn 1.3; forward 0.6, backward 0.5 and sideways 0.3 fell)
LEAGUE_ENVELOPE = WalkEnvelope(vx_forward=0.45, vx_backward=0.3, vy=0.15, turn=1.0)


class LocomotionController(Protocol):
    """Walk-command -> motor effectors, once per cycle."""

    def reset(self) -> None:
        """Forget the walk (e.g. after a beam)."""

    def stand(self, perception: Perception) -> str:
        """Motor effectors that hold the robot standing still (before kick-off, when idle)."""

    def step(self, command: tuple[float, float, float], perception: Perception) -> str:
        """Motor effectors for this cycle under ``command`` = (vx m/s, vy m/s, turn rad/s),
        body frame."""


def quat_yaw(w: float, qx: float, qy: float, qz: float) -> float:
    """Heading (rad) of a world orientation given as a quaternion."""
    return math.atan2(2 * (w * qz + qx * qy), 1 - 2 * (qy * qy + qz * qz))


def torso_pose(perception: Perception) -> tuple[float, float, float]:
    """World (x, y, yaw) of the torso from the ``pos``/``quat`` perceptors (m, m, rad)."""
    try:
        x, y, _ = perception.positions["torso_pos"]
        quat = perception.orientations["torso_quat"]
    except KeyError as exc:
        raise LeagueError(f"perception has no {exc.args[0]} (needed for the torso pose)") from None
    return x, y, quat_yaw(*quat)


@functools.lru_cache(maxsize=1)
def shared_t1():
    """``locomotion.humanoid.t1.load_t1()`` once per process, its arrays read-only.

    Every ``WalkerController`` (one in each agent's kick motion, shared with the agent's walk
    under ``--walker lipm``: 14 in a 7 v 7) reads the same compiled model and keeps its own
    ``MjData``; compiling the MJCF for each took ~0.15 s of CPU, ~2 s per 7 v 7 match. Nothing
    writes the model: its arrays are made read-only so that a write raises instead of changing
    every walker."""
    from locomotion.humanoid.t1 import load_t1

    t1 = load_t1()
    for array in (t1.q_stance, t1.kp, t1.kd, t1.tau_max, t1.act_qadr, t1.act_dadr):
        array.flags.writeable = False
    return t1


class WalkerController:
    """The project's T1 walker driving the server's motors (needs the ``humanoid`` extra).

    Each cycle the measured state (torso position and orientation, gyro, every joint angle and
    velocity) is put into the walker's observer, the walker advances one 20 ms control period
    (``WalkParams.dt`` is set to the cycle) and every motor gets its PD target with the
    walker's gains (``pd_gain_scale`` x the T1's), so no motor is ever left uncommanded."""

    def __init__(self, params=None, feedback: bool = True,
                 velocity_feedforward: bool = False,
                 envelope: WalkEnvelope | None = LEAGUE_ENVELOPE,
                 stand_s: float | None = None) -> None:
        self.feedback = feedback
        #: how long a started walk stands before its first step (s; None: the walker's 0.5 s)
        self.stand_s = stand_s
        #: commands are limited to this (None: walked as given)
        self.envelope = envelope
        #: send the target's own velocity as the PD's dq (else 0: pure damping)
        self.velocity_feedforward = velocity_feedforward
        from locomotion.humanoid.walker import LipmWalker, Observer, _gains

        params = params or LEAGUE_WALK
        # control periods per server cycle (the walker was tuned at 10 ms)
        self._substeps = max(1, round(CYCLE_S / params.dt))
        import mujoco

        t1 = _gains(shared_t1(), params)
        self._t1, self._params = t1, params
        self._walker = LipmWalker(t1, params)
        self._observe = Observer(t1)
        m = t1.model
        joint_of_motor = {j: mtr for mtr, j in T1_MOTORS.items()}
        self._motors = []
        for i in range(m.nu):
            jname = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_JOINT, int(m.actuator_trnid[i, 0]))
            self._motors.append(joint_of_motor[jname])
        self._sensors = [joint_sensor(mtr) for mtr in self._motors]
        self._last_xyz: np.ndarray | None = None
        self._last_q: np.ndarray | None = None
        self._started = False

    def reset(self) -> None:
        self._started = False
        self._last_xyz = None
        self._last_q = None

    @property
    def gait(self) -> tuple[str, float, float] | None:
        """(swing foot "Left"/"Right", time into its step, step period) s; None before the
        first step (standing, or not started since the last reset)."""
        w = self._walker
        if not self._started or w.t_step <= 0.0:
            return None
        return w.swing, w.t_step, w.p.step_period

    def _state(self, p: Perception) -> tuple[np.ndarray, np.ndarray]:
        t1 = self._t1
        qpos = t1.q_stance.copy()
        qvel = np.zeros(t1.model.nv)
        xyz = np.asarray(p.positions["torso_pos"], dtype=float)
        qpos[0:3] = xyz
        qpos[3:7] = p.orientations["torso_quat"]
        if self._last_xyz is not None:
            qvel[0:3] = (xyz - self._last_xyz) / CYCLE_S
        self._last_xyz = xyz
        gyro = p.gyros.get("torso_gyro")
        if gyro is not None:
            qvel[3:6] = gyro
        for k, sensor in enumerate(self._sensors):
            js = p.joints.get(sensor)
            if js is None:
                raise LeagueError(f"perception has no joint {sensor!r} (T1 expected)")
            qpos[t1.act_qadr[k]] = js.angle
            qvel[t1.act_dadr[k]] = js.velocity
        return qpos, qvel

    def step(self, command: tuple[float, float, float], perception: Perception,
             adjust=None) -> str:
        """``adjust(walker, motors, q_ref) -> q_ref``: a change of this cycle's joint targets
        (motor names in ``motors``' order) before they are sent, e.g. a kick's strike on the
        swing leg (``teamenv.league.kick``)."""
        if self.envelope is not None:
            command = self.envelope.limit(command)
        qpos, qvel = self._state(perception)
        obs = self._observe(qpos, qvel)
        if not self._started:
            self._walker.reset(tuple(obs["pose"]))
            if self.stand_s is not None:
                self._walker.t_step = -self.stand_s
            self._started = True
        for _ in range(self._substeps):
            q_ref = self._walker.update(np.asarray(command, dtype=float),
                                        obs if self.feedback else None)
        if adjust is not None:
            q_ref = adjust(self._walker, self._motors, q_ref)
        dq = np.zeros_like(q_ref)
        if self.velocity_feedforward and self._last_q is not None:
            dq = (q_ref - self._last_q) / CYCLE_S
        self._last_q = q_ref.copy()
        return self._motor_message(q_ref, dq)

    def stand(self, perception: Perception) -> str:
        """The walker's stance (the pose each walk starts from) with the walking gains."""
        self.reset()
        q = self._t1.q_stance[self._t1.act_qadr]
        return self._motor_message(q, np.zeros_like(q))

    def _motor_message(self, q: np.ndarray, dq: np.ndarray) -> str:
        kp, kd = self._t1.kp, self._t1.kd
        return effectors.motors(self._motors, q, dq, kp, kd)
