"""A kick for the T1 on the league server: a keyframe motion in joint space, tuned by CMA-ES on
the server's own physics, and the approach that aims it.

**The motion** (``KickMotion``): start(perception, direction, power) / step(perception) ->
motor effectors / done. It begins from the joint angles the robot measures (whatever the walk
left) and moves through six keyframes, each reached by smooth (cosine) interpolation from the
previous one, every motor held by the server's PD at ``KickParams.gain_scale`` x the T1 gains:

1. shift: both hip rolls tilt the pelvis over the support foot (ankle rolls keep the feet flat);
2. wind-up: the kicking leg lifts and swings back (hip pitch +, knee bent);
3. strike: hip pitch forward, knee straight, within ``strike_s`` (the ball is hit here);
4. retract and land: the kicking foot comes back under the hip and is set down, the weight
   still on the support foot;
5. recover: both legs to the stance, where the walk (or standing) takes over.

The kicking foot is the one on the ball's side; the left kick is the right kick mirrored
(left <-> right, roll and yaw signs flipped).

**Aiming.** The motion kicks along the body's heading (plus ``strike_yaw``: the kicking hip's
yaw turns the foot by up to ``MAX_STRIKE_YAW`` to take off a small remaining heading error).
The aim comes from the approach: ``approach_command`` walks the robot so that it faces the
asked direction with the ball at the kick spot in front of the kicking foot
(``KickParams.spot_x``, ``spot_y``), and ``in_kick_spot`` says when it is close enough to start.
Limits: a kick goes where the body faces (so asking for 90 deg means turning first, ~1.5 s
at the walker's 1 rad/s); the ball must lie still or nearly (a rolling ball drifts out of the
spot between the decision and the strike, ~0.6 s); power scales the strike's swing (only
full power is tuned and measured).

**The ball's place** comes from vision only (``BallTracker``): each ``See`` gives the ball's
polar sighting from the head camera; the camera's pose follows from the torso's ``pos``/
``quat`` and the head's yaw/pitch joints (rcsssmj's T1: torso -> H1 -> H2 -> camera site), so
the sighting becomes a world point, kept between sightings and turned into the body frame of
the current torso pose. The head stays level (a pitched head would make the team's own
sightings, which assume a level camera, wrong), so the ball leaves the camera's +-60 deg
when it is nearer than ~0.55 m: the last ~0.3 m of the approach and the kick use the ball's
remembered place (``KICK_SIGHTING_MAX_AGE_S`` in the adapter), which holds for a ball at rest.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace

import numpy as np

from locomotion.humanoid.t1 import PD_GAINS
from locomotion.humanoid.t1 import STANCE as T1_STANCE

from . import effectors
from .controller import CYCLE_S, quat_yaw
from .errors import LeagueError
from .perception import Perception
from .t1 import T1_MOTORS, joint_sensor

MOTORS: tuple[str, ...] = tuple(T1_MOTORS)
_INDEX = {m: k for k, m in enumerate(MOTORS)}

def _per_motor(table) -> np.ndarray:
    return np.array([table(T1_MOTORS[m]) for m in MOTORS], dtype=float)


def _gain(joint: str, which: int) -> float:
    for frag, kp, kd in PD_GAINS:
        if frag in joint:
            return (kp, kd)[which]
    raise LeagueError(f"kick: no PD gains for T1 joint {joint!r}")


#: the T1's standing angles (rad) and PD gains per motor, from the walker's model
STANCE_Q = _per_motor(lambda j: T1_STANCE.get(j, 0.0))
KP = _per_motor(lambda j: _gain(j, 0))
KD = _per_motor(lambda j: _gain(j, 1))

#: the largest hip-yaw turn of the kicking foot used to take off a heading error (rad)
MAX_STRIKE_YAW = 0.35


@dataclass(frozen=True)
class KickParams:
    """A right-foot kick (the left one is its mirror). Angles rad, times s, lengths m.

    shift_roll: hip roll moving the pelvis over the support foot; shift_s: its time.
    back_hip/back_knee/back_ankle: the kicking leg wound up; sup_hip/sup_ankle: the support
    leg's pitch offsets while on one foot (lean); back_s: wind-up time.
    strike_hip/strike_knee/strike_ankle: the kicking leg at the end of the strike; strike_s.
    retract_s, land_s, recover_s: the kicking foot back under the hip; set down with the
    weight still on the support foot (land_hip, land_knee: its hip pitch and knee offsets from
    the stance there, the sole kept flat); both legs back to the stance.
    spot_x, spot_y: where the ball should lie before the kick (torso frame: ahead, towards the
    kicking side). gain_scale: PD gains x the T1's; kick_gain: x that again on the kicking hip
    pitch and knee. tilt_gain, rate_gain: balance feedback,
    the support ankle's roll and pitch targets move against the torso's measured tilt (rad)
    and tilt rate (gyro, rad/s), which keeps the trunk over the support foot;
    hip_roll_gain, hip_pitch_gain: the same on the support hip (rad per rad of tilt)."""

    shift_roll: float = 0.12
    shift_s: float = 0.386
    sup_hip: float = 0.055
    sup_ankle: float = -0.047
    back_hip: float = -0.025
    back_knee: float = 1.028
    back_ankle: float = -0.421
    back_s: float = 0.181
    strike_hip: float = -0.676
    strike_knee: float = 0.108
    strike_ankle: float = -0.101
    strike_s: float = 0.098
    retract_s: float = 0.22
    land_s: float = 0.255
    land_hip: float = -0.2
    land_knee: float = 0.2
    recover_s: float = 0.269
    spot_x: float = 0.29
    spot_y: float = 0.115
    gain_scale: float = 1.753
    kick_gain: float = 2.0
    tilt_gain: float = 0.7
    rate_gain: float = 0.07
    hip_roll_gain: float = -0.9
    hip_pitch_gain: float = -0.8

    def with_(self, **kw: float) -> KickParams:
        return replace(self, **kw)

    def as_dict(self) -> dict[str, float]:
        return {f.name: getattr(self, f.name) for f in fields(self)}

    @property
    def duration_s(self) -> float:
        return (self.shift_s + self.back_s + self.strike_s + self.retract_s + self.land_s
                + self.recover_s)


#: the kick on the league server (see the module doc; tuning command in
#: benchmarks/league_kick_tune.py)
LEAGUE_KICK = KickParams()


def _mirror(q: np.ndarray) -> np.ndarray:
    """A pose mirrored left <-> right (rolls and yaws change sign, pitches do not)."""
    out = q.copy()
    for m, k in _INDEX.items():
        if m.startswith(("l", "r")):
            other = ("r" if m[0] == "l" else "l") + m[1:]
            out[_INDEX[other]] = q[k]
    for m, k in _INDEX.items():
        joint = T1_MOTORS[m]
        if joint.endswith(("_Roll", "_Yaw", "_yaw")) or joint == "Waist":
            out[k] = -out[k]
    return out


def _keyframes(p: KickParams, power: float, strike_yaw: float) -> list[tuple[float, np.ndarray]]:
    """(time to reach, pose) of a right-foot kick, after the start pose."""
    stance = STANCE_Q

    def pose(**angles: float) -> np.ndarray:
        q = stance.copy()
        for m, v in angles.items():
            q[_INDEX[m]] += v
        return q

    # right kick: the pelvis moves left (+y) over the left foot: both feet go -y = hip roll -
    shift = dict(lle2=-p.shift_roll, rle2=-p.shift_roll, lle6=p.shift_roll, rle6=p.shift_roll)
    support = dict(shift, lle1=p.sup_hip, lle5=p.sup_ankle)
    wound = pose(**support, rle1=p.back_hip, rle4=p.back_knee, rle5=p.back_ankle)
    strike_hip = p.back_hip + power * (p.strike_hip - p.back_hip)
    struck = pose(**support, rle1=strike_hip, rle4=p.strike_knee, rle5=p.strike_ankle,
                  rle3=strike_yaw)
    retracted = pose(**support, rle1=-0.25, rle4=0.6, rle5=-0.3)
    # set down where it catches the trunk (ahead: a step against the strike's forward lean),
    # the sole flat: ankle pitch = -(hip + knee) offsets
    landed = pose(**support, rle1=p.land_hip, rle4=p.land_knee, rle5=-(p.land_hip + p.land_knee))
    return [(p.shift_s, pose(**shift)),
            (p.back_s, wound),
            (p.strike_s, struck),
            (p.retract_s, retracted),
            (p.land_s, landed),
            (p.recover_s, stance)]


class KickMotion:
    """One kick at a time: ``start`` it, then ``step`` every cycle until ``done``."""

    def __init__(self, params: KickParams = LEAGUE_KICK) -> None:
        self.params = params
        self._frames: list[tuple[float, np.ndarray]] = []
        self._t = 0.0
        self._from: np.ndarray | None = None
        self.foot: str | None = None
        self.done = True

    def start(self, perception: Perception, direction: float = 0.0, power: float = 1.0,
              foot: str | None = None, ball: tuple[float, float] | None = None) -> None:
        """Begin a kick from the measured joint angles. ``direction`` (rad, body frame): the
        part within +-MAX_STRIKE_YAW turns the kicking foot (the approach aims the rest);
        ``power`` 0-1; ``foot`` "left"/"right" (default: the ball's side, from ``ball`` =
        its body-frame (x, y), else right)."""
        if not 0.0 <= power <= 1.0 or not math.isfinite(power):
            raise LeagueError(f"kick: power {power!r} is not in 0..1")
        if not math.isfinite(direction):
            raise LeagueError(f"kick: direction {direction!r} is not finite")
        if foot is None:
            foot = "left" if ball is not None and ball[1] > 0 else "right"
        if foot not in ("left", "right"):
            raise LeagueError(f"kick: foot {foot!r} is not 'left' or 'right'")
        yaw = float(np.clip(direction, -MAX_STRIKE_YAW, MAX_STRIKE_YAW))
        # the right foot's yaw turns it; mirrored for the left foot (the mirror flips yaw)
        frames = _keyframes(self.params, power, yaw if foot == "right" else -yaw)
        if foot == "left":
            frames = [(t, _mirror(q)) for t, q in frames]
        self._frames = frames
        self._from = measured_angles(perception)
        scale = np.full(len(MOTORS), self.params.gain_scale)
        for m in (("rle1", "rle4") if foot == "right" else ("lle1", "lle4")):
            scale[_INDEX[m]] *= self.params.kick_gain     # the striking hip and knee
        self._kp, self._kd = KP * scale, KD * np.sqrt(scale)
        self._t = 0.0
        self.foot = foot
        self.done = False

    def targets(self) -> np.ndarray:
        """The joint targets at the current time of the motion."""
        return self._reference()[0]

    def _reference(self) -> tuple[np.ndarray, np.ndarray]:
        """The joint targets and their rates (rad, rad/s) at the current time of the motion."""
        assert self._from is not None
        prev, t = self._from, self._t
        for dur, q in self._frames:
            if t < dur:
                s = 0.5 - 0.5 * math.cos(math.pi * t / dur)
                rate = 0.5 * math.pi / dur * math.sin(math.pi * t / dur)
                return prev + s * (q - prev), rate * (q - prev)
            t -= dur
            prev = q
        return prev, np.zeros_like(prev)

    def step(self, perception: Perception) -> str:
        if self.done:
            raise LeagueError("kick: step() without a running kick (start() it first)")
        self._t += CYCLE_S
        q, dq = self._reference()
        roll, pitch = torso_tilt(perception)
        gyro = perception.gyros.get("torso_gyro", (0.0, 0.0, 0.0))
        p = self.params
        ankle_roll, ankle_pitch = ("lle6", "lle5") if self.foot == "right" else ("rle6", "rle5")
        # a positive ankle angle turns the shank back towards -roll / -pitch (foot on the ground)
        q[_INDEX[ankle_roll]] += p.tilt_gain * roll + p.rate_gain * gyro[0]
        q[_INDEX[ankle_pitch]] += p.tilt_gain * pitch + p.rate_gain * gyro[1]
        hip_roll, hip_pitch = ("lle2", "lle1") if self.foot == "right" else ("rle2", "rle1")
        q[_INDEX[hip_roll]] += p.hip_roll_gain * roll
        q[_INDEX[hip_pitch]] += p.hip_pitch_gain * pitch
        if self._t >= sum(d for d, _ in self._frames) - 1e-9:
            self.done = True
        # the targets' own rates go out as the PD's dq: the damping follows the motion instead
        # of braking it (a fast strike lags its keyframes by ~0.1 s without)
        kp, kd = self._kp, self._kd
        return effectors.message(*(
            effectors.motor(m, float(q[k]), float(dq[k]), float(kp[k]), float(kd[k]))
            for k, m in enumerate(MOTORS)))


def torso_tilt(perception: Perception) -> tuple[float, float]:
    """The torso's roll and pitch (rad) from its ``quat`` perceptor."""
    w, x, y, z = perception.orientations["torso_quat"]
    roll = math.atan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y))
    pitch = math.asin(max(-1.0, min(1.0, 2 * (w * y - z * x))))
    return roll, pitch


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
        """Take this cycle's sighting (if any); returns the ball's body-frame (x, y), m."""
        seen = seen_ball_world(perception)
        if seen is not None:
            self.world, self.age_s = seen, 0.0
        else:
            self.age_s += CYCLE_S
        self.body = None if self.world is None else to_body(perception, self.world[:2])
        return self.body


