"""Vectorised walk/kick/fall state of all players: ``Bodies.step`` runs once per env cycle."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

import portable_math as pm

from .errors import StepInputError
from .profile import Profile

__all__ = ["Bodies", "StepResult"]

_EPS = 1e-9
_object_new = object.__new__
_NO_DRAWS = np.empty(0)


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
        self._j_lo = p.impact_fall_impulse_low
        self._kick_sigma = p.kick_direction_std
        self._odo_noise = np.asarray(p.odometry_noise, dtype=np.float64)
        self._odo_noisy = bool(np.any(self._odo_noise > 0))
        # the profile's numbers the compiled step reads, in ``step_kernel``'s P_* order (a
        # kick_max_angle of pi or more: every aim kicks, the kernel skips the test)
        self._params = np.array([
            self._T, p.envelope_vx_forward, p.envelope_vx_backward, p.envelope_vy,
            p.envelope_turn, p.envelope_exponent, self._j_lo, p.impact_fall_impulse_high,
            p.command_jump_threshold, p.command_jump_fall_probability,
            p.fall_duration + p.getup_duration, self._kick_sigma, p.kick_max_angle,
            p.kick_prep_time, p.kick_duration, p.kick_distance_mean, p.kick_distance_std,
            p.kick_distance_min, p.kick_distance_max], dtype=np.float64)
        # its V_* rows: max velocity change per step, the envelope's forward and backward
        # limits (vx, vy, turn), the odometry scale
        self._vectors = np.array([
            np.asarray(p.accel) * self._T,
            [p.envelope_vx_forward, p.envelope_vy, p.envelope_turn],
            [p.envelope_vx_backward, p.envelope_vy, p.envelope_turn],
            p.odometry_scale], dtype=np.float64)
        self._tables = _padded_tables(p.tracking)
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
        self._counts = np.zeros(9, dtype=np.int64)  # bodies down, kicking; the stages' flags
        self._flags = np.zeros((3, n), dtype=bool)  # the stages' per-body flags
        self._scratch = np.zeros((4, n))  # the stages' per-body numbers
        self._cache = np.zeros((n, 3))  # displacement over _cache_dt at the current velocities
        self._cache_dt = np.full(1, -1.0)  # -1: the cache is invalid
        self._all_true = np.ones(n, dtype=bool)
        self._all_true.setflags(write=False)
        # writable like the masks of real pushes: numba compiles per array type (read-only
        # is another), and a second compile would land in a match's cycle
        self._no_push = np.zeros(n, dtype=bool)

    def prepare(self) -> None:
        """Compile the step's kernel now (or load it from numba's disk cache), for the array
        types the env hands it, on a throwaway body: the first compile takes seconds, which
        should not fall into a match's cycle (its stall watchdog times each one). Touches
        nothing of this body and no generator of the caller's."""
        n = self.n
        Bodies(self.profile, n).step(np.zeros((n, 3)), np.zeros(n, dtype=bool), np.zeros(n),
                                     np.zeros(n), np.zeros(n), np.random.default_rng(0))

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
        boundaries), kick contact, odometry noise, fall timers. A compiled kernel
        (``step_kernel.step_bodies``) runs them, stopping where it needs random numbers that
        depend on its own work so far; they are drawn here and it goes on.
        """
        walk_cmd, kick_request, kick_power, kick_dir, impacts = self._checked(
            walk_cmd, kick_request, kick_power, kick_dir, impacts, dt
        )
        k = _kernel()
        pushed = self._pushed
        push_fell = self._push_fell(self.down_left <= 0.0 if self._counts[k.C_DOWN] else
                                    self._all_true) if pushed else self._no_push
        n = self.n
        delta = np.empty((n, 3))
        odometry = np.empty((n, 3))
        kick_now = np.empty(n, dtype=bool)
        kick_distance = np.empty(n)
        kick_direction = np.empty(n)
        fallen = np.empty(n, dtype=bool)
        fell = np.empty(n, dtype=bool)
        can_act = np.empty(n, dtype=bool)
        # the draws, in the NumPy step's order: impacts (known now), command jumps and kicks
        # (when the kernel asks), odometry noise (last)
        draws = rng.random(n) if impacts.max() > self._j_lo else _NO_DRAWS
        stage = k.START
        while True:
            stage = k.step_bodies(
                stage, draws, walk_cmd, kick_request, kick_power, kick_dir, impacts, push_fell,
                pushed, float(dt), self._params, self._tables, self._vectors, self.velocity,
                self.phase, self.down_left, self.kick_elapsed, self.kick_power, self.kick_aim,
                self._cache, self._cache_dt, self._counts, self._flags, self._scratch, delta,
                odometry, kick_now, kick_distance, kick_direction, fallen, fell, can_act)
            if stage == k.NEED_JUMP_DRAWS:
                draws, stage = rng.random(n), k.AFTER_JUMP_DRAWS
            elif stage == k.NEED_KICK_DRAWS:
                p, kicks = self.profile, int(self._counts[k.F_KICKS])
                draws = np.concatenate((rng.normal(p.kick_distance_mean, p.kick_distance_std,
                                                   kicks),
                                        rng.normal(0.0, self._kick_sigma, kicks)))
                stage = k.AFTER_KICK_DRAWS
            else:
                break
        if self._odo_noisy:
            odometry *= 1.0 + self._odo_noise * rng.standard_normal((n, 3))
        # = StepResult(...), without the frozen dataclass's nine object.__setattr__ calls
        result = _object_new(StepResult)
        result.__dict__.update(
            delta_pose=delta,
            velocity=self.velocity.copy(),
            odometry=odometry,
            kick_now=kick_now,
            kick_distance=kick_distance,
            kick_direction=kick_direction,
            fallen=fallen,
            can_act=can_act,
            fell=fell,
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
        """``step``'s inputs as contiguous float (bool) arrays of the right shapes, and ``dt``
        in range."""
        n = self.n
        walk_cmd = np.ascontiguousarray(walk_cmd, dtype=np.float64)
        if walk_cmd.shape != (n, 3):
            raise StepInputError("walk_cmd", walk_cmd.shape, f"must have shape ({n}, 3)")
        kick_request = np.ascontiguousarray(kick_request, dtype=bool)
        kick_power = np.ascontiguousarray(kick_power, dtype=np.float64)
        kick_dir = np.ascontiguousarray(kick_dir, dtype=np.float64)
        impacts = np.ascontiguousarray(impacts, dtype=np.float64)
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

    def _push_fell(self, up: np.ndarray) -> np.ndarray:
        """Falls from the pushes queued since the last step (no random draw); clears them."""
        spd = np.hypot(self._push[:, 0], self._push[:, 1])
        thr = self.push_threshold(pm.arctan2(self._push[:, 1], self._push[:, 0]))
        fell = up & (spd >= thr) & (spd > 0.0)
        self._push[:] = 0.0
        self._pushed = False
        return fell


def _padded_tables(tracking: tuple[tuple[np.ndarray, np.ndarray], ...]) -> np.ndarray:
    """The three tracking curves as one (3, 2, m) array, each padded by repeating its last
    point (np.interp's answer does not change)."""
    m = max(len(xp) for xp, _ in tracking)
    out = np.empty((3, 2, m))
    for k, (xp, fp) in enumerate(tracking):
        out[k, 0, :len(xp)] = xp
        out[k, 0, len(xp):] = xp[-1]
        out[k, 1, :len(fp)] = fp
        out[k, 1, len(fp):] = fp[-1]
    return out


def _kernel():
    """The compiled step (imported on first use: numba's import costs a few tenths of a s)."""
    from . import step_kernel

    return step_kernel
