# Over 500 lines because the walker is one controller whose parts are tuned and tested together:
# its parameters, the preview-control gains, the pattern generator with its IK, the measurement
# its feedback reads (``Observer``, also used by the league controller) and the loop that runs
# it; splitting them would scatter one algorithm over several files.
"""A 3D-LIPM walking pattern generator + leg IK + joint PD for the T1 (seed 001 sec. 4.2),
closed by measured feedback (capture-point foot placement, torso attitude at ankles and hips).

``walk_mujoco`` and ``walk_brax`` run it on the T1 through one control loop (``_control_loop``);
only the physics differs."""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace
from typing import Any

import numpy as np

from ..walk import omni_displacement
from ._deps import require
from .t1 import TORSO_STANDING_MIN, T1Model

__all__ = ["WalkParams", "LipmWalker", "Observer", "walk_mujoco", "walk_brax"]

G = 9.81


@dataclass(frozen=True)
class WalkParams:
    """Walking-engine parameters (m, s, rad).

    Pattern: step_period: one step = single support + double support (s); double_support: its
    share (s); lateral: half distance between the feet (m); com_height: z of the 3D-LIPM (seed
    001 eq. 5); lift: swing-foot apex (m); torso_drop: torso lowered from the stance (m);
    torso_lean: forward pitch of the torso (rad); preview: ZMP preview horizon (s); dt: control
    period (s); pd_gain_scale: joint PD gains x this factor while walking (kd x its square root).

    Feedback (from the measured robot): ankle_fb, ankle_fd: torso roll/pitch (rad) and rate
    (rad/s) added to the ankle targets (the gyro stabilisation of seed 001 sec. 4.2); hip_fb,
    hip_fd: the same added to the hip roll/pitch targets; step_fb: the swing foot's landing
    point moves by this x the capture-point error (measured minus planned CoM + CoM velocity /
    omega, relative to the support foot), clipped to step_max (m); cp_filter: time constant (s)
    of the low-pass on that error; cp_pos: weight of the CoM position in that error (1: the
    capture point); cp_bias_tau: if > 0, the error's slow mean (time constant, s) is removed
    first, so a steady offset between the kinematic and the real CoM does not drift the walk;
    tilt_ik: share of the measured torso roll/pitch used as the
    torso attitude in the IK (so the swing foot lands flat and the CoM is kept over its planned
    point on a tilted robot).

    Command: accel_x, accel_y (m/s^2), accel_turn (rad/s^2): the walk command actually planned
    moves towards the commanded one by at most this x step_period per step.
    """

    # defaults: best of a random search in native MuJoCo (benchmarks/locomotion_walker_tune.py,
    # 29 candidates, started from the earlier walker with lift 0.035; score 10.19 of 14)
    step_period: float = 0.3221
    double_support: float = 0.094
    lateral: float = 0.101
    com_height: float = 0.5431
    lift: float = 0.04
    torso_drop: float = 0.0115
    torso_lean: float = 0.0
    preview: float = 1.6
    dt: float = 0.01
    pd_gain_scale: float = 4.5868
    ankle_fb: float = -0.0009
    ankle_fd: float = 0.0903
    hip_fb: float = -0.0095
    hip_fd: float = 0.0445
    step_fb: float = 0.948
    step_max: float = 0.0646
    cp_filter: float = 0.03
    cp_pos: float = 0.1777
    cp_bias_tau: float = 0.0
    tilt_ik: float = 0.0
    accel_x: float = 0.5
    accel_y: float = 0.5
    accel_turn: float = 2.0

    def with_(self, **kw: float) -> WalkParams:
        """A copy with some fields replaced (unknown names raise TypeError)."""
        return replace(self, **kw)

    def as_dict(self) -> dict[str, float]:
        return {f.name: getattr(self, f.name) for f in fields(self)}


def _rz(yaw: float) -> np.ndarray:
    c, s = math.cos(yaw), math.sin(yaw)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _r2(yaw: float) -> np.ndarray:
    c, s = math.cos(yaw), math.sin(yaw)
    return np.array([[c, -s], [s, c]])


