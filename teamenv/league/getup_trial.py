"""One T1 falling and getting up on the league server, for tuning and testing ``GetUpMotion``.

``getup_trial`` makes the robot fall the way ``fall_setup(side, seed)`` draws it: standing in
the walker's stance with noise, tilted towards its front or back (plus a roll and any
heading), arms in a random posture, limp-ish joints while it falls for a random 1.0-1.8 s (longer,
up to 3 s more, until it is down by the observation's fall test); then it runs the motion until
``done``, and for ``hold_s`` more sees whether it stays up: standing with ``after`` (a walk
controller, as a match hands the robot to its walk; the league's is
``NetworkWalkController``) or, without one, holding the motion's end pose. The plant is
``LocalServer`` (the robot is put in place with ``set_robot_pose``, which the real server
cannot do; ``real_fall_trial`` tips it over with its own motors instead, and runs on either
plant).

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
from .controller import CYCLE_S, LocomotionController
from .falls import is_fallen
from .getup import END_POSE, GROUPS, GetUpMotion, is_up, lying_on_front
from .perception import Perception
from .t1 import T1_MOTORS

TEAM = "GetUp"
#: a field player: the referee stands it up after 15 s on the ground (the goalie, 1: 30 s)
UNUM = 2
#: seconds a fall may take beyond its drawn ``fall_s`` until the robot is down
MAX_EXTRA_FALL_S = 3.0


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
        yaw=float(rng.uniform(-math.pi, math.pi)), tilt=float(rng.uniform(0.3, 0.6)),
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
    ``motion_s``: the motion's duration; ``heights``, ``uprights``: torso height (m) and the
    z of its up axis per cycle of the motion and the hold after."""

    setup: FallSetup
    side_detected: str
    lying_on_front: bool
    up: bool
    time_to_up: float
    fell_after: bool
    motion_s: float
    heights: np.ndarray
    uprights: np.ndarray

    @property
    def success(self) -> bool:
        return self.up and not self.fell_after


def run_getup(motion: GetUpMotion, p: Perception, cycle: Callable[[str], Perception],
              hold_s: float, max_s: float | None = None,
              after: LocomotionController | None = None) -> tuple[bool, float, bool, np.ndarray,
                                                                np.ndarray]:
    """Run ``motion`` from perception ``p``, then stand ``hold_s`` with ``after`` (reset at the
    hand-over; None: the motion holds its end pose); returns (up at done, time to up, fell in
    hold, torso heights, torso up-axis z)."""
    motion.start(p)
    max_s = motion.duration + 1.0 if max_s is None else max_s
    heights, uprights, up_since = [], [], None

    def record(p: Perception) -> None:
        _, x, y, _ = p.orientations["torso_quat"]
        heights.append(p.positions["torso_pos"][2])
        uprights.append(1.0 - 2.0 * (x * x + y * y))

    t = 0.0
    while not motion.done and t < max_s:
        p = cycle(motion.step(p))
        t += CYCLE_S
        record(p)
        if is_up(p):
            up_since = t if up_since is None else up_since
        else:
            up_since = None
    up = motion.succeeded
    fell_after = False
    if after is not None:
        after.reset()
    for _ in range(round(hold_s / CYCLE_S)):
        p = cycle(motion.step(p) if after is None else after.stand(p))
        record(p)
        if is_fallen(p):
            fell_after = True
            break
    return up, (up_since - CYCLE_S if up and up_since is not None else math.nan), \
        fell_after, np.asarray(heights), np.asarray(uprights)


def getup_trial(motion: GetUpMotion, side: str, seed: int, hold_s: float = 2.0,
                server=None, watch: Callable[[object], None] | None = None,
                after: LocomotionController | None = None) -> GetUpTrial:
    """Fall as ``fall_setup(side, seed)`` draws, get up with ``motion`` on ``server`` (a
    ``LocalServer`` that ``trial_server()`` made, reused to save its start-up; default a new
    one). ``watch(server)`` is called after every cycle of the motion and the hold (tuning
    looks at the simulation's state there); ``after``: the walk that stands the robot in the
    hold (see ``run_getup``)."""
    s = fall_setup(side, seed)
    server = server or trial_server()
    key = (TEAM, UNUM)

    def cycle(msg: str) -> Perception:
        return server.cycle({key: msg})[key]

    def watched(msg: str) -> Perception:
        p = cycle(msg)
        watch(server)
        return p

    p = fall(server, s)
    front = lying_on_front(p.orientations["torso_quat"])
    up, t_up, fell_after, heights, uprights = run_getup(
        motion, p, watched if watch else cycle, hold_s, after=after)
    return GetUpTrial(s, motion.side, front, up, t_up, fell_after, motion.duration, heights,
                      uprights)


