"""A kick for the T1 on the league server: a kick step of our walker (a balance-controlled
kick), the approach that aims it, and the ball's place from the robot's own camera.

**The motion** (``KickMotion``: start(perception, direction, power) / step(perception) ->
motor effectors / done) walks on with ``WalkerController`` at ``KickParams.walk_vx`` and, on
the first swing of the kicking foot that begins with the ball at most ``strike_x`` ahead,
adds a strike to that swing leg's walk targets: the hip flexes by up to ``strike_hip`` and
the knee extends by up to ``strike_knee`` (a sine bump over ``strike_from``-``strike_to`` of
the single support), so the foot swings through the ball at ~2-3 m/s and comes back to the
foothold the walker planned. Everything else is the walk's: the LIPM preview control, the
capture-point step adjustment and the attitude feedback keep the robot up through and after
the strike, which a keyframe kick on one foot did not (tuned keyframe kicks fell in nearly
every trial on the server's physics; see docs/league.md). After the strike the walk goes on
for ``follow_s`` with the command falling to zero, then the motion is done. In a running gait
it starts (``KickMotion.ready``) one step before the kicking foot's swing that will find the
ball within ``strike_x``; the approach walks into the spot at ``approach_vx`` to get there
(so the kick lasts ~0.7 s, not up to three swings of that foot).

It starts from whatever the walk left: with the encoder's own ``WalkerController`` it simply
continues that gait (``KickMotion(walker)``); with another controller (e.g. the reference
network) it starts its own walker from the measured pose, its first ``BLEND_S`` blended from
the measured joint angles (the walker stands 0.5 s before its first step, so such a kick
takes ~0.8 s longer).

**Aiming.** The ball goes where the body faces, deflected outwards by the foot's edge (by
``aim_bias``, measured): ``kick_heading`` is the heading to face for a kick along a
direction, and ``approach_command`` walks the robot there with the ball in front of the
kicking foot (``spot_x`` ahead, ``foot_y`` to the side); ``in_kick_spot`` says when to start.
During the motion the walk keeps turning towards the kick heading and stepping sideways to
keep the ball in line. Limits: a kick goes where the body faces, so a direction far off the
heading is a turn first (~1.5 s for 90 deg at the walker's turn rate); the ball must lie
still or nearly (it is placed from memory in the last 0.55 m, below the camera's view);
``power`` scales the strike (0.4 + 0.6 power of the amplitudes; only full power is tuned
and measured).

**The ball's place** comes from vision only (``BallTracker``): each ``See`` gives the ball's
polar sighting from the head camera; the camera's pose follows from the torso's ``pos``/
``quat`` and the head's yaw/pitch joints (rcsssmj's T1: torso -> H1 -> H2 -> camera site), so
the sighting becomes a world point, kept between sightings and turned into the body frame of
the current torso pose. The head stays level (a pitched head would make the team's own
sightings, which assume a level camera, wrong), so the ball leaves the camera's +-60 deg when
it is nearer than ~0.55 m: the end of the approach and the kick use its remembered place.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace

import numpy as np

from .controller import CYCLE_S, LEAGUE_ENVELOPE, WalkerController, quat_yaw
from .errors import LeagueError
from .perception import Perception
from .t1 import T1_MOTORS, joint_sensor

MOTORS: tuple[str, ...] = tuple(T1_MOTORS)
#: the first seconds of a kick on a fresh walker blend from the measured joint angles
BLEND_S = 0.2
#: a kick on a walker of its own waits this much longer for its strike (s): that walker
#: stands 0.5 s and steps once before the kicking foot can swing
FRESH_WALKER_S = 0.8
#: a swing strikes only with the ball this close (m) to the kicking foot's line (else the foot
#: passes beside it); the kick steps sideways to bring it there and waits for the next swing
STRIKE_TOLERANCE_Y = 0.04


@dataclass(frozen=True)
class KickParams:
    """A kick step (m, s, rad).

    spot_x, foot_y: where the approach puts the ball (ahead of the torso; beside it, on the
    kicking foot's side); strike_x: the strike starts on a kicking-foot swing that begins with
    the ball at most this far ahead; walk_vx: walking speed while kicking; strike_hip,
    strike_knee: the strike's hip flexion and knee extension (added to the walk's swing leg);
    strike_from, strike_to: the strike's share of the single support; follow_s: from the
    strike's start to the motion's end (the swing lands within it; the command goes to
    follow_vx, which the trials keep walking after the motion); max_wait_s: a kick whose strike has not begun by then ends without one;
    aim_bias: the ball's measured outward deflection (the body faces this much inwards);
    approach_vx: the lined-up approach's pace into the spot; phase_start: start one step
    before the striking swing (``KickMotion.ready``); handover_stop: with another walk
    controller, it stops and the kick's walker takes over on both feet
    (``teamenv.league.handover``; measured, not the default: docs/league.md)."""

    spot_x: float = 0.43
    foot_y: float = 0.115
    strike_x: float = 0.39
    walk_vx: float = 0.1
    strike_hip: float = 0.6
    strike_knee: float = 0.3
    strike_from: float = 0.1
    strike_to: float = 0.75
    follow_s: float = 0.4
    follow_vx: float = 0.0
    max_wait_s: float = 3.0
    aim_bias: float = 0.18
    approach_vx: float = 0.1
    phase_start: bool = True
    handover_stop: bool = False

    def with_(self, **kw: float | bool) -> KickParams:
        return replace(self, **kw)

    def as_dict(self) -> dict[str, float | bool]:
        return {f.name: getattr(self, f.name) for f in fields(self)}


#: the kick on the league server (``benchmarks/league_kick_tune.py`` measures candidates:
#: ``--check --params '{...}'``; see docs/league.md for how these were chosen)
LEAGUE_KICK = KickParams()


#: within this distance (m) the kicking foot is the one on the ball's side of the body, beyond
#: it the one on the ball's side of the kick line
FOOT_BY_BODY_M = 1.0


def kick_foot(ball: tuple[float, float], direction: float) -> str:
    """The foot that kicks ``ball`` (body frame) along ``direction``: near, the one on the
    ball's side of the body (a robot lined up for a kick faces ``aim_bias`` away from the
    direction, which puts the ball close to the kick line); far, the one on the ball's side
    of the kick line."""
    if math.hypot(*ball) <= FOOT_BY_BODY_M:
        return "left" if ball[1] > 0 else "right"
    c, s = math.cos(direction), math.sin(direction)
    return "left" if -s * ball[0] + c * ball[1] > 0 else "right"


def kick_heading(direction: float, foot: str, params: KickParams = LEAGUE_KICK) -> float:
    """The body heading (body frame, rad) that sends the ball along ``direction``: turned
    inwards by ``aim_bias`` against the kicking foot's outward deflection."""
    return direction + (params.aim_bias if foot == "right" else -params.aim_bias)