# -- the approach that aims the kick ---------------------------------------------------------
#: how close to the kick spot (m) and to the asked heading (rad) the robot must be to kick
SPOT_TOLERANCE_X = 0.07
SPOT_TOLERANCE_Y = 0.05
HEADING_TOLERANCE = 0.12


def kick_foot(ball: tuple[float, float]) -> str:
    """The foot on the ball's side."""
    return "left" if ball[1] > 0 else "right"


def spot_error(ball: tuple[float, float], direction: float,
               params: KickParams = LEAGUE_KICK) -> tuple[float, float, float]:
    """How far the robot is from kicking ``ball`` (body frame) along ``direction``: the ball's
    offset from the kick spot in the frame turned by ``direction`` (ahead, left), and the
    heading error (rad)."""
    c, s = math.cos(direction), math.sin(direction)
    bx, by = c * ball[0] + s * ball[1], -s * ball[0] + c * ball[1]
    side = 1.0 if by > 0 else -1.0
    return bx - params.spot_x, by - side * params.spot_y, direction


def in_kick_spot(ball: tuple[float, float], direction: float,
                 params: KickParams = LEAGUE_KICK) -> bool:
    ex, ey, eh = spot_error(ball, direction, params)
    return (abs(ex) <= SPOT_TOLERANCE_X and abs(ey) <= SPOT_TOLERANCE_Y
            and abs(eh) <= HEADING_TOLERANCE)


