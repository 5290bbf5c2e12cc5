"""One T1 kicking a ball on ``LocalServer``, for tuning and measuring the kick.

``kick_trial`` puts the ball at rest at ``BALL`` and the robot at ``start`` (world x, y, yaw),
lets it stand ``stand_s``, then either kicks at once (``approach=False``: the robot should
already stand at the kick spot) or walks to the ball with ``approach_command`` under the
given walk controller and kicks when ``KickMotion.ready`` (``approach=True``, within
``approach_s``). The kick's target is a world heading (``target_yaw``); each cycle it is
turned into the body frame from the torso's pose, as a team would ask. The ball's place the
robot uses comes from its vision (``BallTracker``); the ball's travel is measured from the
simulation's ground truth ``settle_s`` after the kick ends (or when it stops rolling).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from . import effectors
from .adapter import KICK_LATCH_M
from .controller import CYCLE_S, LocomotionController, WalkerController, torso_pose
from .falls import is_fallen
from .handover import HandOver
from .kick import (
    LEAGUE_KICK,
    BallTracker,
    KickMotion,
    KickParams,
    approach_command,
)

#: head pitch (rad, down) while the robot stands before the approach: the ball at the kick spot
#: is seen (the server applies a message's motor commands in order: this one overrides the
#: walk controller's head target)
LOOK_DOWN = 0.6
#: after the kick the robot walks on (``AFTER_KICK``, as a team following its ball would) this
#: long before it stands (s)
WIND_DOWN_S = 1.0
AFTER_KICK = (0.0, 0.0, 0.0)
#: where the ball lies (world, m): inside the left half, far from lines and the centre circle,
#: so a 10 m kick along +-45 deg stays on the field and no referee rule moves the ball
BALL = (-6.0, 0.0)


@dataclass(frozen=True)
class KickTrial:
    """kicked: the kick motion ran; travel: ball displacement (m) from where it lay to where
    it came to rest (or ``settle_s`` after the kick); direction: its world heading (rad);
    error: direction - target_yaw (rad, wrapped); upright: not down at the end of the trial
    (``falls.is_fallen``); fell_during: down at any time after the kick began;
    kick_s: the motion's duration (from its start to the end of the walk after the strike); approach_s: walking time before the kick; upright_s: time
    from the kick's start to the first cycle down (the whole watch if never)."""

    kicked: bool
    travel: float
    direction: float
    error: float
    upright: bool
    fell_during: bool
    kick_s: float
    approach_s: float
    foot: str | None
    upright_s: float = 0.0
    strike_ball_x: float | None = None
    strike_ball_y: float | None = None


def _wrap(a: float) -> float:
    return (a + math.pi) % (2 * math.pi) - math.pi