def _quat_rpy(roll: float, pitch: float, yaw: float) -> np.ndarray:
    cr, sr = math.cos(roll / 2), math.sin(roll / 2)
    cp, sp = math.cos(pitch / 2), math.sin(pitch / 2)
    cy, sy = math.cos(yaw / 2), math.sin(yaw / 2)
    return np.array(
        [
            cr * cp * cy + sr * sp * sy,
            sr * cp * cy - cr * sp * sy,
            cr * sp * cy + sr * cp * sy,
            cr * cp * sy - sr * sp * cy,
        ]
    )


def preview_gains(zc: float, dt: float, n: int, q: float = 1.0, r: float = 1e-6):
    """Kajita's ZMP preview controller for the cart-table (3D-LIPM) model.

    Returns (A, B, C, Ki, Kx, Gd): u = -Ki * sum(e) - Kx @ x - sum_j Gd[j] * zmp_ref[k + j].
    """
    linalg = require("scipy.linalg")
    A = np.array([[1, dt, dt * dt / 2], [0, 1, dt], [0, 0, 1]])
    B = np.array([[dt**3 / 6], [dt * dt / 2], [dt]])
    C = np.array([[1, 0, -zc / G]])
    A1 = np.block([[np.eye(1), C @ A], [np.zeros((3, 1)), A]])
    B1 = np.vstack([C @ B, B])
    Q1 = np.zeros((4, 4))
    Q1[0, 0] = q
    P = linalg.solve_discrete_are(A1, B1, Q1, np.array([[r]]))
    S = r + (B1.T @ P @ B1)[0, 0]
    K = (B1.T @ P @ A1) / S
    Ki, Kx = K[0, 0], K[0, 1:]
    Ac = A1 - B1 @ K
    I1 = np.array([[1.0], [0.0], [0.0], [0.0]])
    X = -Ac.T @ P @ I1
    Gd = np.zeros(n)
    Gd[0] = -Ki
    for j in range(1, n):
        Gd[j] = ((B1.T @ X) / S)[0, 0]
        X = Ac.T @ X
    return A, B, C, Ki, Kx, Gd


class Observer:
    """What the walker measures on the robot, computed the same way for either engine: the
    generalized state (qpos, qvel) goes into a MuJoCo MjData of the same model and its
    kinematics give the whole-body CoM and its velocity, the feet and the torso attitude."""

    def __init__(self, t1: T1Model) -> None:
        mujoco = require("mujoco")
        self.mj, self.m = mujoco, t1.model
        self.d = mujoco.MjData(t1.model)
        self.feet = {
            s: mujoco.mj_name2id(t1.model, mujoco.mjtObj.mjOBJ_BODY, f"{s.lower()}_foot_link")
            for s in LipmWalker.LEGS
        }

    def __call__(self, qpos: np.ndarray, qvel: np.ndarray) -> dict[str, Any]:
        mj, m, d = self.mj, self.m, self.d
        d.qpos[:] = qpos
        d.qvel[:] = qvel
        mj.mj_kinematics(m, d)
        mj.mj_comPos(m, d)
        mj.mj_comVel(m, d)
        mj.mj_subtreeVel(m, d)
        w, x, y, z = qpos[3:7]
        roll = math.atan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y))
        pitch = math.asin(max(-1.0, min(1.0, 2 * (w * y - z * x))))
        yaw = math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))
        feet = {}
        for s, b in self.feet.items():
            R = d.xmat[b].reshape(3, 3)
            feet[s] = np.array([d.xpos[b][0], d.xpos[b][1], math.atan2(R[1, 0], R[0, 0])])
        return {
            "pose": np.array([qpos[0], qpos[1], yaw]),
            "height": float(qpos[2]),
            "roll": roll,
            "pitch": pitch,
            "wx": float(qvel[3]),
            "wy": float(qvel[4]),
            "com": d.subtree_com[1].copy(),
            "comvel": d.subtree_linvel[1].copy(),
            "feet": feet,
        }