class KickMotion:
    """One kick at a time: ``start`` it, then ``step`` every cycle until ``done``.

    ``walker``: the ``WalkerController`` the robot walks with (its gait goes on through the
    kick); None: the kick brings its own, started from the measured pose."""

    def __init__(self, walker: WalkerController | None = None,
                 params: KickParams = LEAGUE_KICK) -> None:
        self.params = params
        self.shares_walker = walker is not None
        self.walker = walker if walker is not None else WalkerController()
        self.done = True
        self.foot: str | None = None
        self.struck = False
        self.strike_ball_x: float | None = None
        self.strike_ball_y: float | None = None
        self._t = 0.0
        self._strike_t: float | None = None
        self._ball_world: np.ndarray | None = None
        self._heading_world = 0.0
        self._amplitude = 1.0
        self._from: np.ndarray | None = None

    def start(self, perception: Perception, direction: float = 0.0, power: float = 1.0,
              foot: str | None = None, ball: tuple[float, float] | None = None) -> None:
        """Begin a kick along ``direction`` (rad, body frame) with ``power`` 0-1; ``ball``: its
        body-frame (x, y) m (where the approach put it); ``foot``: "left"/"right" (default:
        the ball's side of the kick line)."""
        if not math.isfinite(power) or not 0.0 <= power <= 1.0:
            raise LeagueError(f"kick: power {power!r} is not in 0..1")
        if not math.isfinite(direction):
            raise LeagueError(f"kick: direction {direction!r} is not finite")
        if ball is None:
            raise LeagueError("kick: start() needs the ball's body-frame place (ball=(x, y))")
        if foot is None:
            foot = kick_foot(ball, direction)
        if foot not in ("left", "right"):
            raise LeagueError(f"kick: foot {foot!r} is not 'left' or 'right'")
        x, y, _ = perception.positions["torso_pos"]
        yaw = quat_yaw(*perception.orientations["torso_quat"])
        c, s = math.cos(yaw), math.sin(yaw)
        self._ball_world = np.array([x + c * ball[0] - s * ball[1], y + s * ball[0] + c * ball[1]])
        self._heading_world = yaw + kick_heading(direction, foot, self.params)
        self._amplitude = 0.4 + 0.6 * power
        self.foot = foot
        self.struck = False
        self.strike_ball_x = self.strike_ball_y = None
        self._strike_t = None
        self._t = 0.0
        self._from = None
        if not self.shares_walker:
            self.walker.reset()
            self._from = measured_angles(perception)
        self.done = False

    def ready(self, ball: tuple[float, float], direction: float, walking: bool = True) -> bool:
        """Whether to start the kick now: ``in_kick_spot`` and, with ``phase_start`` while
        this kick's walker walks the approach (``walking``), the kicking foot's swing is the
        next step and finds the ball (walking on at ``walk_vx``) at most ``strike_x`` ahead,
        so the strike comes on that swing: the wait for it is walked as approach, in the
        same gait, instead of inside the kick."""
        p = self.params
        if not in_kick_spot(ball, direction, p):
            return False
        gait = self.walker.gait if walking and p.phase_start else None
        if gait is None:
            return True
        swing, t_step, period = gait
        kicking = "Left" if kick_foot(ball, direction) == "left" else "Right"
        return swing != kicking and ball[0] - p.walk_vx * (period - t_step) <= p.strike_x

    @property
    def elapsed_s(self) -> float:
        return self._t

    def _command(self, perception: Perception) -> tuple[float, float, float]:
        p = self.params
        bx, by = to_body(perception, self._ball_world)
        yaw = quat_yaw(*perception.orientations["torso_quat"])
        err = math.remainder(self._heading_world - yaw, 2 * math.pi)
        turn = float(np.clip(1.2 * err, -0.4, 0.4))
        if self._strike_t is not None:      # after the strike: from walk_vx to follow_vx
            left = max(0.0, 1.0 - (self._t - self._strike_t) / max(p.follow_s, 1e-6))
            return p.follow_vx + (p.walk_vx - p.follow_vx) * left, 0.0, turn * left
        side = 1.0 if self.foot == "left" else -1.0
        vy = float(np.clip(3.0 * (by - side * p.foot_y), -0.1, 0.1))
        return p.walk_vx, vy, turn

    def _strike(self, walker, motors, q_ref: np.ndarray) -> np.ndarray:
        """The strike added to the kicking leg's walk targets (``WalkerController.step``)."""
        p = self.params
        swing = "Left" if self.foot == "left" else "Right"
        ss = walker.p.step_period - walker.p.double_support
        if (self._strike_t is None and walker.swing == swing
                and 0.0 < walker.t_step <= CYCLE_S + walker.p.dt + 1e-9):   # began this cycle
            bx, by = to_body(self._perception, self._ball_world)
            side = 1.0 if self.foot == "left" else -1.0
            if bx <= p.strike_x and abs(by - side * p.foot_y) <= STRIKE_TOLERANCE_Y:
                self._strike_t = self._t   # this swing is the kick
                self.strike_ball_x, self.strike_ball_y = bx, by
        if self._strike_t is None or self.struck or walker.swing != swing:
            return q_ref
        u = (walker.t_step / ss - p.strike_from) / (p.strike_to - p.strike_from)
        if walker.t_step / ss >= 1.0:
            self.struck = True
            return q_ref
        bump = math.sin(math.pi * min(1.0, max(0.0, u))) * self._amplitude
        leg = "lle" if self.foot == "left" else "rle"
        q = q_ref.copy()
        q[motors.index(f"{leg}1")] -= p.strike_hip * bump
        k = motors.index(f"{leg}4")
        q[k] = max(0.0, q[k] - p.strike_knee * bump)
        return q

    def step(self, perception: Perception) -> str:
        if self.done:
            raise LeagueError("kick: step() without a running kick (start() it first)")
        self._t += CYCLE_S
        self._perception = perception
        message = self.walker.step(self._command(perception), perception, adjust=self._blend)
        p = self.params
        wait = p.max_wait_s + (0.0 if self.shares_walker else FRESH_WALKER_S)
        if self._strike_t is None and self._t >= wait:
            self.done = True                # the strike never began (the ball moved away)
        elif self.struck and self._t - self._strike_t >= p.follow_s:
            self.done = True
        return message

    def _blend(self, walker, motors, q_ref: np.ndarray) -> np.ndarray:
        q = self._strike(walker, motors, q_ref)
        if self._from is not None and self._t < BLEND_S:
            start = np.array([self._from[MOTORS.index(m)] for m in motors])
            w = self._t / BLEND_S
            q = start + w * (q - start)
        return q