def fall(server, s: FallSetup) -> Perception:
    """Make the trial robot on ``server`` fall as ``s`` says; returns the perception of the
    cycle it is down (the server's pending answer is the falling command's)."""
    key = (TEAM, UNUM)
    side = s.side
    sign = 1.0 if side == "front" else -1.0  # + pitch tips the torso forward
    tip = _quat_mul(_axis_quat((0, 1, 0), sign * s.tilt), _axis_quat((1, 0, 0), s.roll))
    quat = _quat_mul(_axis_quat((0, 0, 1), s.yaw), tip)
    falling = effectors.message(*(effectors.motor(m, s.joints[m], 0.0, s.fall_gain,
                                                  s.fall_gain / 20) for m in T1_MOTORS))

    def cycle(msg: str) -> Perception:
        return server.cycle({key: msg})[key]

    # answered first, so the pose below moves under the falling command from its first step
    # (the server applies an answer one cycle late), not under the last trial's
    cycle(falling)
    server.set_robot_pose(TEAM, UNUM, (s.x, s.y, 0.67), quat, joints=s.joints,
                          angular_velocity=(0.0, sign * s.tip_rate, 0.0))
    p = cycle(falling)
    for _ in range(round(s.fall_s / CYCLE_S)):
        p = cycle(falling)
    # a slow fall (sitting down on bent knees) is not over yet: the motion starts when the
    # robot is down, as a match starts it
    for _ in range(round(MAX_EXTRA_FALL_S / CYCLE_S)):
        if is_fallen(p):
            break
        p = cycle(falling)
    return p


def trial_server():
    """A ``LocalServer`` with the trial robot joined (before kick-off: the referee's rule
    that stands up a robot lying 15 s does not act then)."""
    from .local_server import LocalServer

    server = LocalServer()
    server.join(TEAM, UNUM)
    server.cycle({})
    return server


#: postures (joint group -> rad, the rest the end pose) that tip a standing robot over with its
#: own motors: hips bent back and toes down fall forward, hips bent forward fall backward
TIP_POSTURES = {
    "front": {"hip_pitch": 0.5, "knee": 0.0, "ankle_pitch": -0.6, "shoulder_pitch": 0.8},
    "back": {"hip_pitch": -0.9, "ankle_pitch": 0.35, "shoulder_pitch": -1.0},
}


def tip_message(side: str) -> str:
    """Motor effectors that tip a standing robot onto its ``side`` (works on any server)."""
    if side not in TIP_POSTURES:
        raise ValueError(f"tip_message: side must be 'front' or 'back', not {side!r}")
    pose = dict(END_POSE)
    pose.update(TIP_POSTURES[side])
    joints = {}
    for group, angle in pose.items():
        motors, sign = GROUPS[group]
        joints[motors[0]] = angle
        if len(motors) == 2:
            joints[motors[1]] = sign * angle
    return effectors.message(*(effectors.motor(m, joints[m], 0.0, 150.0, 3.0)
                               for m in T1_MOTORS))


def real_fall_trial(motion: GetUpMotion, side: str, hold_s: float = 1.0,
                    real_server: bool = True,
                    after: LocomotionController | None = None) -> GetUpTrial:
    """Beam a robot, let it stand 0.5 s, tip it onto ``side`` with its own motors (at most 3 s
    until it is down and 0.5 s more to settle), get up with ``motion``, stand ``hold_s`` with
    ``after`` (see ``run_getup``); on the real ``rcssservermj`` (``real_server``) or on
    ``LocalServer``."""
    from .controller import WalkerController

    def run(first: Perception, cycle: Callable[[str], Perception],
            kick_off: Callable[[], None]) -> GetUpTrial:
        stand = WalkerController().stand(first)
        p = cycle(effectors.message(effectors.beam(-5.0, 0.0, 0.0), stand))
        kick_off()
        for _ in range(25):
            p = cycle(stand)
        tip = tip_message(side)
        for _ in range(150):
            p = cycle(tip)
            if is_fallen(p):
                break
        for _ in range(25):
            p = cycle(tip)
        front = lying_on_front(p.orientations["torso_quat"])
        up, t_up, fell_after, heights, uprights = run_getup(motion, p, cycle, hold_s,
                                                            after=after)
        setup = FallSetup(side=side, x=-5.0, y=0.0, yaw=0.0, tilt=0.0, roll=0.0, tip_rate=0.0,
                          joints={}, fall_gain=150.0, fall_s=0.0)
        return GetUpTrial(setup, motion.side, front, up, t_up, fell_after, motion.duration,
                          heights, uprights)

    if real_server:
        from .server import LeagueServer
        from .team_client import TeamClient

        with LeagueServer() as server, TeamClient("127.0.0.1", server.agent_port, TEAM, (UNUM,),
                                                  check_alive=server.check_alive) as team:
            team.join()

            def cycle(msg: str) -> Perception:
                team.act({UNUM: msg})
                return team.perceive()[UNUM]

            return run(team.perceive()[UNUM], cycle, lambda: server.monitor.kick_off("Left"))
    server = trial_server()
    key = (TEAM, UNUM)
    return run(server.latest[key], lambda msg: server.cycle({key: msg})[key],
               lambda: server.kick_off("Left"))
