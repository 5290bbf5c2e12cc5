"""One T1 falling and getting up on the league server, for tuning and testing ``GetUpMotion``.

``getup_trial`` makes the robot fall the way ``fall_setup(side, seed)`` draws it: standing in
the walker's stance with noise, tilted towards its front or back (plus a roll and any
heading), arms in a random posture, limp-ish joints while it falls for a random 1.0-1.8 s;
then it runs the motion until ``done``, and keeps holding the end pose for ``hold_s`` to see
whether it stays up. The plant is ``LocalServer`` (the robot is put in place with
``set_robot_pose``, which the real server cannot do; ``real_fall_trial`` tips it over with
its own motors instead, and runs on either plant).

Reported: whether it was up when the motion was done, the time from the start of the motion
to the first cycle it was up and stayed up until the motion was done (``time_to_up``), and
whether it was down again within ``hold_s`` after.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from . import effectors
from .controller import CYCLE_S
from .getup import END_POSE, GROUPS, GetUpMotion, is_up, lying_on_front
from .observation import is_fallen
from .perception import Perception
from .t1 import T1_MOTORS

TEAM = "GetUp"


@dataclass(frozen=True)
class FallSetup:
    """How a trial's robot falls (world frame, rad, m)."""

    side: str  # "front" or "back": the way it is tipped
    x: float
    y: float
    yaw: float
    tilt: float  # towards ``side`` from upright
    roll: float
    tip_rate: float  # initial angular velocity towards ``side`` (rad/s)
    joints: dict[str, float]  # motor -> angle, the posture it holds while falling
    fall_gain: float  # kp of every motor while falling (kd = kp / 20)
    fall_s: float  # time it falls before the motion starts


def fall_setup(side: str, seed: int) -> FallSetup:
    """A random fall towards ``side`` ("front" or "back"), the same for the same seed."""
    if side not in ("front", "back"):
        raise ValueError(f"fall_setup: side must be 'front' or 'back', not {side!r}")
    rng = np.random.default_rng([seed, 0 if side == "front" else 1])
    pose = dict(END_POSE)
    pose.update(
        shoulder_pitch=float(rng.uniform(-1.2, 0.6)),
        shoulder_roll=float(rng.uniform(-1.5, -0.3)),
        elbow_pitch=float(rng.uniform(-1.2, 1.2)),
        elbow_yaw=float(rng.uniform(-1.2, 0.0)),
        hip_pitch=float(rng.uniform(-0.6, 0.1)),
        knee=float(rng.uniform(0.0, 0.9)),
        ankle_pitch=float(rng.uniform(-0.4, 0.1)),
        waist=float(rng.uniform(-0.3, 0.3)),
    )
    joints = {}
    for group, angle in pose.items():
        motors, sign = GROUPS[group]
        joints[motors[0]] = angle
        if len(motors) == 2:
            # not quite symmetric: falls are not
            joints[motors[1]] = sign * angle + float(rng.normal(0.0, 0.1))
    return FallSetup(
        side=side, x=float(rng.uniform(-12.0, -2.0)), y=float(rng.uniform(-8.0, 8.0)),
        yaw=float(rng.uniform(-math.pi, math.pi)), tilt=float(rng.uniform(0.15, 0.5)),
        roll=float(rng.uniform(-0.25, 0.25)), tip_rate=float(rng.uniform(0.0, 1.5)),
        joints=joints, fall_gain=float(rng.uniform(5.0, 60.0)),
        fall_s=float(rng.uniform(1.0, 1.8)))


def _quat_mul(a, b):
    w1, x1, y1, z1 = a
    w2, x2, y2, z2 = b
    return (w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2, w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
            w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2, w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2)


def _axis_quat(axis, angle):
    s = math.sin(angle / 2)
    return (math.cos(angle / 2), axis[0] * s, axis[1] * s, axis[2] * s)


@dataclass(frozen=True)
class GetUpTrial:
    """``side_detected``: what the motion chose; ``up``: up when it was done; ``time_to_up``
    (s from its start; NaN if never up); ``fell_after``: down again within ``hold_s``;
    ``motion_s``: the motion's duration; ``heights``: torso height per cycle of the motion."""

    setup: FallSetup
    side_detected: str
    lying_on_front: bool
    up: bool
    time_to_up: float
    fell_after: bool
    motion_s: float
    heights: np.ndarray

    @property
    def success(self) -> bool:
        return self.up and not self.fell_after


def run_getup(motion: GetUpMotion, p: Perception, cycle: Callable[[str], Perception],
              hold_s: float, max_s: float = 10.0) -> tuple[bool, float, bool, np.ndarray]:
    """Run ``motion`` from perception ``p``; returns (up at done, time to up, fell in hold,
    torso heights)."""
    motion.start(p)
    heights, up_since = [], None
    t = 0.0
    while not motion.done and t < max_s:
        p = cycle(motion.step(p))
        t += CYCLE_S
        heights.append(p.positions["torso_pos"][2])
        if is_up(p):
            up_since = t if up_since is None else up_since
        else:
            up_since = None
    up = motion.succeeded
    fell_after = False
    for _ in range(round(hold_s / CYCLE_S)):
        p = cycle(motion.step(p))
        heights.append(p.positions["torso_pos"][2])
        if is_fallen(p):
            fell_after = True
            break
    return up, (up_since - CYCLE_S if up and up_since is not None else math.nan), \
        fell_after, np.asarray(heights)


def getup_trial(motion: GetUpMotion, side: str, seed: int, hold_s: float = 2.0) -> GetUpTrial:
    """Fall as ``fall_setup(side, seed)`` draws, get up with ``motion`` (on ``LocalServer``)."""
    from .local_server import LocalServer

    s = fall_setup(side, seed)
    server = LocalServer(seed=seed)
    key = (TEAM, 1)
    server.join(*key)
    server.cycle({})
    sign = 1.0 if side == "front" else -1.0  # + pitch tips the torso forward
    tip = _quat_mul(_axis_quat((0, 1, 0), sign * s.tilt), _axis_quat((1, 0, 0), s.roll))
    quat = _quat_mul(_axis_quat((0, 0, 1), s.yaw), tip)
    server.set_robot_pose(TEAM, 1, (s.x, s.y, 0.67), quat, joints=s.joints,
                          angular_velocity=(0.0, sign * s.tip_rate, 0.0))
    falling = effectors.message(*(effectors.motor(m, s.joints[m], 0.0, s.fall_gain,
                                                  s.fall_gain / 20) for m in T1_MOTORS))

    def cycle(msg: str) -> Perception:
        return server.cycle({key: msg})[key]

    p = cycle(falling)
    for _ in range(round(s.fall_s / CYCLE_S)):
        p = cycle(falling)
    front = lying_on_front(p.orientations["torso_quat"])
    up, t_up, fell_after, heights = run_getup(motion, p, cycle, hold_s)
    return GetUpTrial(s, motion.side, front, up, t_up, fell_after, motion.duration, heights)