class LipmWalker:
    """Omnidirectional walk (seed 001 sec. 4.2): footsteps from eq. 4 for the current command,
    a ZMP reference at the centre of the support foot (moved linearly between the feet during
    double support), the CoM from Kajita's preview control of the 3D-LIPM, the swing foot
    interpolated between footholds, and both legs from damped-least-squares IK that puts the
    whole-body CoM of the kinematic model on the planned CoM.

    With a measurement (:class:`Observer` output) the walk is closed-loop: the landing point of
    the swing foot moves with the capture-point error, the torso attitude is fed back to ankles
    and hips, and the IK may use the measured torso tilt.
    """

    LEGS = ("Left", "Right")
    LEG_JOINTS = ("Hip_Pitch", "Hip_Roll", "Hip_Yaw", "Knee_Pitch", "Ankle_Pitch", "Ankle_Roll")

    def __init__(self, t1: T1Model, params: WalkParams = WalkParams()) -> None:
        mujoco = require("mujoco")
        self.mj = mujoco
        self.t1, self.p = t1, params
        m = t1.model
        self.m = m
        self.kin = mujoco.MjData(m)
        self.kin.qpos[:] = t1.q_stance
        self.foot_body = {
            s: mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, f"{s.lower()}_foot_link")
            for s in self.LEGS
        }

        def adr(table, s, j):
            return table[mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, f"{s}_{j}")]

        self.leg_q = {
            s: np.array([adr(m.jnt_qposadr, s, j) for j in self.LEG_JOINTS]) for s in self.LEGS
        }
        self.leg_d = {
            s: np.array([adr(m.jnt_dofadr, s, j) for j in self.LEG_JOINTS]) for s in self.LEGS
        }
        self.torso_z = t1.q_stance[2] - params.torso_drop
        mujoco.mj_forward(m, self.kin)
        self.com_off = (self.kin.subtree_com[1] - self.kin.xpos[1])[:2].copy()
        self.foot_zmp = np.array([0.01, 0.0])  # foot box centre in the foot frame
        self.n_prev = int(round(params.preview / params.dt))
        self.A, self.B, self.C, self.Ki, self.Kx, self.Gd = preview_gains(
            params.com_height, params.dt, self.n_prev
        )
        self.omega = math.sqrt(G / params.com_height)
        self.q_ref = t1.q_stance[t1.act_qadr].copy()
        aq = list(t1.act_qadr)
        # per leg: actuator index of hip pitch, hip roll, ankle pitch, ankle roll
        self.fb_idx = {s: [aq.index(self.leg_q[s][k]) for k in (0, 1, 4, 5)] for s in self.LEGS}
        self.reset()

    def reset(self, pose: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> None:
        """Standing at ``pose`` (x, y, yaw); the first step starts after 0.5 s."""
        x, y, yaw = pose
        self.torso = np.array([x, y, yaw])
        R = _r2(yaw)
        self.feet = {
            s: np.array([*(np.array([x, y]) + R @ np.array([0.04, sg * self.p.lateral])), yaw])
            for s, sg in (("Left", 1.0), ("Right", -1.0))
        }
        com = np.array([x, y]) + R @ self.com_off
        self.state = np.array([[com[0], 0, 0], [com[1], 0, 0]], dtype=float)  # per axis c, c', c''
        self.origin = np.array([x, y], dtype=float)  # frame of the preview law (see update)
        # the IK's Jacobians read com-based data (cdof, subtree_com) that only mj_comPos
        # updates, i.e. from the previous solution: move the kinematic model to the new pose
        # first, or a walk reset metres away from it starts from a wrong Jacobian and diverges
        kin = self.kin
        kin.qpos[:] = self.t1.q_stance
        kin.qpos[0:2] = (x, y)
        kin.qpos[3:7] = _quat_rpy(0.0, 0.0, yaw)
        self.mj.mj_kinematics(self.m, kin)
        self.mj.mj_comPos(self.m, kin)
        self.err = np.zeros(2)
        self.swing = "Left"
        self.t_step = -0.5  # stand 0.5 s (ZMP at the centre) before the first step
        self.plan: list = []
        self.adj = np.zeros(2)  # landing adjustment of the current swing foot (walker frame)
        self.cp_err = np.zeros(2)
        self.cp_bias = np.zeros(2)
        self.torso_off = self.com_off.copy()  # CoM - torso origin (xy) of the last IK solution
        self.cmd = np.zeros(3)  # the command being walked (slew-limited)

    def _slew(self, cmd: np.ndarray) -> np.ndarray:
        p = self.p
        lim = np.array([p.accel_x, p.accel_y, p.accel_turn]) * p.step_period
        self.cmd = self.cmd + np.clip(np.asarray(cmd, float) - self.cmd, -lim, lim)
        return self.cmd

    def _zmp_point(self, foot: np.ndarray) -> np.ndarray:
        return foot[:2] + _r2(foot[2]) @ self.foot_zmp

    def _limit_landing(self, land: np.ndarray, support: np.ndarray, sg: float) -> np.ndarray:
        """Keep the landing point at least 1.6 x lateral beside the support foot (no crossing)."""
        Rs = _r2(support[2])
        rel = Rs.T @ (land[:2] - support[:2])
        rel[1] = sg * max(sg * rel[1], 1.6 * self.p.lateral)
        out = land.copy()
        out[:2] = support[:2] + Rs @ rel
        return out

    def _plan(self, cmd: np.ndarray) -> None:
        """Footsteps for the preview horizon under a constant ``cmd`` (eq. 4 per step)."""
        p = self.p
        d = omni_displacement(np.asarray(cmd, float)[None], p.step_period)[0]
        torso = self.torso.copy()
        feet = {k: v.copy() for k, v in self.feet.items()}
        swing = self.swing
        plan = []
        for _ in range(int(math.ceil(p.preview / p.step_period)) + 2):
            support = "Right" if swing == "Left" else "Left"
            nxt = np.array([*(torso[:2] + _r2(torso[2]) @ d[:2]), torso[2] + d[2]])
            sg = 1.0 if swing == "Left" else -1.0
            land = np.array([*(nxt[:2] + _r2(nxt[2]) @ np.array([0.04, sg * p.lateral])), nxt[2]])
            land = self._limit_landing(land, feet[support], sg)
            plan.append((swing, feet[swing].copy(), land, feet[support].copy(), torso.copy(), nxt))
            feet[swing] = land
            torso = nxt
            swing = support
        self.plan = plan

    def _landing(self) -> np.ndarray:
        """Where the current swing foot lands: the plan plus the capture-point adjustment."""
        swing, _, land, sup, _, _ = self.plan[0]
        out = land.copy()
        out[:2] += self.adj
        return self._limit_landing(out, sup, 1.0 if swing == "Left" else -1.0)

    def _zmp_ref(self) -> np.ndarray:
        """(n_prev, 2) ZMP reference from now over the preview horizon (vectorised over the
        points; each point's arithmetic is the point-by-point form's, so the numbers are the
        same: tests/locomotion/test_humanoid_walk.py)."""
        p = self.p
        ss = p.step_period - p.double_support
        land0 = self._landing()
        tau = self.t_step + np.arange(self.n_prev) * p.dt
        out = np.empty((self.n_prev, 2))
        stand = tau < 0
        if stand.any():  # initial stand: centre, then move onto the first support foot
            first_sup = self._zmp_point(self.plan[0][3])
            mid = 0.5 * (self._zmp_point(self.feet["Left"]) + self._zmp_point(self.feet["Right"]))
            a = np.minimum(np.maximum((tau[stand] + p.double_support) / p.double_support, 0.0),
                           1.0)
            out[stand] = mid + a[:, None] * (first_sup - mid)
        walk = ~stand
        if walk.any():
            t = tau[walk]
            k = np.floor_divide(t, p.step_period)
            r = t - k * p.step_period
            k = k.astype(np.int64)
            beyond = k >= len(self.plan)
            k[beyond], r[beyond] = len(self.plan) - 1, ss
            sups = np.array([self._zmp_point(step[3]) for step in self.plan])
            nxts = np.array([self._zmp_point(land0 if i == 0 else step[2])
                             for i, step in enumerate(self.plan)])
            sup, nxt = sups[k], nxts[k]
            frac = ((r - ss) / p.double_support)[:, None]
            out[walk] = np.where((r < ss)[:, None], sup, sup + frac * (nxt - sup))
        return out

    def _feedback_step(self, obs: dict[str, Any]) -> None:
        """Capture-point error relative to the support foot -> landing adjustment."""
        p = self.p
        swing, _, _, sup_p, _, _ = self.plan[0]
        support = "Right" if swing == "Left" else "Left"
        sup_m = obs["feet"][support]
        Rm, Rp = _r2(sup_m[2]), _r2(sup_p[2])
        rel_m = Rm.T @ (obs["com"][:2] - sup_m[:2])
        vel_m = Rm.T @ obs["comvel"][:2]
        rel_p = Rp.T @ (self.state[:, 0] - sup_p[:2])
        vel_p = Rp.T @ self.state[:, 1]
        e = Rp @ (p.cp_pos * (rel_m - rel_p) + (vel_m - vel_p) / self.omega)
        if p.cp_bias_tau > 0:
            self.cp_bias += min(p.dt / p.cp_bias_tau, 1.0) * (e - self.cp_bias)
            e = e - self.cp_bias
        a = min(p.dt / max(p.cp_filter, 1e-9), 1.0)
        self.cp_err += a * (e - self.cp_err)
        ss = p.step_period - p.double_support
        if 0.0 < self.t_step < 0.8 * ss:  # freeze the landing point shortly before touch-down
            self.adj = np.clip(p.step_fb * self.cp_err, -p.step_max, p.step_max)

    def update(self, cmd: np.ndarray, obs: dict[str, Any] | None = None) -> np.ndarray:
        """Advance one control period under command (vx m/s, vy m/s, w rad/s); joint targets.

        ``obs`` (from :class:`Observer`) closes the loop; without it the walk is open-loop.
        """
        p = self.p
        if not self.plan:
            self._plan(self._slew(cmd))
        if self.t_step >= p.step_period - 1e-9:  # step boundary: the swing foot has landed
            swing, _, _, _, _, nxt = self.plan[0]
            self.feet[swing] = self._landing()
            self.torso = nxt
            self.swing = "Right" if swing == "Left" else "Left"
            self.t_step -= p.step_period
            self.adj = np.zeros(2)
            self._plan(self._slew(cmd))
        if obs is not None and p.step_fb != 0.0 and self.t_step > 0.0:
            self._feedback_step(obs)
        zref = self._zmp_ref()
        for ax in range(2):
            # the preview law is not translation-invariant (its truncated preview gains leave a
            # bias of (Kx[0] + sum Gd[1:]) x position), so it runs in the frame of the point
            # where the walk started: a walk begun at (-5, 0) behaves as one begun at (0, 0)
            o = self.origin[ax]
            x = self.state[ax].copy()
            x[0] -= o
            zmp = (self.C @ x)[0]
            self.err[ax] += zmp - (zref[0, ax] - o)
            u = -self.Ki * self.err[ax] - self.Kx @ x - self.Gd[1:] @ (zref[1:, ax] - o)
            self.state[ax] = self.A @ x + self.B[:, 0] * u
            self.state[ax, 0] += o
        self.t_step += p.dt
        com = self.state[:, 0]
        if self.t_step <= 0:
            yaw = self.torso[2]
            targets = {s: (self.feet[s], 0.0) for s in self.LEGS}
            stance = None
        else:
            swing, frm, _, _, t0, t1 = self.plan[0]
            land = self._landing()
            ss = p.step_period - p.double_support
            s = min(self.t_step / ss, 1.0)
            blend = 0.5 - 0.5 * math.cos(math.pi * s)
            sw = frm + blend * (land - frm)
            yaw = t0[2] + min(self.t_step / p.step_period, 1.0) * (t1[2] - t0[2])
            stance = "Right" if swing == "Left" else "Left"
            targets = {
                swing: (sw, p.lift * math.sin(math.pi * s)),
                stance: (self.feet[stance], 0.0),
            }
        roll = pitch = 0.0
        if obs is not None and p.tilt_ik:
            roll, pitch = p.tilt_ik * obs["roll"], p.tilt_ik * obs["pitch"]
        self._ik(com, roll, pitch + p.torso_lean, yaw, targets)
        out = self.q_ref.copy()
        if obs is not None:
            for leg in self.LEGS:
                hp, hr, ap, ar = self.fb_idx[leg]
                out[ap] += p.ankle_fb * obs["pitch"] + p.ankle_fd * obs["wy"]
                out[ar] += p.ankle_fb * obs["roll"] + p.ankle_fd * obs["wx"]
                if stance is None or leg == stance:
                    out[hp] += p.hip_fb * obs["pitch"] + p.hip_fd * obs["wy"]
                    out[hr] += p.hip_fb * obs["roll"] + p.hip_fd * obs["wx"]
        return out

    def _ik(self, com: np.ndarray, roll: float, pitch: float, yaw: float, targets: dict) -> None:
        """Leg joint angles that put the feet on ``targets`` with the whole-body CoM (xy) of the
        kinematic model on ``com`` (torso at height ``torso_z`` with the given attitude)."""
        mj, m, d = self.mj, self.m, self.kin
        d.qpos[2] = self.torso_z
        d.qpos[3:7] = _quat_rpy(roll, pitch, yaw)
        jacp = np.zeros((3, m.nv))
        jacr = np.zeros((3, m.nv))
        for _ in range(3):
            d.qpos[0:2] = com - self.torso_off
            for _ in range(2):
                mj.mj_kinematics(m, d)
                for leg, (foot, lift) in targets.items():
                    b = self.foot_body[leg]
                    goal = np.array([foot[0], foot[1], 0.0301 + lift])
                    e_p = goal - d.xpos[b]
                    R = d.xmat[b].reshape(3, 3)
                    Re = _rz(foot[2]) @ R.T
                    e_r = 0.5 * np.array(
                        [Re[2, 1] - Re[1, 2], Re[0, 2] - Re[2, 0], Re[1, 0] - Re[0, 1]]
                    )
                    mj.mj_jacBody(m, d, jacp, jacr, b)
                    cols = self.leg_d[leg]
                    J = np.vstack([jacp[:, cols], jacr[:, cols]])
                    e = np.concatenate([e_p, e_r])
                    dq = J.T @ np.linalg.solve(J @ J.T + 1e-4 * np.eye(6), e)
                    d.qpos[self.leg_q[leg]] += dq
            mj.mj_kinematics(m, d)
            mj.mj_comPos(m, d)
            self.torso_off = d.subtree_com[1][:2] - d.qpos[0:2]
        for leg in self.LEGS:
            self.q_ref[np.searchsorted(self.t1.act_qadr, self.leg_q[leg])] = d.qpos[self.leg_q[leg]]


def _gains(t1: T1Model, params: WalkParams) -> T1Model:
    g = params.pd_gain_scale
    return replace(t1, kp=t1.kp * g, kd=t1.kd * math.sqrt(g))


def walk_mujoco(
    t1: T1Model,
    command_fn,
    seconds: float,
    params: WalkParams = WalkParams(),
    settle_s: float = 0.3,
    feedback: bool = True,
):
    """Walk the T1 in native MuJoCo; ``command_fn(t, pose) -> (vx, vy, w)`` (body frame), or
    None to stop the run (the manoeuvre is complete).

    Returns (times (k,) s, torso poses (k, 3) x m, y m, yaw rad, fell: bool).
    """
    from .mujoco_sim import settle_mujoco

    t1 = _gains(t1, params)
    data = settle_mujoco(t1, settle_s)
    walker = LipmWalker(t1, params)
    observe = Observer(t1)
    return _control_loop(_MujocoPhysics(t1, data, params, seconds), walker, observe,
                         command_fn, feedback)


def walk_brax(
    t1: T1Model,
    command_fn,
    seconds: float,
    params: WalkParams = WalkParams(),
    settle_s: float = 0.3,
    brax_t1=None,
    feedback: bool = True,
):
    """The same walk as :func:`walk_mujoco`, physics in brax (generalized pipeline).

    The pattern generator, observer and IK run on the host each control period; the physics
    chunk of ``params.dt`` is jitted. Returns (times (k,) s, torso poses (k, 3), fell: bool).
    """
    from .brax_sim import BraxT1

    dt = t1.model.opt.timestep
    every = int(round(params.dt / dt))
    b = brax_t1 or BraxT1(t1, every=every)
    if b.every != every:
        raise ValueError(f"BraxT1.every = {b.every} must equal params.dt / timestep = {every}")
    state = b.settle(settle_s)
    walker = LipmWalker(_gains(t1, params), params)
    observe = Observer(t1)
    return _control_loop(_BraxPhysics(b, state, params, seconds), walker, observe, command_fn,
                         feedback)


def _control_loop(physics, walker: LipmWalker, observe: Observer, command_fn,
                  feedback: bool):
    """The walk's closed loop, the same for either engine: each control period measure the
    robot, stop when it fell or ``command_fn`` ends the run, let the walker plan the joint
    targets and the engine's ``physics`` run them until the next period.

    ``physics``: ``periods`` (how many control periods the run lasts), ``time(k)`` (s, the
    start of period k), ``state()`` (qpos, qvel) and ``advance(q_ref)``."""
    times, poses = [], []
    fell = False
    for k in range(physics.periods):
        t = physics.time(k)
        obs = observe(*physics.state())
        times.append(t)
        poses.append(obs["pose"])
        if obs["height"] < TORSO_STANDING_MIN:
            fell = True
            break
        cmd = command_fn(t, obs["pose"])
        if cmd is None:
            break
        q_ref = walker.update(np.asarray(cmd, float), obs if feedback else None)
        physics.advance(q_ref)
    return np.array(times), np.array(poses), fell


class _MujocoPhysics:
    """Native MuJoCo under joint PD: one control period is ``params.dt / timestep`` physics
    steps; a run of ``seconds`` is that many physics steps, so its last period may be short."""

    def __init__(self, t1: T1Model, data: Any, params: WalkParams, seconds: float) -> None:
        self.mj = require("mujoco")
        from .mujoco_sim import _pd

        self._pd = _pd
        self.t1, self.data = t1, data
        self.dt = t1.model.opt.timestep
        self.every = int(round(params.dt / self.dt))
        self.steps = int(round(seconds / self.dt))
        self.periods = -(-self.steps // self.every)  # the steps that start a period
        self.step_index = 0

    def time(self, k: int) -> float:
        return (k * self.every) * self.dt

    def state(self) -> tuple[np.ndarray, np.ndarray]:
        return self.data.qpos, self.data.qvel

    def advance(self, q_ref: np.ndarray) -> None:
        m = self.t1.model
        for _ in range(min(self.every, self.steps - self.step_index)):
            self._pd(self.t1, self.data, q_ref)
            self.mj.mj_step(m, self.data)
            self.step_index += 1


class _BraxPhysics:
    """brax's generalized pipeline: one jitted call runs a whole control period."""

    def __init__(self, brax_t1: Any, state: Any, params: WalkParams, seconds: float) -> None:
        self.brax_t1, self.brax_state = brax_t1, state
        self.dt = params.dt
        self.gain = params.pd_gain_scale
        self.periods = int(round(seconds / params.dt))

    def time(self, k: int) -> float:
        return k * self.dt

    def state(self) -> tuple[np.ndarray, np.ndarray]:
        return np.asarray(self.brax_state.q), np.asarray(self.brax_state.qd)

    def advance(self, q_ref: np.ndarray) -> None:
        self.brax_state = self.brax_t1.run_to(self.brax_state, q_ref, self.gain)