def kick_trial(start: tuple[float, float, float], target_yaw: float = 0.0, power: float = 1.0,
               params: KickParams = LEAGUE_KICK, approach: bool = True,
               walker: LocomotionController | None = None, stand_s: float = 0.6,
               approach_s: float = 12.0, settle_s: float = 3.0, seed: int = 0,
               ball: tuple[float, float] = BALL) -> KickTrial:
    from .local_server import LocalServer

    server = LocalServer(seed=seed)
    key = ("Kicker", 1)
    walker = walker or WalkerController()
    walker.reset()
    p = server.join(*key)
    # beam x is mirrored onto the own half: the left team's x is -|x|
    p = server.cycle({key: effectors.message(effectors.beam(*start), walker.stand(p))})[key]
    server.kick_off("Left")   # applied in the next cycle: it drops the ball at the centre
    p = server.cycle({key: walker.stand(p)})[key]
    server.place_ball(*ball)
    tracker = BallTracker()
    for _ in range(round(stand_s / CYCLE_S)):
        tracker.update(p)
        # the robot looks down at the ball while it stands (at the kick spot the ball is below
        # a level camera's view; a match's robot has seen it on its way there)
        p = server.cycle({key: walker.stand(p) + effectors.motor("he2", LOOK_DOWN, 0.0, 20.0,
                                                                   0.5)})[key]
    # as RequestEncoder: the kick is a step of our walker's gait; with another walk, the
    # kick's own walker takes over the approach within KICK_LATCH_M of the ball (the trials
    # walk the approach's pace: at once; with ``params.handover_stop`` once the walk has
    # stopped there, ``HandOver``)
    handover = HandOver(stop=params.handover_stop)
    kick = KickMotion(walker if isinstance(walker, WalkerController)
                      else WalkerController(stand_s=handover.stand_s), params)
    walking = walker
    walked = 0
    while True:
        rel = tracker.update(p)
        handover.update(p)
        direction = _wrap(target_yaw - torso_pose(p)[2])
        if is_fallen(p) or walked * CYCLE_S >= (approach_s if approach else 0.0):
            break
        if rel is not None and kick.ready(rel, direction, walking is kick.walker):
            break
        command = approach_command(rel, direction, params) if rel is not None else (0, 0, 0.5)
        begun = walking is kick.walker or handover.braking
        now = kick.walker if rel is not None and handover.near(math.hypot(*rel), KICK_LATCH_M,
                                                               begun) else walker
        braking = (handover.stop and now is not walking and walking is walker
                   and not handover.ready)
        if braking:
            now, command = walker, handover.brake(command)     # the walk stops first
        if now is not walking:
            now.reset()
            if now is walker:
                handover.reset()                        # its walk starts from rest
            walking = now
        if now is walker and not braking:
            handover.walked(command)
        p = server.cycle({key: walking.step(command, p)})[key]
        walked += 1
    ball0 = np.array(server.ball_position()[:2])
    if is_fallen(p) or (approach and walked * CYCLE_S >= approach_s) or rel is None:
        return KickTrial(False, 0.0, 0.0, math.pi, not is_fallen(p), is_fallen(p), 0.0,
                         walked * CYCLE_S, None)
    if walking is not kick.walker:
        kick.walker.reset()
    kick.start(p, direction, power, ball=rel)
    fell = False
    cycles = watched = 0
    while not kick.done:
        p = server.cycle({key: kick.step(p)})[key]
        fell |= is_fallen(p)
        cycles += 1
        watched += not fell
    last = np.array(server.ball_position()[:2])
    for k in range(round(settle_s / CYCLE_S)):
        # the walk the kick leaves winds down for a second, then the robot stands
        msg = kick.walker.step(AFTER_KICK, p) if k < round(WIND_DOWN_S / CYCLE_S) \
            else walker.stand(p)
        p = server.cycle({key: msg})[key]
        fell |= is_fallen(p)
        watched += not fell
        now = np.array(server.ball_position()[:2])
        if np.linalg.norm(now - last) < 0.002 and np.linalg.norm(now - ball0) > 0.05:  # at rest
            last = now
            break
        last = now
    d = last - ball0
    heading = math.atan2(d[1], d[0])
    return KickTrial(True, float(np.hypot(*d)), heading, _wrap(heading - target_yaw),
                     not is_fallen(p), fell, cycles * CYCLE_S, walked * CYCLE_S, kick.foot,
                     watched * CYCLE_S, kick.strike_ball_x, kick.strike_ball_y)


def spot_start(params: KickParams = LEAGUE_KICK, foot: str = "right", dx: float = 0.0,
               dy: float = 0.0, ball: tuple[float, float] = BALL) -> tuple[float, float, float]:
    """The beam pose (world x, y, yaw 0) that puts ``ball`` at the kick spot of ``foot``,
    offset by (dx, dy) m (ball further ahead / more to the left)."""
    side = -1.0 if foot == "right" else 1.0
    return (ball[0] - params.spot_x - dx, ball[1] - side * params.foot_y - dy, 0.0)