def approach_command(ball: tuple[float, float], direction: float,
                     params: KickParams = LEAGUE_KICK,
                     speed: float = 0.35) -> tuple[float, float, float]:
    """A walk command (vx, vy, turn; body frame) that brings the kick spot onto ``ball`` while
    turning to face ``direction``: far away it walks at the ball and turns, near it it
    steps sideways/back into the spot (a proportional controller in the direction's frame,
    with the heading turned first when the error is large)."""
    ex, ey, eh = spot_error(ball, direction, params)
    dist = math.hypot(ball[0], ball[1])
    turn = float(np.clip(1.5 * eh, -0.8, 0.8))
    if dist > 0.9:
        # far: walk to a point behind the ball on the kick line
        c, s = math.cos(direction), math.sin(direction)
        tx = ball[0] - c * (params.spot_x + 0.25)
        ty = ball[1] - s * (params.spot_x + 0.25)
        head = math.atan2(ty, tx)
        turn = float(np.clip(1.5 * head, -0.8, 0.8))
        vx = speed * max(0.0, math.cos(head))
        return vx, 0.0, turn
    # near: correct along the kick frame, rotated back into the body frame
    c, s = math.cos(direction), math.sin(direction)
    ux = float(np.clip(1.2 * ex, -0.2, 0.25))
    uy = float(np.clip(1.5 * ey, -0.12, 0.12))
    if abs(eh) > 0.4:   # turn first when the heading is far off (sideways walking is slow)
        ux, uy = min(ux, 0.0) * 0.5, uy * 0.5
    return c * ux - s * uy, s * ux + c * uy, turn
