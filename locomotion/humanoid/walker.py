"""A 3D-LIPM walking pattern generator + leg IK + joint PD for the T1 (seed 001 sec. 4.2)."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from ..walk import omni_displacement
from ._deps import require
from .t1 import TORSO_STANDING_MIN, T1Model

__all__ = ["WalkParams", "LipmWalker", "walk_mujoco", "walk_brax"]

G = 9.81


@dataclass(frozen=True)
class WalkParams:
    """Walking-engine parameters (m, s).

    step_period: one step = single support + double support (s); double_support: its share
    (s); lateral: half distance between the feet (m); com_height: z of the 3D-LIPM (seed 001
    eq. 5); lift: swing-foot apex (m); torso_drop: torso lowered from the stance (m);
    preview: ZMP preview horizon (s); dt: control period (s); pd_gain_scale: joint PD gains
    x this factor while walking (kd x its square root); ankle_fb, ankle_fd: torso roll/pitch
    (rad) and rate (rad/s) fed back to the ankles (the gyro stabilisation of seed 001 sec. 4.2).
    """

    # defaults: best of a 40-sample random search in native MuJoCo (survival over 6 commands)
    step_period: float = 0.362
    double_support: float = 0.080
    lateral: float = 0.1077
    com_height: float = 0.550
    lift: float = 0.022
    torso_drop: float = 0.0115
    preview: float = 1.6
    dt: float = 0.01
    pd_gain_scale: float = 4.0
    ankle_fb: float = 0.075
    ankle_fd: float = 0.065


def _rz(yaw: float) -> np.ndarray:
    c, s = math.cos(yaw), math.sin(yaw)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


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


class LipmWalker:
    """Omnidirectional walk (seed 001 sec. 4.2): footsteps from eq. 4 for the current command,
    a ZMP reference at the centre of the support foot (moved linearly between the feet during
    double support), the CoM from Kajita's preview control of the 3D-LIPM, the swing foot
    interpolated between footholds, and both legs from damped-least-squares IK with the torso
    carrying the CoM (the CoM is approximated by a fixed point of the torso).
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
        self.leg_q = {
            s: np.array(
                [
                    m.jnt_qposadr[mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, f"{s}_{j}")]
                    for j in self.LEG_JOINTS
                ]
            )
            for s in self.LEGS
        }
        self.leg_d = {
            s: np.array(
                [
                    m.jnt_dofadr[mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, f"{s}_{j}")]
                    for j in self.LEG_JOINTS
                ]
            )
            for s in self.LEGS
        }
        self.torso_z = t1.q_stance[2] - params.torso_drop
        mujoco.mj_forward(m, self.kin)
        self.com_off = (self.kin.subtree_com[1] - self.kin.xpos[1])[:2].copy()
        self.foot_zmp = np.array([0.01, 0.0])  # foot box centre in the foot frame
        self.n_prev = int(round(params.preview / params.dt))
        self.A, self.B, self.C, self.Ki, self.Kx, self.Gd = preview_gains(
            params.com_height, params.dt, self.n_prev
        )
        self.q_ref = t1.q_stance[t1.act_qadr].copy()
        aq = list(t1.act_qadr)
        self.ankle_idx = np.array(
            [[aq.index(self.leg_q[s][4]), aq.index(self.leg_q[s][5])] for s in self.LEGS]
        )
        self.reset()

    def reset(self, pose: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> None:
        """Standing at ``pose`` (x, y, yaw); the first step starts after one double support."""
        x, y, yaw = pose
        self.torso = np.array([x, y, yaw])
        R = _rz(yaw)[:2, :2]
        self.feet = {
            s: np.array([*(np.array([x, y]) + R @ np.array([0.04, sg * self.p.lateral])), yaw])
            for s, sg in (("Left", 1.0), ("Right", -1.0))
        }
        com = np.array([x, y]) + R @ self.com_off
        self.state = np.array([[com[0], 0, 0], [com[1], 0, 0]], dtype=float)  # per axis c, c', c''
        self.err = np.zeros(2)
        self.swing = "Left"
        self.t = 0.0
        self.t_step = -0.5  # stand 0.5 s (ZMP at the centre) before the first step
        self.plan: list = []
        self.swing_from = self.feet["Left"].copy()
        self.swing_to = self.feet["Left"].copy()
        self.yaw_from = self.yaw_to = yaw

    def _zmp_point(self, foot: np.ndarray) -> np.ndarray:
        return foot[:2] + _rz(foot[2])[:2, :2] @ self.foot_zmp

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
            Rt = _rz(torso[2])[:2, :2]
            nxt = np.array([*(torso[:2] + Rt @ d[:2]), torso[2] + d[2]])
            sg = 1.0 if swing == "Left" else -1.0
            land = np.array(
                [*(nxt[:2] + _rz(nxt[2])[:2, :2] @ np.array([0.04, sg * p.lateral])), nxt[2]]
            )
            Rs = _rz(feet[support][2])[:2, :2]
            rel = Rs.T @ (land[:2] - feet[support][:2])
            rel[1] = sg * max(sg * rel[1], 1.6 * p.lateral)  # legs never cross
            land[:2] = feet[support][:2] + Rs @ rel
            plan.append((swing, feet[swing].copy(), land, feet[support].copy(), torso.copy(), nxt))
            feet[swing] = land
            torso = nxt
            swing = support
        self.plan = plan

    def _zmp_ref(self) -> np.ndarray:
        """(n_prev, 2) ZMP reference from now over the preview horizon."""
        p = self.p
        out = np.empty((self.n_prev, 2))
        ss = p.step_period - p.double_support
        for j in range(self.n_prev):
            tau = self.t_step + j * p.dt
            if tau < 0:  # initial stand: centre, then move onto the first support foot
                first_sup = self._zmp_point(self.plan[0][3])
                mid = 0.5 * (
                    self._zmp_point(self.feet["Left"]) + self._zmp_point(self.feet["Right"])
                )
                a = min(max((tau + p.double_support) / p.double_support, 0.0), 1.0)
                out[j] = mid + a * (first_sup - mid)
                continue
            k = int(tau // p.step_period)
            r = tau - k * p.step_period
            if k >= len(self.plan):
                k, r = len(self.plan) - 1, ss
            sup = self._zmp_point(self.plan[k][3])
            if r < ss:
                out[j] = sup
            else:  # double support: towards the foot that just landed
                nxt = self._zmp_point(self.plan[k][2])
                out[j] = sup + (r - ss) / p.double_support * (nxt - sup)
        return out

    def stabilise(
        self, q_ref: np.ndarray, roll: float, pitch: float, wx: float, wy: float
    ) -> np.ndarray:
        """Ankle feedback of the measured torso roll/pitch (rad) and rates (rad/s)."""
        out = q_ref.copy()
        out[self.ankle_idx[:, 0]] += self.p.ankle_fb * pitch + self.p.ankle_fd * wy
        out[self.ankle_idx[:, 1]] += self.p.ankle_fb * roll + self.p.ankle_fd * wx
        return out

    def update(self, cmd: np.ndarray) -> np.ndarray:
        """Advance one control period under command (vx m/s, vy m/s, w rad/s); joint targets."""
        p = self.p
        if not self.plan:
            self._plan(cmd)
        if self.t_step >= p.step_period - 1e-9:  # step boundary: the swing foot has landed
            swing, _, land, _, _, nxt = self.plan[0]
            self.feet[swing] = land
            self.torso = nxt
            self.swing = "Right" if swing == "Left" else "Left"
            self.t_step -= p.step_period
            self._plan(cmd)
        zref = self._zmp_ref()
        for ax in range(2):
            x = self.state[ax]
            zmp = (self.C @ x)[0]
            self.err[ax] += zmp - zref[0, ax]
            u = -self.Ki * self.err[ax] - self.Kx @ x - self.Gd[1:] @ zref[1:, ax]
            self.state[ax] = self.A @ x + self.B[:, 0] * u
        self.t_step += p.dt
        com = self.state[:, 0]
        targets = {}
        if self.t_step <= 0:
            yaw = self.torso[2]
            targets = {s: (self.feet[s], 0.0) for s in self.LEGS}
        else:
            swing, frm, land, _, t0, t1 = self.plan[0]
            ss = p.step_period - p.double_support
            s = min(self.t_step / ss, 1.0)
            blend = 0.5 - 0.5 * math.cos(math.pi * s)
            sw = frm + blend * (land - frm)
            yaw = t0[2] + min(self.t_step / p.step_period, 1.0) * (t1[2] - t0[2])
            other = "Right" if swing == "Left" else "Left"
            targets = {swing: (sw, p.lift * math.sin(math.pi * s)), other: (self.feet[other], 0.0)}
        torso_xy = com - _rz(yaw)[:2, :2] @ self.com_off
        self._ik(np.array([torso_xy[0], torso_xy[1], self.torso_z]), yaw, targets)
        return self.q_ref

    def _ik(self, torso_pos: np.ndarray, yaw: float, targets: dict, iters: int = 3) -> None:
        mj, m, d = self.mj, self.m, self.kin
        d.qpos[0:3] = torso_pos
        d.qpos[3:7] = [math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2)]
        jacp = np.zeros((3, m.nv))
        jacr = np.zeros((3, m.nv))
        for _ in range(iters):
            mj.mj_kinematics(m, d)
            for leg, (foot, lift) in targets.items():
                b = self.foot_body[leg]
                goal = np.array([foot[0], foot[1], 0.0301 + lift])
                e_p = goal - d.xpos[b]
                R = d.xmat[b].reshape(3, 3)
                Rg = _rz(foot[2])
                Re = Rg @ R.T
                e_r = 0.5 * np.array(
                    [Re[2, 1] - Re[1, 2], Re[0, 2] - Re[2, 0], Re[1, 0] - Re[0, 1]]
                )
                mj.mj_jacBody(m, d, jacp, jacr, b)
                cols = self.leg_d[leg]
                J = np.vstack([jacp[:, cols], jacr[:, cols]])
                e = np.concatenate([e_p, e_r])
                dq = J.T @ np.linalg.solve(J @ J.T + 1e-4 * np.eye(6), e)
                d.qpos[self.leg_q[leg]] += dq
        for leg in self.LEGS:
            self.q_ref[np.searchsorted(self.t1.act_qadr, self.leg_q[leg])] = d.qpos[self.leg_q[leg]]


def walk_mujoco(
    t1: T1Model,
    command_fn,
    seconds: float,
    params: WalkParams = WalkParams(),
    settle_s: float = 0.3,
):
    """Walk the T1 in native MuJoCo; ``command_fn(t, pose) -> (vx, vy, w)`` (body frame).

    Returns (times (k,) s, torso poses (k, 3) x m, y m, yaw rad, fell: bool).
    """
    mujoco = require("mujoco")
    from .mujoco_sim import _pd, settle_mujoco

    g = params.pd_gain_scale
    t1 = replace(t1, kp=t1.kp * g, kd=t1.kd * math.sqrt(g))
    m = t1.model
    data = settle_mujoco(t1, settle_s)
    walker = LipmWalker(t1, params)
    q_ref = t1.q_stance[t1.act_qadr]
    dt = m.opt.timestep
    every = int(round(params.dt / dt))
    times, poses = [], []
    fell = False
    for i in range(int(round(seconds / dt))):
        if i % every == 0:
            pose = _torso_pose(data)
            times.append(i * dt)
            poses.append(pose)
            if data.qpos[2] < TORSO_STANDING_MIN:
                fell = True
                break
            roll, pitch = _roll_pitch(data.qpos[3:7])
            q_ref = walker.stabilise(
                walker.update(np.asarray(command_fn(i * dt, pose), float)),
                roll,
                pitch,
                data.qvel[3],
                data.qvel[4],
            )
        _pd(t1, data, q_ref)
        mujoco.mj_step(m, data)
    return np.array(times), np.array(poses), fell


def walk_brax(
    t1: T1Model,
    command_fn,
    seconds: float,
    params: WalkParams = WalkParams(),
    settle_s: float = 0.3,
    brax_t1=None,
):
    """The same walk as :func:`walk_mujoco`, physics in brax (generalized pipeline).

    The pattern generator and IK run on the host each control period; the physics chunk of
    ``params.dt`` is jitted. Returns (times (k,) s, torso poses (k, 3), fell: bool).
    """
    from .brax_sim import BraxT1

    dt = t1.model.opt.timestep
    every = int(round(params.dt / dt))
    b = brax_t1 or BraxT1(t1, every=every)
    if b.every != every:
        raise ValueError(f"BraxT1.every = {b.every} must equal params.dt / timestep = {every}")
    state = b.settle(settle_s)
    g = params.pd_gain_scale
    walker = LipmWalker(replace(t1, kp=t1.kp * g, kd=t1.kd * math.sqrt(g)), params)
    times, poses = [], []
    fell = False
    for i in range(int(round(seconds / params.dt))):
        q = np.asarray(state.q)
        qd = np.asarray(state.qd)
        w, x, y, z = q[3:7]
        pose = np.array([q[0], q[1], math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))])
        times.append(i * params.dt)
        poses.append(pose)
        if q[2] < TORSO_STANDING_MIN:
            fell = True
            break
        roll, pitch = _roll_pitch(q[3:7])
        q_ref = walker.stabilise(
            walker.update(np.asarray(command_fn(i * params.dt, pose), float)),
            roll,
            pitch,
            qd[3],
            qd[4],
        )
        state = b.run_to(state, q_ref, g)
    return np.array(times), np.array(poses), fell


def _roll_pitch(quat: np.ndarray) -> tuple[float, float]:
    w, x, y, z = quat
    roll = math.atan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y))
    pitch = math.asin(max(-1.0, min(1.0, 2 * (w * y - z * x))))
    return roll, pitch


def _torso_pose(data) -> np.ndarray:
    w, x, y, z = data.qpos[3:7]
    yaw = math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))
    return np.array([data.qpos[0], data.qpos[1], yaw])
