# Over 500 lines because it is one algorithm: the docstring below is its specification (~90
# lines), and BatchLocalizer's steps (predict, sightings, likelihood, correct, resample,
# sensor reset) work on one set of (agents, particles) arrays; its parameters stay beside it.
"""Monte Carlo localization (seed 000 §3 / 001 §3) for ``vision`` mode, batched over agents.

Each agent keeps ``n_particles`` poses ``(x, y, psi)`` in its team frame with log-weights.
``BatchLocalizer`` holds the filters of several agents in one ``(A, N)`` set of arrays so a
team localizes all its agents in one numpy pass; every agent's filter is its own (its own
odometry, gyro and sightings, its own resampling and resets). ``Localizer`` is the same for
one agent.

The cycle (seed 000 §3):

- **Motion update** (every cycle, ``predict``): the walk engine's odometry ``(dx, dy, dpsi)``
  (body frame, it over-reports) is scaled per channel, ``d' = (alpha dx, beta dy, gamma dpsi)``
  (eq. 2; ``odometry_scale``, by default the inverse of the engine's 1.1, 1.1, 1.05), and
  applied to each particle in its own body frame (eq. 3) with process noise of standard
  deviation ``motion_noise_rel * |d'| + motion_noise_abs`` per channel. With ``use_gyro``
  (the default) and a gyro reading given, the gyro's heading change replaces ``gamma dpsi``
  (noise ``gyro_noise_rad``): it is the true turn plus 0.002 rad of noise and it feels what
  the walk engine does not (pushes, slips); odometry's turn is 5 % noise on a biased scale.
- **Sensor update** (vision cycles only, ``correct``): log-likelihood per particle, summed
  over independent sightings (eq. 1):

  * landmarks (identified: row k of ``teamenv.landmarks.landmarks(field, kind)``): distance
    ``-0.5 ((d_seen - d_pred) / sigma_d)^2`` with ``sigma_d = sigma_distance_rel * d_seen +
    sigma_distance_m``, where (``distance_model="ground"``, the default) ``d_seen = d cos(el)``
    is the ground distance of the sighting (independent of the camera height) and ``d_pred``
    the particle's ground distance to the landmark; ``distance_model="3d"`` compares the 3D
    distance with the particle's 3D distance from a camera ``camera_height`` above it. Bearing:
    a von Mises term ``kappa (cos(az_seen - az_pred) - 1)``, ``kappa = 1 / sigma_bearing^2``
    (the Gaussian of eq. 1 for small errors, without an angle wrap or an ``atan2``).
  * field lines: the seen lines' endpoints (as many as ``line_points``, the nearest first)
    are projected to the ground in the body frame (``d cos(el)``, ``az``) and placed on the
    pitch from each particle's pose; each point's distance ``r`` to the nearest painted line
    (``teamenv.landmarks.field_lines``; a precomputed distance grid of ``line_grid_m``
    cells, nearest cell) scores ``-0.5 line_weight (min(r, line_cap_m) / sigma_l)^2`` with
    ``sigma_l = sigma_line_m + sigma_line_rel * ground distance``. Endpoints clipped by the
    view cone lie on their line too, so every endpoint counts. ``line_weight`` (default 1:
    the points as independent sightings) can damp the term, since the two ends of one line
    are not independent and a point matches *any* line; the cap keeps one far-off point from
    vetoing a particle. The distance alone ignores which line a point belongs to, so lines
    sharpen a belief the landmarks have placed but cannot place it alone.

  Weights are log-weights (normalized to ``logsumexp = 0`` after each update).
- **Resampling**: O(N) low-variance (systematic) resampling, per agent, only when its
  effective sample size ``1 / sum(w^2)`` falls below ``resample_ess * N``.
- **Augmented MCL with sensor resetting** (seed 000 §3's Adaptive-MCL; Thrun, Burgard & Fox,
  Probabilistic Robotics, Table 8.3): the fit of each update is ``q = sum_i w_i
  exp(l_i / m)`` (the weighted mean of the per-sighting geometric-mean likelihood, ``m`` the
  number of sightings, lines counted with ``line_weight``, so that it does not depend on how
  many things are in view). ``w_slow`` and ``w_fast`` average it with ``alpha_slow`` and
  ``alpha_fast``; a share ``1 - w_fast / w_slow`` of the particles (none below
  ``min_reset_share``, the fit's own jitter: a well-placed belief that sees one far landmark
  would otherwise be smeared along that landmark's circle; at least ``lost_share`` while
  ``w_fast < lost_quality``; at most ``max_reset_share``) — the lowest-weighted — is
  replaced by poses computed from the current sightings, perturbed by
  ``reset_sigma_distance_rel`` and ``reset_sigma_bearing_deg`` (the seed adds noise to
  spread them):

  * two seen landmarks (a random pair per particle): the circle intersection (seed 000
    Fig. 1a), the two seen goal posts of one goal: the closed form of seed 002 §2.4
    (``strategy.perception.two_posts``); of the two mirror candidates the one off the pitch
    (more than ``field_margin_m`` out) is discarded, then the one whose two bearings give
    the less consistent heading;
  * one seen landmark: its distance and bearing with a heading drawn from the current
    belief (its circular mean, spread by the larger of ``reset_sigma_heading_deg`` and the
    belief's circular standard deviation).

  Reset particles are weighted by the same likelihood as the others (with the mean prior
  weight), so a wrong candidate loses. A referee's beam to an unknown pose makes the fit
  collapse, ``w_fast`` falls below ``w_slow`` and the resets relocalize the agent: no oracle.
  When the agent itself asked for a beam it knows the target: ``beamed(agent, pose)``.
- **Estimate**: the weighted mean position, the circular mean heading, the 3x3 weighted
  covariance of ``(x, y, wrap(psi - mean))``, and ``spread = sqrt(var x + var y)``.

Randomness only from the ``numpy.random.Generator`` given to the constructor (motion noise,
resampling offsets, reset choices and noise, the prior): the same generator state and inputs
give the same particles bit for bit.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, fields, replace
from functools import lru_cache
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

import portable_math as pm
from paramkit.checks import check_fields, in_range, invalid, non_negative, one_of, positive
from strategy.perception.two_posts import (
    on_field,
    two_landmark_candidates,
    two_post_candidates,
)
from teamenv.config import build_config
from teamenv.errors import ConfigError, TeamEnvError
from teamenv.field import FieldSpec, field_preset
from teamenv.landmarks import LANDMARK_KINDS, field_lines, landmarks

DISTANCE_MODELS = ("ground", "3d")


class LocalizationError(TeamEnvError, ValueError):
    """A localization parameter or input is not valid; the message names field and value."""


class LocalizationParamsError(LocalizationError, ConfigError):
    """A ``LocalizationParams`` value is not valid: a ``LocalizationError`` and, as every bad
    parameter, a ``ConfigError``."""


def _number(value: Any) -> bool:
    return not isinstance(value, bool) and isinstance(value, (int, float, np.integer,
                                                              np.floating)) \
        and math.isfinite(value)


@dataclass(frozen=True)
class LocalizationParams:
    """Parameters of the Monte Carlo localization (metres, radians unless ``_deg``).

    Particles: ``n_particles`` per agent (50: ``benchmarks/localization.py`` meets the error
    targets with 30 to 200 alike, and 50 keeps all 22 agents under 2 ms on vision cycles too;
    more particles only shave the rare worst cases).
    Motion (seed 000 eq. 2-3): ``odometry_scale`` (alpha, beta, gamma) multiplies the
    odometry's dx, dy, dpsi; process noise per cycle and channel ``motion_noise_rel * |d'| +
    motion_noise_abs``; ``use_gyro``: the gyro's heading change replaces dpsi when given, with
    noise ``gyro_noise_rad`` (SimSpark's gyro: 0.002 rad per cycle).
    Landmarks: ``distance_model`` ("ground": d cos(el) vs the ground distance; "3d": d vs the
    3D distance from the camera), ``sigma_distance_rel`` * distance + ``sigma_distance_m``,
    ``sigma_bearing_deg``.
    Lines: ``use_lines``, ``line_weight``, ``line_points`` (endpoints used per update, nearest
    first), ``sigma_line_m`` + ``sigma_line_rel`` * distance, ``line_cap_m``,
    ``line_grid_m`` (cell of the distance grid).
    Resampling: when the effective sample size is below ``resample_ess`` * N.
    Resetting (augmented MCL): ``alpha_slow`` < ``alpha_fast`` (per vision update),
    ``lost_quality`` / ``lost_share``, ``min_reset_share`` / ``max_reset_share`` (0: no
    sensor resetting), the noise added to sightings
    before resetting (``reset_sigma_distance_rel``, ``reset_sigma_bearing_deg``), the
    heading spread of one-landmark resets (``reset_sigma_heading_deg``), and
    ``field_margin_m`` (candidates farther out are rejected; particles are kept within it).
    Beams: ``beam_sigma_m``, ``beam_sigma_deg``: the spread around a known beam target.
    Outliers: ``landmark_outlier_cap`` (inf: none): each landmark sighting lowers a particle's
    log-likelihood by at most this much, so a misclassified or made-up sighting cannot outvote
    the rest (a Gaussian with a uniform floor); ``for_camera`` sets it for a camera that makes
    detection errors.
    """

    n_particles: int = field(default=50, metadata=in_range(1))
    odometry_scale: tuple[float, float, float] = field(
        default=(1.0 / 1.1, 1.0 / 1.1, 1.0 / 1.05), metadata=positive())
    use_gyro: bool = True
    motion_noise_rel: tuple[float, float, float] = field(default=(0.1, 0.1, 0.1),
                                                         metadata=non_negative())
    motion_noise_abs: tuple[float, float, float] = field(default=(0.004, 0.004, 0.004),
                                                         metadata=non_negative())
    gyro_noise_rad: float = field(default=0.002, metadata=positive())
    distance_model: str = field(default="ground", metadata=one_of(*DISTANCE_MODELS))
    sigma_distance_rel: float = field(default=0.003, metadata=non_negative())
    sigma_distance_m: float = field(default=0.06, metadata=positive())
    sigma_bearing_deg: float = field(default=1.5, metadata=positive())
    use_lines: bool = True
    line_weight: float = field(default=1.0, metadata=positive())
    line_points: int = field(default=8, metadata=non_negative())
    sigma_line_m: float = field(default=0.06, metadata=positive())
    sigma_line_rel: float = field(default=0.01, metadata=non_negative())
    line_cap_m: float = field(default=1.0, metadata=positive())
    line_grid_m: float = field(default=0.05, metadata=positive())
    resample_ess: float = field(default=0.5, metadata=in_range(0.0, 1.0, low_open=True))
    alpha_slow: float = field(default=0.05, metadata=in_range(0.0, 1.0, low_open=True))
    alpha_fast: float = field(default=0.5, metadata=in_range(0.0, 1.0, low_open=True))
    lost_quality: float = field(default=0.05, metadata=in_range(0.0, 1.0, high_open=True))
    # 0: no sensor resetting
    lost_share: float = field(default=0.5, metadata=in_range(0.0, 1.0))
    max_reset_share: float = field(default=0.5, metadata=in_range(0.0, 1.0))
    min_reset_share: float = field(default=0.1, metadata=in_range(0.0, 1.0))
    reset_sigma_distance_rel: float = field(default=0.002, metadata=non_negative())
    reset_sigma_bearing_deg: float = field(default=0.5, metadata=non_negative())
    reset_sigma_heading_deg: float = field(default=5.0, metadata=positive())
    field_margin_m: float = field(default=1.0, metadata=non_negative())
    beam_sigma_m: float = field(default=0.1, metadata=positive())
    beam_sigma_deg: float = field(default=5.0, metadata=positive())
    landmark_outlier_cap: float = field(default=math.inf, metadata=positive(infinite=True))

    def __post_init__(self) -> None:
        check_fields(self, LocalizationParamsError)
        if self.alpha_slow >= self.alpha_fast:
            raise invalid(self, "alpha_slow", f"< alpha_fast ({self.alpha_fast!r})",
                          LocalizationParamsError)
        if self.lost_share > self.max_reset_share:
            raise invalid(self, "lost_share", f"<= max_reset_share ({self.max_reset_share!r})",
                          LocalizationParamsError)

    @classmethod
    def from_overrides(cls, overrides: Mapping[str, Any]) -> LocalizationParams:
        """The defaults with ``overrides`` applied; an unknown key names the known ones."""
        values = {k: tuple(v) if isinstance(v, list) else v for k, v in overrides.items()}
        return build_config(cls, values, section="LocalizationParams",
                            error=LocalizationParamsError)


OUTLIER_CAP = 8.0
"""``for_camera``'s ``landmark_outlier_cap``: a sighting 4 standard deviations off costs its
full Gaussian penalty; one farther off is treated as an outlier. On the ``mj_noisy`` camera
(7 v 7, 20 s, ``benchmarks/localization.py``'s env scene) it takes the position error's p95
from 4.2 m to 0.12 m."""


def for_camera(params: LocalizationParams, camera: Any) -> LocalizationParams:
    """``params`` fitted to the camera a team is told about (``TeamContext.perception``, a
    ``teamenv.PerceptionConfig``): a camera that misses, misnames or makes up sightings gets the
    outlier cap (``OUTLIER_CAP``, unless one is set) and a distance sigma no smaller than 1.2 x
    the camera's distance noise. Other cameras leave ``params`` as they are."""
    if camera is None or not getattr(camera, "detection_errors", False):
        return params
    changes: dict[str, float] = {}
    if not math.isfinite(params.landmark_outlier_cap):
        changes["landmark_outlier_cap"] = OUTLIER_CAP
    rel = 1.2 * float(camera.distance_sigma_rel)
    if rel > params.sigma_distance_rel:
        changes["sigma_distance_rel"] = rel
    return replace(params, **changes) if changes else params


def _shaped(what: str, value: ArrayLike, shape: tuple[int, ...]) -> NDArray[np.float64]:
    """``value`` as a float array of ``shape`` (a leading 1-row form is accepted)."""
    arr = np.array(value, dtype=np.float64)
    if arr.size != math.prod(shape):
        raise LocalizationError(f"{what} must have shape {shape}, got {arr.shape}")
    return arr.reshape(shape)


class PoseEstimate(NamedTuple):
    """Pose ``(..., 3)`` = x, y, psi (team frame) and its covariance ``(..., 3, 3)``."""

    pose: NDArray[np.float64]
    covariance: NDArray[np.float64]

    @property
    def spread(self) -> NDArray[np.float64]:
        """Position spread ``sqrt(var x + var y)`` (m): the scalar confidence (small: sure)."""
        return np.sqrt(np.maximum(self.covariance[..., 0, 0] + self.covariance[..., 1, 1], 0.0))

    @property
    def heading_sigma(self) -> NDArray[np.float64]:
        """Heading standard deviation (rad)."""
        return np.sqrt(np.maximum(self.covariance[..., 2, 2], 0.0))


@lru_cache(maxsize=8)
def line_distance_grid(field: FieldSpec, cell_m: float = 0.05, margin_m: float = 3.0
                       ) -> tuple[NDArray[np.float32], float, float]:
    """The distance (m) from each cell centre to the nearest painted line of ``field``.

    Returns ``(grid, x0, y0)``: ``grid[iy, ix]`` is the distance at ``(x0 + ix cell_m,
    y0 + iy cell_m)``; the grid covers the pitch grown by ``margin_m``. Read-only, cached.
    """
    segs = np.asarray(field_lines(field), dtype=np.float64)
    x0, y0 = -field.half_length - margin_m, -field.half_width - margin_m
    nx = int(math.ceil(2.0 * (field.half_length + margin_m) / cell_m)) + 1
    ny = int(math.ceil(2.0 * (field.half_width + margin_m) / cell_m)) + 1
    xs = x0 + cell_m * np.arange(nx)
    grid = np.full((ny, nx), np.inf, dtype=np.float64)
    for row0 in range(0, ny, 256):
        ys = y0 + cell_m * np.arange(row0, min(ny, row0 + 256))
        px, py = np.meshgrid(xs, ys)
        best = grid[row0:row0 + len(ys)]
        for ax, ay, bx, by in segs:
            dx, dy = bx - ax, by - ay
            t = np.clip(((px - ax) * dx + (py - ay) * dy) / (dx * dx + dy * dy), 0.0, 1.0)
            np.minimum(best, np.hypot(px - ax - t * dx, py - ay - t * dy), out=best)
    out = grid.astype(np.float32)
    out.flags.writeable = False
    return out, x0, y0


@dataclass
class _Sightings:
    """One update's sightings of R agents, padded: landmarks (R, K) and line points (R, P)."""

    n_landmarks: NDArray[np.intp]       # (R,) landmarks seen
    lm_xy: NDArray[np.float64]          # (R, K, 2) their team-frame positions
    lm_index: NDArray[np.intp]          # (R, K) their rows in the landmark table
    lm_dist: NDArray[np.float64]        # (R, K) seen distance (ground or 3D: the model)
    lm_dz2: NDArray[np.float64]         # (R, K) (z - camera height)^2 (the 3D model)
    lm_az: NDArray[np.float64]          # (R, K) seen azimuth
    lm_cos: NDArray[np.float64]         # (R, K) cos(az) (0 where padding)
    lm_sin: NDArray[np.float64]         # (R, K) sin(az)
    lm_ground: NDArray[np.float64]      # (R, K) seen ground distance
    lm_inv_var: NDArray[np.float64]     # (R, K) 0.5 / sigma_d^2 (0 where padding)
    lm_kappa: NDArray[np.float64]       # (R, K) kappa (0 where padding)
    n_points: NDArray[np.intp]          # (R,) line points used
    pt_fwd: NDArray[np.float64]         # (R, P) body-frame ground point of a line
    pt_left: NDArray[np.float64]
    pt_inv_var: NDArray[np.float64]     # (R, P) 0.5 line_weight / sigma_l^2 (0: padding)
    weight: NDArray[np.float64]         # (R,) sightings, line points times line_weight

    def rows(self, rows: NDArray[np.intp]) -> _Sightings:
        return _Sightings(*(getattr(self, f.name)[rows] for f in fields(self)))


class BatchLocalizer:
    """Monte Carlo localization of ``n_agents`` agents at once (see the module docstring).

    Args:
        n_agents: how many independent filters (agent index 0..n_agents-1).
        field: the pitch (a ``FieldSpec`` or a preset name).
        landmark_kind: the landmark table of the observations ("simspark" or "mj").
        camera_height: the camera above the ground (m; used by ``distance_model="3d"``).
        params: ``LocalizationParams`` (None: the defaults).
        rng: the ``numpy.random.Generator`` all randomness comes from (required).

    The filters start from a uniform prior over the pitch (``reset``).
    """

    def __init__(self, n_agents: int, field: FieldSpec | str, landmark_kind: str = "simspark",
                 camera_height: float = 0.5, params: LocalizationParams | None = None,
                 rng: np.random.Generator | None = None) -> None:
        if isinstance(n_agents, bool) or not isinstance(n_agents, (int, np.integer)) \
                or n_agents < 1:
            raise LocalizationError(f"BatchLocalizer.n_agents: must be an int >= 1, got "
                                    f"{n_agents!r}")
        if landmark_kind not in LANDMARK_KINDS:
            raise LocalizationError(f"BatchLocalizer.landmark_kind: must be one of "
                                    f"{list(LANDMARK_KINDS)}, got {landmark_kind!r}")
        if not (_number(camera_height) and camera_height > 0):
            raise LocalizationError(f"BatchLocalizer.camera_height: must be a number > 0, got "
                                    f"{camera_height!r}")
        if params is None:
            params = LocalizationParams()
        if not isinstance(params, LocalizationParams):
            raise LocalizationError(f"BatchLocalizer.params: must be a LocalizationParams, got "
                                    f"{params!r}")
        if not isinstance(rng, np.random.Generator):
            raise LocalizationError(f"BatchLocalizer.rng: must be a numpy.random.Generator "
                                    f"(all randomness comes from it), got {rng!r}")
        self.n_agents = int(n_agents)
        self.field = field_preset(field)
        self.landmark_kind = landmark_kind
        self.camera_height = float(camera_height)
        self.params = params
        self.rng = rng
        self.n = int(params.n_particles)
        table = landmarks(self.field, landmark_kind)
        self.landmark_names = table.names
        self._lm = np.asarray(table.xyz, dtype=np.float64)
        # the two posts of one goal: the closed form of seed 002 resets from them
        self._same_goal = np.zeros((len(table), len(table)), dtype=bool)
        for end in ("own", "their"):
            if f"post_{end}_left" in table.names:
                i, j = table.index(f"post_{end}_left"), table.index(f"post_{end}_right")
                self._same_goal[i, j] = self._same_goal[j, i] = True
        p = params
        self._scale = np.asarray(p.odometry_scale, dtype=np.float64)
        self._noise_rel = np.asarray(p.motion_noise_rel, dtype=np.float64)
        self._noise_abs = np.asarray(p.motion_noise_abs, dtype=np.float64)
        self._kappa = 1.0 / math.radians(p.sigma_bearing_deg) ** 2
        self._xlim = self.field.half_length + p.field_margin_m
        self._ylim = self.field.half_width + p.field_margin_m
        if p.use_lines:
            grid, self._gx0, self._gy0 = line_distance_grid(self.field, p.line_grid_m)
            self._grid = grid.ravel()
            self._gny, self._gnx = grid.shape
        self._p = np.zeros((3, self.n_agents, self.n))
        self._logw = np.zeros((self.n_agents, self.n))
        self.w_slow = np.full(self.n_agents, np.nan)
        self.w_fast = np.full(self.n_agents, np.nan)
        self.quality = np.full(self.n_agents, np.nan)
        """The last update's fit ``q`` per agent (NaN before the first, or after a reset)."""
        self.resets = np.zeros(self.n_agents, dtype=np.int64)
        """Particles replaced by sensor resetting so far, per agent."""
        self._estimate: PoseEstimate | None = None
        # (log-weights, their exp): the log-weights change on vision cycles only, the
        # particles (hence the estimate) every cycle
        self._exp_memo: tuple[NDArray[np.float64], NDArray[np.float64]] | None = None
        self.reset()

    # -- state ------------------------------------------------------------------------------
    @property
    def particles(self) -> NDArray[np.float64]:
        """(A, N, 3) a copy of the particles ``x, y, psi``."""
        return np.moveaxis(self._p, 0, -1).copy()

    @property
    def weights(self) -> NDArray[np.float64]:
        """(A, N) the normalized weights."""
        w = pm.exp(self._logw - self._logw.max(axis=1, keepdims=True))
        return w / w.sum(axis=1, keepdims=True)

    def _exp_logw(self) -> NDArray[np.float64]:
        """``pm.exp(self._logw)`` (read-only), computed again only when they changed."""
        memo = self._exp_memo
        if memo is None or not np.array_equal(memo[0], self._logw):
            memo = self._exp_memo = (self._logw.copy(), pm.exp(self._logw))
            memo[1].setflags(write=False)
        return memo[1]

    def _rows(self, agents: ArrayLike | None) -> NDArray[np.intp] | slice:
        if agents is None:
            return slice(None)
        idx = np.asarray(agents).reshape(-1)
        if idx.size and not np.issubdtype(idx.dtype, np.integer):
            raise LocalizationError(f"agents: must be integer indices, got {agents!r}")
        idx = idx.astype(np.intp)
        if idx.size and (idx.min() < 0 or idx.max() >= self.n_agents):
            raise LocalizationError(f"agents: indices must lie in 0..{self.n_agents - 1}, "
                                    f"got {idx.tolist()}")
        if len(np.unique(idx)) != idx.size:
            raise LocalizationError(f"agents: each agent at most once, got {idx.tolist()}")
        if idx.size == self.n_agents and (idx == np.arange(self.n_agents)).all():
            return slice(None)
        return idx

    def _count(self, rows: NDArray[np.intp] | slice) -> int:
        return self.n_agents if isinstance(rows, slice) else len(rows)

    def reset(self, agents: ArrayLike | None = None) -> None:
        """A uniform prior over the pitch (and heading) for ``agents`` (None: all)."""
        rows = self._rows(agents)
        r = self._count(rows)
        u = self.rng.random((3, r, self.n))
        hl, hw = self.field.half_length, self.field.half_width
        self._p[:, rows] = np.stack(((2 * u[0] - 1) * hl, (2 * u[1] - 1) * hw,
                                     (2 * u[2] - 1) * np.pi))
        self._logw[rows] = -math.log(self.n)
        self.w_slow[rows] = self.w_fast[rows] = self.quality[rows] = np.nan
        self._estimate = None

    def beamed(self, agent: int, pose: ArrayLike,
               spread: float | tuple[float, float] | None = None) -> None:
        """Agent ``agent`` was beamed to ``pose`` (x, y, psi; team frame) on its own request:
        its particles are redrawn around it, Gaussian with ``spread`` = sigma (m) or
        (sigma m, sigma rad) (None: ``beam_sigma_m``, ``beam_sigma_deg``)."""
        if isinstance(agent, bool) or not isinstance(agent, (int, np.integer)) or \
                not 0 <= agent < self.n_agents:
            raise LocalizationError(f"beamed: agent must be an index in 0..{self.n_agents - 1}, "
                                    f"got {agent!r}")
        rows = int(agent)
        pose = np.asarray(pose, dtype=np.float64).reshape(-1)
        if pose.shape != (3,) or not np.isfinite(pose).all():
            raise LocalizationError(f"beamed: pose must be 3 finite numbers, got {pose!r}")
        if spread is None:
            s_xy, s_psi = self.params.beam_sigma_m, math.radians(self.params.beam_sigma_deg)
        elif np.ndim(spread) == 0:
            s_xy, s_psi = float(spread), math.radians(self.params.beam_sigma_deg)
        else:
            s_xy, s_psi = (float(v) for v in spread)
        if not (math.isfinite(s_xy) and math.isfinite(s_psi) and s_xy >= 0 and s_psi >= 0):
            raise LocalizationError(f"beamed: spread must be finite and >= 0, got {spread!r}")
        noise = self.rng.standard_normal((3, self.n)) * np.array([s_xy, s_xy, s_psi])[:, None]
        self._p[:, rows] = pose[:, None] + noise
        self._logw[rows] = -math.log(self.n)
        self.w_slow[rows] = self.w_fast[rows] = self.quality[rows] = np.nan
        self._estimate = None

    # -- motion -----------------------------------------------------------------------------
    def predict(self, agents: ArrayLike | None, odometry: ArrayLike,
                gyro: ArrayLike | None = None) -> None:
        """The motion update of ``agents`` (None: all, in order) from this cycle's odometry
        (R, 3) body-frame dx, dy, dpsi and, optionally, gyro (R,) heading changes."""
        rows = self._rows(agents)
        r = self._count(rows)
        d = _shaped("predict: odometry", odometry, (r, 3)) * self._scale
        if gyro is not None and self.params.use_gyro:
            d[:, 2] = _shaped("predict: gyro", gyro, (r,))
        if not np.isfinite(d).all():
            raise LocalizationError(f"predict: odometry and gyro must be finite, got {d!r}")
        sigma = np.abs(d) * self._noise_rel + self._noise_abs       # (R, 3)
        if gyro is not None and self.params.use_gyro:
            sigma[:, 2] = self.params.gyro_noise_rad
        step = self.rng.standard_normal((3, r, self.n))
        step *= sigma.T[:, :, None]
        step += d.T[:, :, None]
        p = self._p[:, rows]
        c, s = np.cos(p[2]), np.sin(p[2])
        p[0] += c * step[0] - s * step[1]
        p[1] += s * step[0] + c * step[1]
        p[2] += step[2]
        if not isinstance(rows, slice):
            self._p[:, rows] = p
        self._estimate = None

    # -- sensing ----------------------------------------------------------------------------
    def _sightings(self, lm: NDArray[np.float64], lines: NDArray[np.float64] | None
                   ) -> _Sightings:
        p = self.params
        r = lm.shape[0]
        present = lm[:, :, 0] > 0.5
        count = present.sum(axis=1)
        k = int(count.max()) if r else 0
        order = np.argsort(~present, axis=1, kind="stable")[:, :k]
        valid = np.arange(k) < count[:, None]
        d = np.take_along_axis(lm[:, :, 1], order, axis=1)
        az = np.take_along_axis(lm[:, :, 2], order, axis=1)
        el = np.take_along_axis(lm[:, :, 3], order, axis=1)
        ground = d * np.cos(el)
        xyz = self._lm[order]
        dz2 = (xyz[:, :, 2] - self.camera_height) ** 2
        seen = d if p.distance_model == "3d" else ground
        sigma = p.sigma_distance_rel * seen + p.sigma_distance_m
        inv_var = np.where(valid, 0.5 / (sigma * sigma), 0.0)
        kappa = np.where(valid, self._kappa, 0.0)
        cos_az, sin_az = np.where(valid, np.cos(az), 0.0), np.where(valid, np.sin(az), 0.0)

        n_points = np.zeros(r, dtype=np.intp)
        fwd = left = pt_inv = np.zeros((r, 0))
        if p.use_lines and lines is not None and lines.size and p.line_points:
            on = lines[:, :, 0] > 0.5
            g1 = lines[:, :, 1] * np.cos(lines[:, :, 3])
            g2 = lines[:, :, 4] * np.cos(lines[:, :, 6])
            g = np.concatenate((g1, g2), axis=1)
            a = np.concatenate((lines[:, :, 2], lines[:, :, 5]), axis=1)
            key = np.where(np.concatenate((on, on), axis=1), g, np.inf)
            n_points = np.minimum(2 * on.sum(axis=1), p.line_points)
            m = int(n_points.max()) if r else 0
            if m:
                pick = np.argsort(key, axis=1, kind="stable")[:, :m]
                g = np.take_along_axis(g, pick, axis=1)
                a = np.take_along_axis(a, pick, axis=1)
                ok = np.arange(m) < n_points[:, None]
                fwd, left = g * np.cos(a), g * np.sin(a)
                sl = p.sigma_line_m + p.sigma_line_rel * g
                pt_inv = np.where(ok, 0.5 * p.line_weight / (sl * sl), 0.0)
        return _Sightings(count, xyz[:, :, :2], order, seen, dz2, az, cos_az, sin_az, ground,
                          inv_var, kappa, n_points, fwd, left, pt_inv,
                          count + p.line_weight * n_points)

    def _loglik(self, x: NDArray, y: NDArray, h: NDArray, s: _Sightings) -> NDArray:
        """(R, N) log-likelihood of the particles (R, N) given the sightings."""
        c, sn = np.cos(h), np.sin(h)
        ll = np.zeros(x.shape)
        if s.lm_xy.shape[1]:
            dx = s.lm_xy[:, None, :, 0] - x[:, :, None]               # (R, N, K)
            dy = s.lm_xy[:, None, :, 1] - y[:, :, None]
            g2 = dx * dx + dy * dy
            g = np.sqrt(g2)
            pred = np.sqrt(g2 + s.lm_dz2[:, None, :]) if self.params.distance_model == "3d" \
                else g
            e = pred - s.lm_dist[:, None, :]
            # the seen direction in the team frame, per particle: heading + azimuth
            cc, ss = c[:, :, None], sn[:, :, None]
            ca, sa = s.lm_cos[:, None, :], s.lm_sin[:, None, :]
            dot = dx * (cc * ca - ss * sa) + dy * (ss * ca + cc * sa)
            cos_err = dot / np.maximum(g, 1e-9)
            cap = self.params.landmark_outlier_cap
            if math.isfinite(cap):
                # each sighting costs at most ``cap``: a misnamed or made-up one cannot
                # outvote the others (a Gaussian with a uniform outlier floor)
                term = e * e * s.lm_inv_var[:, None, :] \
                    - (cos_err - 1.0) * s.lm_kappa[:, None, :]
                ll -= np.minimum(term, cap).sum(axis=2)
            else:
                ll -= pm.matmul(e * e, s.lm_inv_var[:, :, None])[:, :, 0]
                ll += pm.matmul(cos_err, s.lm_kappa[:, :, None])[:, :, 0]
                ll -= s.lm_kappa.sum(axis=1)[:, None]
        if s.pt_fwd.shape[1]:
            cc, ss = c[:, :, None], sn[:, :, None]
            f, lf = s.pt_fwd[:, None, :], s.pt_left[:, None, :]
            inv = 1.0 / self.params.line_grid_m
            ix = (x[:, :, None] + cc * f - ss * lf - self._gx0) * inv + 0.5
            iy = (y[:, :, None] + ss * f + cc * lf - self._gy0) * inv + 0.5
            np.clip(ix, 0.0, self._gnx - 1, out=ix)
            np.clip(iy, 0.0, self._gny - 1, out=iy)
            flat = iy.astype(np.intp) * self._gnx + ix.astype(np.intp)
            r = np.minimum(self._grid.take(flat), self.params.line_cap_m)
            ll -= pm.matmul(r * r, s.pt_inv_var[:, :, None].astype(np.float32))[:, :, 0]
        return ll

    def correct(self, agents: ArrayLike | None, landmarks: ArrayLike,
                lines: ArrayLike | None = None) -> None:
        """The sensor update of ``agents`` (None: all) on a vision cycle: ``landmarks``
        (R, K, 4) and ``lines`` (R, L, 7) as the observation gives them (rows with nothing
        seen leave that agent's filter unchanged). Weights, resets, resampling."""
        rows = self._rows(agents)
        r = self._count(rows)
        lm = _shaped("correct: landmarks", landmarks, (r, len(self._lm), 4))
        li = None if lines is None else np.asarray(lines, dtype=np.float64)
        if li is not None and li.size:
            if li.size % (7 * r):
                raise LocalizationError(f"correct: lines must have shape ({r}, L, 7), got "
                                        f"{li.shape}")
            li = li.reshape(r, -1, 7)
        elif li is not None:
            li = None
        s = self._sightings(lm, li)
        weight = s.weight
        active = weight > 0
        if not active.any():
            return
        p = self._p[:, rows]
        logw = self._logw[rows]
        ll = self._loglik(p[0], p[1], p[2], s)

        # the fit of this update and the augmented-MCL averages (active agents only)
        w = self._exp_logw()[rows].copy()  # = pm.exp(logw), element by element
        q = (w * pm.exp(ll / np.maximum(weight, 1e-12)[:, None])).sum(axis=1)
        prm = self.params
        slow = np.where(np.isnan(self.w_slow[rows]), q, self.w_slow[rows])
        fast = np.where(np.isnan(self.w_fast[rows]), q, self.w_fast[rows])
        slow = np.where(active, slow + prm.alpha_slow * (q - slow), self.w_slow[rows])
        fast = np.where(active, fast + prm.alpha_fast * (q - fast), self.w_fast[rows])
        self.w_slow[rows], self.w_fast[rows] = slow, fast
        self.quality[rows] = np.where(active, q, self.quality[rows])
        with np.errstate(divide="ignore", invalid="ignore"):
            share = np.where(slow > 0, 1.0 - fast / slow, 0.0)
        share = np.where(fast < prm.lost_quality, np.maximum(share, prm.lost_share), share)
        share = np.where(share >= prm.min_reset_share, share, 0.0)
        share = np.clip(share, 0.0, prm.max_reset_share)
        n_reset = np.where(active & (s.n_landmarks > 0), np.rint(share * self.n), 0)
        n_reset = n_reset.astype(np.intp)
        if n_reset.any():
            ll, replaced = self._reset(p, logw, ll, s, n_reset, w)
            self.resets[rows] += replaced

        logw = logw + ll
        logw -= logw.max(axis=1, keepdims=True)
        w = pm.exp(logw)
        total = w.sum(axis=1, keepdims=True)
        logw -= pm.log(total)
        w /= total
        ess = 1.0 / (w * w).sum(axis=1)
        low = np.flatnonzero(active & (ess < prm.resample_ess * self.n))
        if low.size:
            self._resample(p, logw, w, low)
        p[2] = (p[2] + np.pi) % (2.0 * np.pi) - np.pi
        np.clip(p[0], -self._xlim, self._xlim, out=p[0])
        np.clip(p[1], -self._ylim, self._ylim, out=p[1])
        self._p[:, rows] = p
        self._logw[rows] = logw
        self._estimate = None

    def _resample(self, p: NDArray, logw: NDArray, w: NDArray, rows: NDArray[np.intp]) -> None:
        """Systematic (low-variance) resampling of ``rows`` in place, O(N) per row: particle
        i gets ``ceil(N C_i - u) - ceil(N C_{i-1} - u)`` copies (C the cumulative weights)."""
        n = self.n
        cum = np.cumsum(w[rows], axis=1)
        cum /= cum[:, -1:]
        u = self.rng.random((len(rows), 1))
        upto = np.ceil(cum * n - u).astype(np.intp)
        counts = upto.copy()  # np.diff(upto, axis=1, prepend=0), without the concatenation
        counts[:, 1:] -= upto[:, :-1]
        source = np.repeat(np.arange(len(rows) * n), counts.ravel())
        block = p[:, rows].reshape(3, -1)[:, source].reshape(3, len(rows), n)
        p[:, rows] = block
        logw[rows] = -math.log(n)

    def _reset(self, p: NDArray, logw: NDArray, ll: NDArray, s: _Sightings,
               n_reset: NDArray[np.intp], w: NDArray) -> tuple[NDArray, NDArray[np.intp]]:
        """Replace the ``n_reset`` lowest-weighted particles of each row by poses from the
        sightings (see the module docstring); returns the updated log-likelihood and how
        many particles of each row were replaced."""
        prm, rng, n = self.params, self.rng, self.n
        rows = np.flatnonzero(n_reset)
        m = int(n_reset.max())
        order = np.argsort(logw[rows] + ll[rows], axis=1, kind="stable")[:, :m]
        take = np.arange(m) < n_reset[rows][:, None]
        ri = np.broadcast_to(rows[:, None], (len(rows), m))[take]   # (T,) row of each slot
        pi = order[take]                                              # (T,) particle
        t = len(ri)
        k = s.n_landmarks[ri]
        u = rng.random((2, t))
        i1 = np.minimum((u[0] * k).astype(np.intp), k - 1)
        i2 = (i1 + 1 + np.minimum((u[1] * (k - 1)).astype(np.intp), np.maximum(k - 2, 0))) % k
        noise = rng.standard_normal((4, t))
        g_rel, az_sig = prm.reset_sigma_distance_rel, math.radians(prm.reset_sigma_bearing_deg)
        g1 = s.lm_ground[ri, i1] * (1.0 + g_rel * noise[0])
        a1 = s.lm_az[ri, i1] + az_sig * noise[1]
        g2 = s.lm_ground[ri, i2] * (1.0 + g_rel * noise[2])
        a2 = s.lm_az[ri, i2] + az_sig * noise[3]
        l1, l2 = s.lm_xy[ri, i1], s.lm_xy[ri, i2]
        new = np.full((t, 3), np.nan)

        pair = k >= 2
        if pair.any():
            cand, res = two_landmark_candidates(l1[pair], l2[pair], g1[pair], a1[pair],
                                                g2[pair], a2[pair])
            posts = self._same_goal[s.lm_index[ri, i1], s.lm_index[ri, i2]][pair]
            if posts.any():  # seed 002's closed form from the posts' (u, v)
                gp1, ap1, gp2, ap2 = (v[pair][posts] for v in (g1, a1, g2, a2))
                cand[posts], res[posts] = two_post_candidates(
                    gp1 * np.cos(ap1), gp1 * np.sin(ap1), gp2 * np.cos(ap2),
                    gp2 * np.sin(ap2), l1[pair][posts], l2[pair][posts])
            ok = on_field(cand[..., 0], cand[..., 1], self.field, prm.field_margin_m)
            ok &= np.isfinite(cand).all(axis=-1)
            score = np.where(ok, res, np.inf)
            best = np.argmin(score, axis=1)
            chosen = cand[np.arange(len(best)), best]
            chosen[~np.isfinite(score.min(axis=1))] = np.nan
            new[pair] = chosen

        single = ~pair
        if single.any():  # one landmark: its distance and bearing, the heading believed
            c, sn = np.cos(p[2]), np.sin(p[2])
            mean = pm.arctan2((w * sn).sum(axis=1), (w * c).sum(axis=1))
            length = np.hypot((w * sn).sum(axis=1), (w * c).sum(axis=1))
            circ_std = np.sqrt(-2.0 * pm.log(np.clip(length, 1e-12, 1.0)))
            sigma = np.maximum(math.radians(prm.reset_sigma_heading_deg), circ_std)
            rs = ri[single]
            psi = mean[rs] + sigma[rs] * rng.standard_normal(len(rs))
            direction = psi + a1[single]
            new[single, 0] = l1[single, 0] - g1[single] * np.cos(direction)
            new[single, 1] = l1[single, 1] - g1[single] * np.sin(direction)
            new[single, 2] = psi
            off = ~on_field(new[single, 0], new[single, 1], self.field, prm.field_margin_m)
            new[np.flatnonzero(single)[off]] = np.nan

        keep = np.isfinite(new).all(axis=1)
        if not keep.any():
            return ll, np.zeros(len(ll), dtype=np.intp)
        ri, pi, new = ri[keep], pi[keep], new[keep]
        p[0, ri, pi], p[1, ri, pi] = new[:, 0], new[:, 1]
        p[2, ri, pi] = (new[:, 2] + np.pi) % (2.0 * np.pi) - np.pi
        logw[ri, pi] = -math.log(n)  # the mean prior weight (the log-weights are normalized)
        changed = np.unique(ri)
        ll = ll.copy()
        ll[changed] = self._loglik(p[0, changed], p[1, changed], p[2, changed],
                                   s.rows(changed))
        return ll, np.bincount(ri, minlength=len(ll))

    # -- output -----------------------------------------------------------------------------
    def estimate(self) -> PoseEstimate:
        """Every agent's pose (A, 3) and covariance (A, 3, 3) (see ``PoseEstimate``)."""
        if self._estimate is None:
            w = self._exp_logw().copy()  # normalized log-weights
            w /= w.sum(axis=1, keepdims=True)
            x, y, h = self._p
            trig = np.stack((np.cos(h), np.sin(h)))
            mx, my = (w * x).sum(axis=1), (w * y).sum(axis=1)
            mc, ms = (trig * w).sum(axis=2)
            mh = pm.arctan2(ms, mc)
            dev = np.empty((self.n_agents, 3, self.n))
            np.subtract(x, mx[:, None], out=dev[:, 0])
            np.subtract(y, my[:, None], out=dev[:, 1])
            dev[:, 2] = (h - mh[:, None] + np.pi) % (2.0 * np.pi) - np.pi
            cov = pm.matmul(dev * w[:, None, :], dev.transpose(0, 2, 1))
            self._estimate = PoseEstimate(np.stack((mx, my, mh), axis=1), cov)
        return PoseEstimate(self._estimate.pose.copy(), self._estimate.covariance.copy())

    # -- observations -----------------------------------------------------------------------
    def observe(self, observations: Sequence[Mapping[str, Any]]) -> PoseEstimate:
        """One cycle of every agent from its ``vision``-mode observation (Dict form, agent
        order): predict from ``odometry`` and ``gyro``, correct where ``vision[0]`` is fresh."""
        if len(observations) != self.n_agents:
            raise LocalizationError(f"observe: {self.n_agents} observations expected, got "
                                    f"{len(observations)}")
        odometry = np.array([o["odometry"] for o in observations], dtype=np.float64)
        gyro = np.array([np.asarray(o["gyro"]).reshape(-1)[0] for o in observations],
                        dtype=np.float64)
        self.predict(None, odometry, gyro)
        fresh = [k for k, o in enumerate(observations) if o["vision"][0] > 0.5]
        if fresh:
            seen = [observations[k] for k in fresh]
            lines = None
            if "lines" in seen[0]:
                lines = np.stack([np.asarray(o["lines"], dtype=np.float64).reshape(-1, 7)
                                  for o in seen])
            self.correct(fresh, np.stack([o["landmarks"] for o in seen]), lines)
        return self.estimate()


class Localizer:
    """Monte Carlo localization of one agent: a ``BatchLocalizer`` of one (same arguments
    but ``n_agents``; arrays without the agent axis)."""

    def __init__(self, field: FieldSpec | str, landmark_kind: str = "simspark",
                 camera_height: float = 0.5, params: LocalizationParams | None = None,
                 rng: np.random.Generator | None = None) -> None:
        self.batch = BatchLocalizer(1, field, landmark_kind, camera_height, params, rng)

    @property
    def particles(self) -> NDArray[np.float64]:
        """(N, 3) a copy of the particles."""
        return self.batch.particles[0]

    @property
    def weights(self) -> NDArray[np.float64]:
        """(N,) the normalized weights."""
        return self.batch.weights[0]

    @property
    def quality(self) -> float:
        """The last update's fit (NaN before the first)."""
        return float(self.batch.quality[0])

    def reset(self) -> None:
        """A uniform prior over the pitch."""
        self.batch.reset()

    def beamed(self, pose: ArrayLike, spread: float | tuple[float, float] | None = None
               ) -> None:
        """The agent was beamed to ``pose`` on its own request (see ``BatchLocalizer``)."""
        self.batch.beamed(0, pose, spread)

    def predict(self, odometry: ArrayLike, gyro: float | None = None) -> None:
        """The motion update: odometry (3,), gyro (a float) or None."""
        self.batch.predict(None, np.asarray(odometry, dtype=np.float64).reshape(1, 3),
                           None if gyro is None else np.reshape(gyro, (1,)))

    def correct(self, landmarks: ArrayLike, lines: ArrayLike | None = None) -> None:
        """The sensor update: landmarks (K, 4), lines (L, 7) or None."""
        self.batch.correct(None, np.asarray(landmarks, dtype=np.float64)[None],
                           None if lines is None else np.asarray(lines, dtype=np.float64)[None])

    def estimate(self) -> PoseEstimate:
        """Pose (3,) and covariance (3, 3)."""
        est = self.batch.estimate()
        return PoseEstimate(est.pose[0], est.covariance[0])

    def observe(self, observation: Mapping[str, Any]) -> PoseEstimate:
        """One cycle from a ``vision``-mode observation (Dict form)."""
        est = self.batch.observe([observation])
        return PoseEstimate(est.pose[0], est.covariance[0])
