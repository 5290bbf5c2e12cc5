"""Vectorised walk/kick/fall state of all players: ``Bodies.step`` runs once per env cycle."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

import portable_math as pm

from .errors import StepInputError
from .profile import Profile
from .walk import apply_envelope, compose, omni_displacement, track

__all__ = ["Bodies", "StepResult"]

_EPS = 1e-9
_object_new = object.__new__


@dataclass(frozen=True)
class StepResult:
    """What the bodies did during one cycle (arrays of length n, body frame at cycle start).

    Attributes:
        delta_pose: (n, 3) true displacement (dx m, dy m, dpsi rad) over dt, seed 001 eq. 4.
        velocity: (n, 3) body-frame velocity at the end of the cycle (m/s, m/s, rad/s).
        odometry: (n, 3) displacement the walking engine *believes* it made (slip, noise).
        kick_now: (n,) bool, a kick's foot-ball contact happens this cycle.
        kick_distance: (n,) metres the ball should roll (spread applied; 0 where no kick).
        kick_direction: (n,) rad, body frame, direction of the kicked ball (spread applied).
        fallen: (n,) bool, falling, lying or getting up at the end of the cycle.
        can_act: (n,) bool, walk and kick commands are accepted next cycle.
        fell: (n,) bool, a fall started this cycle.
    """

    delta_pose: np.ndarray
    velocity: np.ndarray
    odometry: np.ndarray
    kick_now: np.ndarray
    kick_distance: np.ndarray
    kick_direction: np.ndarray
    fallen: np.ndarray
    can_act: np.ndarray
    fell: np.ndarray


class Bodies:
    """Locomotion state of ``n_players`` humanoids sharing one :class:`Profile`.

    Model (all per player, vectorised, documented in ``docs/locomotion.md``):

    * **Walk.** The body moves at a velocity held constant during a step of period
      ``T = profile.step_period`` and displaces exactly as seed 001 eq. 4 says. At each step
      boundary the latest command is mapped through the measured tracking curves, limited by
      the combined envelope, then moved towards by at most ``accel * T`` per axis (and the
      envelope is applied again). A player standing still starts its first step at once.
    * **Falls.** (i) a collision impulse ``J`` (N*s) topples with probability
      ``clip((J - J_lo) / (J_hi - J_lo), 0, 1)``, ``J_lo/J_hi`` = mass x weakest/strongest push
      speed; (ii) a push (:meth:`push`, body-frame velocity change) topples when it exceeds
      the direction-dependent push threshold (an ellipse through the forward, backward and
      side thresholds); (iii) a change demanded at a step boundary larger than
      ``command_jump_threshold`` (envelope-normalised units) topples with probability
      ``command_jump_fall_probability``. A fallen player is still for ``fall_duration +
      getup_duration`` seconds and cannot act; a kick in progress is cancelled.
    * **Kicks.** A request with power > 0 from a player that can act starts the kick; the
      player stands still for ``kick_duration``; contact happens ``kick_prep_time`` after the
      request. Distance = power x truncated normal(mean, std) in [min, max]; direction =
      aim + normal(0, ``profile.kick_direction_std``). A request aimed more than
      ``kick_max_angle`` off the heading does not start (a forward-kicking body turns, or
      walks round the ball, first; at pi, the default, every aim starts).
    * **Odometry.** ``odometry = delta_pose * odometry_scale * (1 + odometry_noise * N(0,1))``
      per channel (seed 000 eqs. 2-3: the engine over-reports when the feet slip).

    Randomness comes only from the ``rng`` passed to :meth:`step`.
    """

    def __init__(self, profile: Profile, n_players: int) -> None:
        """Args: profile: validated robot profile; n_players: number of bodies (>= 1)."""
        if not isinstance(profile, Profile):
            raise StepInputError("profile", type(profile).__name__, "must be a locomotion.Profile")
        if (
            isinstance(n_players, bool)
            or not isinstance(n_players, (int, np.integer))
            or n_players < 1
        ):
            raise StepInputError("n_players", n_players, "must be a positive integer")
        self.profile = profile
        self.n = int(n_players)
        p = profile
        self._T = float(p.step_period)
        self._env = (
            p.envelope_vx_forward,
            p.envelope_vx_backward,
            p.envelope_vy,
            p.envelope_turn,
            p.envelope_exponent,
        )
        self._dv = np.asarray(p.accel) * self._T  # max velocity change per step
        self._lim_fwd = np.array([p.envelope_vx_forward, p.envelope_vy, p.envelope_turn])
        self._lim_back = np.array([p.envelope_vx_backward, p.envelope_vy, p.envelope_turn])
        self._j_lo = p.impact_fall_impulse_low
        self._j_hi = p.impact_fall_impulse_high
        self._down_time = p.fall_duration + p.getup_duration
        self._kick_sigma = p.kick_direction_std
        # None: every aim kicks (the omnidirectional kick; no extra work per kick)
        self._kick_max_angle = p.kick_max_angle if p.kick_max_angle < math.pi else None
        self._odo_scale = np.asarray(p.odometry_scale, dtype=np.float64)
        self._odo_noise = np.asarray(p.odometry_noise, dtype=np.float64)
        self._odo_noisy = bool(np.any(self._odo_noise > 0))
        self.reset()

    # ------------------------------------------------------------------ state
    def reset(self) -> None:
        """All players standing, still, able to act, at the start of a step."""
        n = self.n
        self.velocity = np.zeros((n, 3))
        self.phase = np.full(n, self._T)  # time since the last step boundary (s)
        self.down_left = np.zeros(n)  # remaining fallen + get-up time (s)
        self.kick_elapsed = np.full(n, -1.0)  # time since kick start (s); < 0: no kick
        self.kick_power = np.zeros(n)
        self.kick_aim = np.zeros(n)
        self._push = np.zeros((n, 2))
        self._pushed = False
        self._n_down = 0
        self._n_kicking = 0
        self._cache = np.zeros((n, 3))
        self._cache_dt = -1.0
        self._all_true = np.ones(n, dtype=bool)
        self._all_false = np.zeros(n, dtype=bool)
        self._all_true.setflags(write=False)
        self._all_false.setflags(write=False)

    @property
    def fallen(self) -> np.ndarray:
        """(n,) bool: falling, lying or getting up."""
        return self.down_left > 0.0

    @property
    def kicking(self) -> np.ndarray:
        """(n,) bool: a kick motion is in progress."""
        return self.kick_elapsed >= 0.0

    @property
    def can_act(self) -> np.ndarray:
        """(n,) bool: neither fallen nor kicking."""
        return (self.down_left <= 0.0) & (self.kick_elapsed < 0.0)

    def push(self, index: int | np.ndarray, dv: np.ndarray) -> None:
        """Queue a push: a body-frame velocity change (m/s, shape (2,) or (k, 2)) to ``index``.

        It is evaluated against the direction-dependent push thresholds in the next
        :meth:`step`; pushes queued for one player in one cycle add up.
        """
        dv = np.asarray(dv, dtype=np.float64)
        idx = np.atleast_1d(np.asarray(index))
        if dv.shape[-1:] != (2,) or not np.all(np.isfinite(dv)):
            raise StepInputError("dv", dv.tolist(), "must be finite with shape (2,) or (k, 2)")
        if idx.size and (idx.min() < 0 or idx.max() >= self.n):
            raise StepInputError("index", idx.tolist(), f"must lie in [0, {self.n})")
        np.add.at(self._push, idx, np.broadcast_to(dv, (idx.size, 2)))
        self._pushed = True

    def push_threshold(self, direction: np.ndarray) -> np.ndarray:
        """Push speed (m/s) that topples a standing body pushed towards ``direction`` (rad,
        body frame): an ellipse per half-plane through the forward/backward/side thresholds."""
        p = self.profile
        c = np.cos(direction)
        s = np.sin(direction)
        ax = np.where(c >= 0.0, p.push_fall_speed_forward, p.push_fall_speed_backward)
        return 1.0 / np.sqrt((c / ax) ** 2 + (s / p.push_fall_speed_side) ** 2)

    # ------------------------------------------------------------------ step
    def step(
        self,
        walk_cmd: np.ndarray,
        kick_request: np.ndarray,
        kick_power: np.ndarray,
        kick_dir: np.ndarray,
        impacts: np.ndarray,
        rng: np.random.Generator,
        dt: float = 0.02,
    ) -> StepResult:
        """Advance every body by ``dt`` seconds (0 < dt <= step_period).

        Args:
            walk_cmd: (n, 3) body-frame command (vx m/s, vy m/s, vturn rad/s).
            kick_request: (n,) bool; a kick starts where True, power > 0 and the player can act.
            kick_power: (n,) in [0, 1]; kick_dir: (n,) aim (rad, body frame).
            impacts: (n,) collision impulse magnitude (N*s) taken during the last cycle.
            rng: the env's numpy Generator (the only source of randomness).
            dt: cycle length (s).

        The steps below run in this order, and so draw from ``rng`` in this order: falls from
        collisions and pushes, kick starts, the walk (and falls from command jumps at step
        boundaries), kick contact, odometry noise, fall timers.
        """
        walk_cmd, kick_request, kick_power, kick_dir, impacts = self._checked(
            walk_cmd, kick_request, kick_power, kick_dir, impacts, dt
        )
        any_down = self._n_down > 0
        up = self.down_left <= 0.0 if any_down else self._all_true
        fell, fell_any = self._topple(impacts, up, rng)
        kicking, kick_active = self._start_kicks(
            kick_request, kick_power, kick_dir, up, any_down, fell, fell_any
        )
        all_walk = not (any_down or fell_any or kick_active)
        if all_walk:
            walking = self._all_true
        else:
            walking = up
            if fell_any:
                walking = walking & ~fell
            if kick_active:
                walking = walking & ~kicking
        delta, fell, fell_any = self._walk(walk_cmd, walking, all_walk, fell, fell_any, rng, dt)
        kick_now, kick_distance, kick_direction = self._kick_contact(
            kick_active, fell, fell_any, rng, dt
        )
        odometry = self._odometry(delta, rng)
        fallen = self._fall_timers(any_down, fell, fell_any, dt)
        kicking_after = self.kick_elapsed >= 0.0 if self._n_kicking else self._all_false
        # = StepResult(...), without the frozen dataclass's nine object.__setattr__ calls
        result = _object_new(StepResult)
        result.__dict__.update(
            delta_pose=delta,
            velocity=self.velocity.copy(),
            odometry=odometry,
            kick_now=kick_now,
            kick_distance=kick_distance,
            kick_direction=kick_direction,
            fallen=fallen.copy(),
            can_act=~(fallen | kicking_after),
            fell=fell.copy(),
        )
        return result

    def _checked(
        self,
        walk_cmd: np.ndarray,
        kick_request: np.ndarray,
        kick_power: np.ndarray,
        kick_dir: np.ndarray,
        impacts: np.ndarray,
        dt: float,
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """``step``'s inputs as float (bool) arrays of the right shapes, and ``dt`` in range."""
        n = self.n
        walk_cmd = np.asarray(walk_cmd, dtype=np.float64)
        if walk_cmd.shape != (n, 3):
            raise StepInputError("walk_cmd", walk_cmd.shape, f"must have shape ({n}, 3)")
        kick_request = np.asarray(kick_request, dtype=bool)
        kick_power = np.asarray(kick_power, dtype=np.float64)
        kick_dir = np.asarray(kick_dir, dtype=np.float64)
        impacts = np.asarray(impacts, dtype=np.float64)
        for name, arr in (
            ("kick_request", kick_request),
            ("kick_power", kick_power),
            ("kick_dir", kick_dir),
            ("impacts", impacts),
        ):
            if arr.shape != (n,):
                raise StepInputError(name, arr.shape, f"must have shape ({n},)")
        T = self._T
        if not 0.0 < dt <= T + _EPS:
            raise StepInputError("dt", dt, f"must lie in (0, step_period = {T}] s")
        return walk_cmd, kick_request, kick_power, kick_dir, impacts

    def _topple(
        self, impacts: np.ndarray, up: np.ndarray, rng: np.random.Generator
    ) -> tuple[np.ndarray, bool]:
        """Falls from collisions and pushes, decided at the start of the cycle: (fell, any)."""
        fell = self._all_false
        fell_any = False
        if impacts.max() > self._j_lo:
            prob = np.clip((impacts - self._j_lo) / max(self._j_hi - self._j_lo, _EPS), 0.0, 1.0)
            fell = (impacts > self._j_lo) & up & (rng.random(self.n) < prob)
            fell_any = bool(np.count_nonzero(fell))
        if self._pushed:
            spd = np.hypot(self._push[:, 0], self._push[:, 1])
            thr = self.push_threshold(pm.arctan2(self._push[:, 1], self._push[:, 0]))
            fell = fell | (up & (spd >= thr) & (spd > 0.0))
            fell_any = bool(np.count_nonzero(fell))
            self._push[:] = 0.0
            self._pushed = False
        return fell, fell_any

    def _start_kicks(
        self,
        kick_request: np.ndarray,
        kick_power: np.ndarray,
        kick_dir: np.ndarray,
        up: np.ndarray,
        any_down: bool,
        fell: np.ndarray,
        fell_any: bool,
    ) -> tuple[np.ndarray, bool]:
        """Start the requested kicks of players that can act: (kicking, any kicking)."""
        if not (self._n_kicking or np.count_nonzero(kick_request)):
            return self._all_false, False
        start = kick_request & (kick_power > 0.0) & (self.kick_elapsed < 0.0)
        if self._kick_max_angle is not None:
            off = np.abs(np.remainder(kick_dir + math.pi, 2.0 * math.pi) - math.pi)
            start &= off <= self._kick_max_angle
        if any_down:
            start &= up
        if fell_any:
            start &= ~fell
        if np.count_nonzero(start):
            self.kick_elapsed[start] = 0.0
            self.kick_power[start] = np.clip(kick_power[start], 0.0, 1.0)
            self.kick_aim[start] = kick_dir[start]
        kicking = self.kick_elapsed >= 0.0
        return kicking, bool(np.count_nonzero(kicking))

    def _walk(
        self,
        walk_cmd: np.ndarray,
        walking: np.ndarray,
        all_walk: bool,
        fell: np.ndarray,
        fell_any: bool,
        rng: np.random.Generator,
        dt: float,
    ) -> tuple[np.ndarray, np.ndarray, bool]:
        """The walk: constant velocity within a step (eq. 4), the command taken at step
        boundaries, where too big a change may topple. Updates ``velocity`` and ``phase``;
        returns (delta_pose, fell, any fell)."""
        T = self._T
        vel = self.velocity
        phase = self.phase
        boundary = phase + dt >= T - _EPS
        if not all_walk:
            boundary &= walking
        if dt != self._cache_dt:  # displacement over dt at the current velocities
            self._cache = omni_displacement(vel, dt)
            self._cache_dt = dt
        if np.count_nonzero(boundary):
            tb = np.where(boundary, np.maximum(T - phase, 0.0), dt)
            target = apply_envelope(track(walk_cmd, self.profile.tracking), *self._env)
            change = target - vel
            lim = np.where(change[:, :1] >= 0.0, self._lim_fwd, self._lim_back)
            jump = np.sqrt(np.sum((change / lim) ** 2, axis=1))
            risky = boundary & (jump > self.profile.command_jump_threshold)
            if np.count_nonzero(risky):
                fell = fell | (
                    risky & (rng.random(self.n) < self.profile.command_jump_fall_probability)
                )
                fell_any = bool(np.count_nonzero(fell))
            new_vel = apply_envelope(vel + np.clip(change, -self._dv, self._dv), *self._env)
            if (tb < dt - _EPS).any():  # a boundary inside the cycle: split it exactly
                d1 = omni_displacement(vel, tb)
                vel = np.where(boundary[:, None], new_vel, vel)
                delta = compose(d1, omni_displacement(vel, dt - tb))
            else:  # every boundary falls at the end of the cycle (T a multiple of dt)
                delta = self._cache.copy()
                vel = np.where(boundary[:, None], new_vel, vel)
            phase = np.where(boundary, np.maximum(phase + dt - T, 0.0), phase + dt)
            self._cache_dt = -1.0
        else:
            delta = self._cache.copy()
            phase = phase + dt
        if not all_walk or fell_any:
            moving = walking & ~fell if fell_any else walking
            mcol = moving[:, None]
            delta *= mcol
            # the cache stays valid: rows of bodies that stop are masked until their next
            # walking cycle, which is always a step boundary (phase = T below)
            vel = vel * mcol
            phase = np.where(moving, phase, T)
        self.phase = phase
        self.velocity = vel
        return delta, fell, fell_any

    def _kick_contact(
        self,
        kick_active: bool,
        fell: np.ndarray,
        fell_any: bool,
        rng: np.random.Generator,
        dt: float,
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Kick contact and end (a fall cancels the kick): (kick_now, distance, direction)."""
        n = self.n
        if fell_any:
            self.kick_elapsed[fell] = -1.0
        kick_now = np.zeros(n, dtype=bool)
        kick_distance = np.zeros(n)
        kick_direction = np.zeros(n)
        if not kick_active:
            self._n_kicking = 0
            return kick_now, kick_distance, kick_direction
        p = self.profile
        e0 = self.kick_elapsed
        prep = p.kick_prep_time
        # e0 < 0 where no kick is in progress
        if prep <= _EPS:
            kick_now = (e0 >= 0.0) & (e0 <= _EPS)
        else:
            kick_now = (e0 <= prep + _EPS) & (e0 > max(prep + _EPS - dt, -0.5))
        if np.count_nonzero(kick_now):
            k = int(np.count_nonzero(kick_now))
            dist = rng.normal(p.kick_distance_mean, p.kick_distance_std, k)
            dist = np.clip(dist, p.kick_distance_min, p.kick_distance_max)
            kick_distance[kick_now] = self.kick_power[kick_now] * dist
            kick_direction[kick_now] = self.kick_aim[kick_now] + rng.normal(
                0.0, self._kick_sigma, k
            )
        e1 = e0 + dt
        e1[(e0 < 0.0) | (e1 >= p.kick_duration - _EPS)] = -1.0
        self.kick_elapsed = e1
        self._n_kicking = int(np.count_nonzero(e1 >= 0.0))
        return kick_now, kick_distance, kick_direction

    def _odometry(self, delta: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        """What the walking engine believes it moved: scaled, with per-channel noise."""
        odometry = delta * self._odo_scale
        if self._odo_noisy:
            odometry *= 1.0 + self._odo_noise * rng.standard_normal((self.n, 3))
        return odometry

    def _fall_timers(
        self, any_down: bool, fell: np.ndarray, fell_any: bool, dt: float
    ) -> np.ndarray:
        """Count the fallen players' down time; start it for the new falls. Returns fallen."""
        if not (any_down or fell_any):
            return self._all_false
        left = self.down_left - dt
        if fell_any:
            left[fell] = self._down_time
        left[left <= _EPS] = 0.0
        self.down_left = left
        fallen = left > 0.0
        self._n_down = int(np.count_nonzero(fallen))
        return fallen