def measured_angles(perception: Perception) -> np.ndarray:
    """Every T1 motor's measured joint angle (rad), in ``MOTORS`` order."""
    out = np.zeros(len(MOTORS))
    for k, m in enumerate(MOTORS):
        js = perception.joints.get(joint_sensor(m))
        if js is None:
            raise LeagueError(f"kick: perception has no joint {joint_sensor(m)!r} (T1 expected)")
        out[k] = js.angle
    return out


# -- where the ball is ---------------------------------------------------------------------
#: rcsssmj's T1: H1 (head yaw) in the torso, H2 (head pitch) in H1, the camera site in H2 (m)
_H1 = np.array([0.0625, 0.0, 0.243])
_H2 = np.array([0.0, 0.0, 0.06185])
_CAMERA = np.array([0.05, 0.0, 0.12])


def _quat_matrix(w: float, x: float, y: float, z: float) -> np.ndarray:
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def _rz(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _ry(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def seen_ball_world(perception: Perception) -> np.ndarray | None:
    """The ball's world position (m) from this perception's sighting, or None if not seen."""
    if perception.vision is None or perception.vision.ball is None:
        return None
    try:
        torso = np.asarray(perception.positions["torso_pos"], dtype=float)
        rot = _quat_matrix(*perception.orientations["torso_quat"])
        yaw = perception.joints["q_hj1"].angle
        pitch = perception.joints["q_hj2"].angle
    except KeyError as exc:
        raise LeagueError(f"kick: perception has no {exc.args[0]} (needed to place the ball)") \
            from None
    r1 = rot @ _rz(yaw)
    r2 = r1 @ _ry(pitch)
    camera = torso + rot @ _H1 + r1 @ _H2 + r2 @ _CAMERA
    b = perception.vision.ball
    local = b.distance * np.array([math.cos(b.elevation) * math.cos(b.azimuth),
                                   math.cos(b.elevation) * math.sin(b.azimuth),
                                   math.sin(b.elevation)])
    return camera + r2 @ local


def to_body(perception: Perception, world_xy) -> tuple[float, float]:
    """A world point (x, y) in the torso's body frame (x ahead, y left), m."""
    x, y, _ = perception.positions["torso_pos"]
    yaw = quat_yaw(*perception.orientations["torso_quat"])
    dx, dy = float(world_xy[0]) - x, float(world_xy[1]) - y
    c, s = math.cos(yaw), math.sin(yaw)
    return c * dx + s * dy, -s * dx + c * dy


class BallTracker:
    """The ball's last seen world place (vision comes every second cycle), as a body-frame
    point of the current torso pose; ``age_s`` since it was last seen."""

    def __init__(self) -> None:
        self.world: np.ndarray | None = None
        self.age_s = math.inf
        #: the ball in the body frame of the last update (None: never seen)
        self.body: tuple[float, float] | None = None

    def reset(self) -> None:
        self.world, self.age_s, self.body = None, math.inf, None

    def update(self, perception: Perception) -> tuple[float, float] | None:
        """Take this cycle's sighting (if any); returns the ball's body-frame (x, y), m (None
        also for a perception without the torso's pose)."""
        if "torso_pos" not in perception.positions or \
                "torso_quat" not in perception.orientations:
            self.body = None
            return None
        seen = seen_ball_world(perception)
        if seen is not None:
            self.world, self.age_s = seen, 0.0
        else:
            self.age_s += CYCLE_S
        self.body = None if self.world is None else to_body(perception, self.world[:2])
        return self.body


# -- the approach that aims the kick ---------------------------------------------------------
#: how close to the kick spot (m: along the kick (range), sideways) and to the kick heading
#: (rad) the robot must be to start the kick (the kick then walks on and corrects as it goes;
#: the range keeps the wait for the strike short)
SPOT_TOLERANCE_X = (-0.06, 0.03)
SPOT_TOLERANCE_Y = 0.05
HEADING_TOLERANCE = 0.12
#: within this (m, the ball beyond the spot) a lined-up approach walks at ``approach_vx``
APPROACH_WALK_IN_M = 0.2
#: the share of the walker's envelope (``LEAGUE_ENVELOPE``, as an ellipsoid) the approach uses
APPROACH_ENVELOPE_SHARE = 0.7


def spot_error(ball: tuple[float, float], direction: float,
               params: KickParams = LEAGUE_KICK) -> tuple[float, float, float]:
    """How far the robot is from starting a kick of ``ball`` (body frame) along
    ``direction``: the ball's offset from the kick spot in the body frame turned to the kick
    heading (ahead, left), and the heading error (rad)."""
    foot = kick_foot(ball, direction)
    heading = kick_heading(direction, foot, params)
    c, s = math.cos(heading), math.sin(heading)
    bx, by = c * ball[0] + s * ball[1], -s * ball[0] + c * ball[1]
    side = 1.0 if foot == "left" else -1.0
    return bx - params.spot_x, by - side * params.foot_y, heading


def in_kick_spot(ball: tuple[float, float], direction: float,
                 params: KickParams = LEAGUE_KICK) -> bool:
    ex, ey, eh = spot_error(ball, direction, params)
    return (SPOT_TOLERANCE_X[0] <= ex <= SPOT_TOLERANCE_X[1] and abs(ey) <= SPOT_TOLERANCE_Y
            and abs(eh) <= HEADING_TOLERANCE)


def approach_command(ball: tuple[float, float], direction: float,
                     params: KickParams = LEAGUE_KICK,
                     speed: float = 0.3) -> tuple[float, float, float]:
    """A walk command (vx, vy, turn; body frame) to the kick spot: the torso's goal is
    ``spot_x`` behind the ball along the kick heading and ``foot_y`` to the side of the
    kicking foot; it faces the goal while far and the kick heading when near (blended in
    between), slowing its translation while the heading is far off; gains and limits stay
    inside what the walker follows without falling (it falls under large sideways steps and
    fast command reversals)."""
    foot = kick_foot(ball, direction)
    heading = kick_heading(direction, foot, params)
    side = 1.0 if foot == "left" else -1.0
    c, s = math.cos(heading), math.sin(heading)
    gx = ball[0] - (c * params.spot_x - s * side * params.foot_y)
    gy = ball[1] - (s * params.spot_x + c * side * params.foot_y)
    dist = math.hypot(gx, gy)
    far = min(1.0, max(0.0, (dist - 0.25) / 0.5))       # 1 beyond 0.75 m, 0 within 0.25 m
    toward = math.atan2(gy, gx) if dist > 1e-6 else heading
    aim = far * toward + (1.0 - far) * heading
    turn = float(np.clip(1.2 * aim, -0.6, 0.6))
    slow = max(0.0, 1.0 - abs(aim) / 0.8)               # turn first when far off
    vx = float(np.clip(1.5 * gx, -0.15, speed)) * slow
    ex, ey, _ = spot_error(ball, direction, params)
    if (params.approach_vx > 0.0 and SPOT_TOLERANCE_X[0] < ex <= APPROACH_WALK_IN_M
            and abs(ey) <= SPOT_TOLERANCE_Y and abs(heading) <= HEADING_TOLERANCE):
        # lined up: walk into the spot at the kick's own pace instead of slowing into it, so
        # the kick starts in a forward gait with the ball coming into reach
        vx = max(vx, params.approach_vx)
    vy = float(np.clip(3.0 * gy, -0.1, 0.1)) * slow     # small sideways commands barely move
    # the walker falls near the edge of its envelope when walking, stepping sideways and
    # turning at once: keep the combined command within APPROACH_ENVELOPE_SHARE of it
    e = LEAGUE_ENVELOPE
    norm = math.sqrt((vx / (e.vx_forward if vx >= 0 else e.vx_backward)) ** 2
                     + (vy / e.vy) ** 2 + (turn / e.turn) ** 2)
    k = min(1.0, APPROACH_ENVELOPE_SHARE / max(norm, 1e-9))
    return vx * k, vy * k, turn * k
