"""Vision: every agent's ``vision``-mode observation at once, in its team's frame.

The league's restricted vision (SimSpark's RestrictedVisionPerceptor, RCSSServerMJ 0.2.1's
camera), vectorized over all 2N agents. Per agent, polar sightings (``teamenv.landmarks.to_polar``
conventions: 3D distance from a camera ``camera_height_m`` above the agent, azimuth positive to
the left of the body heading, elevation positive up) of

- the landmarks of ``landmarks(field, landmark_kind)`` (team frame: row k is the same landmark
  for both teams; the right team's landmark k lies at minus the left's x, y in the world),
- the ball (its centre, z = ball radius),
- every other player (one point at camera height; the row says team and uniform number),
- the field lines (``field_lines(field)``, z = 0) clipped to the horizontal cone, both
  endpoints as polar sightings (when ``lines``).

The head is fixed: the camera looks along the body heading (head pan 0, reported in ``body``
so that a later head command fits). No own pose is given: the agent gets odometry (what its
walk engine believes it moved this cycle) and a gyro (its true heading change plus noise).

A sighting is reported when it lies in the cone (``|azimuth| <= fov_horizontal_deg / 2``,
``|elevation| <= fov_vertical_deg / 2``) and is at least ``min_distance_m`` away, both checked
on the reported (noisy, truncated) values, so every present point sighting lies inside the
cone (line endpoints are clipped on the noise-free geometry, then get their noise).
The pipeline per sighting: camera-relative vector + the agent's calibration error -> polar ->
noise (distance ``d += d * N(0, distance_sigma_rel)``, azimuth and elevation Gaussian) ->
truncation toward zero (degrees / metres, ``truncate_decimals``) -> cone and distance checks ->
occlusion (``occlusion``: hidden when a nearer player's disc covers its azimuth; lines are
never occluded) -> detection errors (``missed_rate``, ``misclassified_rate``, ``false_rate`` /
``false_max``: a sighting lost, a landmark or ball sighting reported in another world object's
row, a made-up one in the cone; see ``_detection_errors``). Vision updates on cycles where ``cycle % update_period_cycles == 0``; on other
cycles nothing is seen (every present mask 0, every sighting 0).

Randomness: the generator given to ``reset`` (the env's own vision generator) draws the
calibration errors at reset, then, when the profile is noisy, one block of normals per update
cycle, then, when it has detection errors, their draws (uniforms for the missed and the
misclassified sightings, binomial counts and uniforms for the false ones), and the gyro noise
every cycle.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

import portable_math as pm
from teamenv.box_layout import (
    LINE_DIM,
    SIGHTING_DIM,
    VisionLayout,
    play_mode_and_game_block,
)
from teamenv.config import PerceptionConfig
from teamenv.field import FieldSpec
from teamenv.landmarks import field_lines, landmarks
from teamenv.sim.playmode import PlayMode


def vision_layout(field: FieldSpec, team_size: int, heard_slots: int,
                  config: PerceptionConfig) -> VisionLayout:
    """The layout of ``config``'s vision observation on ``field``."""
    return VisionLayout(len(landmarks(field, config.landmark_kind)), team_size,
                        len(field_lines(field)) if config.lines else 0, heard_slots)


def _trunc(values: np.ndarray, scale: float) -> np.ndarray:
    """Toward zero to 1/scale (RCSSServerMJ's ``np.trunc(v * 100) / 100``)."""
    return np.trunc(values * scale) / scale


@dataclass
class VisionFrame:
    """One cycle's observations of every agent: float32 rows in the flat layout, plus the
    heard texts and team-relative play modes the Dict form needs."""

    rows: np.ndarray
    heard_texts: Sequence[tuple]
    team_modes: list[int]


class VisionPerception:
    """Vision observations for 2N agents (players 0..N-1 left, N..2N-1 right).

    Args:
        field: the pitch.
        team_size: players per side.
        heard_slots: heard-message slots of the say channel.
        config: the camera (a ``PerceptionConfig``, e.g. ``VISION_PROFILES["simspark"]``).
        body_radius: the players' disc radius (occlusion).
        ball_radius: the ball's radius (its sighting's height).
    """

    def __init__(self, field: FieldSpec, team_size: int, heard_slots: int,
                 config: PerceptionConfig, body_radius: float, ball_radius: float) -> None:
        self.field, self.team_size, self.heard_slots = field, team_size, heard_slots
        self.config = config
        self.body_radius = float(body_radius)
        self.ball_radius = float(ball_radius)
        n = 2 * team_size
        self.n = n
        self.team_of = np.repeat([0, 1], team_size)
        self._team_list = self.team_of.tolist()
        self._rows = np.arange(n)
        self.landmarks = landmarks(field, config.landmark_kind)
        self._lm = np.asarray(self.landmarks.xyz, dtype=float)
        self._segments = np.asarray(field_lines(field), dtype=float) if config.lines else \
            np.zeros((0, 4))
        self.layout = vision_layout(field, team_size, heard_slots, config)
        self._off = self.layout.offsets
        self._size = self.layout.size
        # Player columns of each agent: own team first (uniform order), then the opponents.
        order = [np.arange(n), np.r_[np.arange(team_size, n), np.arange(team_size)]]
        self._cols = np.stack([order[t] for t in self._team_list])
        self._self_col = np.zeros((n, n), dtype=bool)
        self._self_col[self._rows, self._rows % team_size] = True
        self.n_points = len(self._lm) + 1 + n
        cfg = config
        self._half_h = math.radians(cfg.fov_horizontal_deg / 2.0)
        self._half_v = math.radians(cfg.fov_vertical_deg / 2.0)
        self._half_h_deg = cfg.fov_horizontal_deg / 2.0
        self._half_v_deg = cfg.fov_vertical_deg / 2.0
        self._scale = None if cfg.truncate_decimals is None else 10.0 ** cfg.truncate_decimals
        self._sigma = np.array([cfg.distance_sigma_rel, math.radians(cfg.azimuth_sigma_deg),
                                math.radians(cfg.elevation_sigma_deg)])
        self._noisy = bool(np.any(self._sigma > 0))
        self._errors = cfg.detection_errors
        self.rng = np.random.default_rng(0)
        self.calibration = np.zeros((n, 3))
        self._block_key: tuple | None = None

    def reset(self, rng: np.random.Generator) -> None:
        """A new match: keep ``rng`` (the vision generator) and draw each agent's camera
        calibration error, uniform in ``±calibration_error_m`` per axis (team-frame axes)."""
        self.rng = rng
        c = self.config.calibration_error_m
        self.calibration = rng.uniform(-1.0, 1.0, (self.n, 3)) * c

    # -- geometry --------------------------------------------------------------------------
    def _polar(self, fwd: np.ndarray, left: np.ndarray, dz: np.ndarray,
               noise: np.ndarray | None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Distance, azimuth, elevation (rad) of camera-frame vectors, with noise and
        truncation applied."""
        ground = np.hypot(fwd, left)
        dist = np.sqrt(ground * ground + dz * dz)
        az = pm.arctan2(left, fwd)
        el = pm.arctan2(dz, ground)
        if noise is not None:
            s = self._sigma
            dist = dist + dist * (s[0] * noise[0])
            az = az + s[1] * noise[1]
            el = el + s[2] * noise[2]
        if self._scale is not None:
            scale = self._scale
            az = np.radians(_trunc(np.degrees(az), scale))
            el = np.radians(_trunc(np.degrees(el), scale))
            dist = _trunc(dist, scale)
        return dist, az, el

    def _in_cone(self, az: np.ndarray, el: np.ndarray) -> np.ndarray:
        if self._scale is not None:  # compare the truncated degrees, as RCSSServerMJ does
            scale = self._scale
            az_deg, el_deg = _trunc(np.degrees(az), scale), _trunc(np.degrees(el), scale)
            return (np.abs(az_deg) <= self._half_h_deg) & (np.abs(el_deg) <= self._half_v_deg)
        return (np.abs(az) <= self._half_h) & (np.abs(el) <= self._half_v)

    def _clip(self, af: np.ndarray, al: np.ndarray, bf: np.ndarray, bl: np.ndarray
              ) -> tuple[np.ndarray, np.ndarray]:
        """Parameters ``t0 <= t1`` of the part of segments a -> b (camera frame, horizontal
        forward/left) inside the horizontal cone; ``t1 <= t0`` where nothing is inside.
        Beyond 180° the visible region is not convex: the longer remaining piece is kept."""
        h = self._half_h
        if h >= math.pi:
            return np.zeros_like(af), np.ones_like(af)
        c, s = math.cos(h), math.sin(h)
        # g[0] >= 0: left of the right boundary ray; g[1] >= 0: right of the left one.
        k = np.array((c, -c))[:, None, None]
        ga = s * af + k * al
        gb = s * bf + k * bl
        with np.errstate(divide="ignore", invalid="ignore"):
            t = ga / (ga - gb)  # where g crosses 0 along the segment
        neg_a, neg_b = ga < 0, gb < 0
        if h <= math.pi / 2:  # convex wedge: the intersection of both half-planes
            lo = np.where(neg_a, t, 0.0).max(axis=0)
            hi = np.where(neg_b, t, 1.0).min(axis=0)
            empty = (neg_a & neg_b).any(axis=0)
            return np.where(empty, 0.0, lo), np.where(empty, -1.0, hi)
        # Wider than 180°: the excluded wedge behind is where both g < 0.
        lo = np.where(neg_a, 0.0, t).max(axis=0)
        hi = np.where(neg_b, 1.0, t).min(axis=0)
        none = (~neg_a & ~neg_b).any(axis=0) | (hi <= lo)
        first_longer = lo >= 1.0 - hi
        t0 = np.where(none | first_longer, 0.0, hi)
        t1 = np.where(none, 1.0, np.where(first_longer, lo, 1.0))
        return t0, t1

    # -- the observation -------------------------------------------------------------------
    def observe(
        self, cycle: int, poses: np.ndarray, ball: np.ndarray, fallen: np.ndarray,
        odometry: np.ndarray, turn: np.ndarray, mode: PlayMode, time_s: float, half: int,
        score: Sequence[int], attack_sign: Sequence[float], heard_info: np.ndarray,
        heard_texts: Sequence[tuple],
    ) -> VisionFrame:
        """Every agent's vision observation of this cycle (world-frame inputs).

        ``odometry`` (n, 3): the walk engine's body-frame displacement this cycle; ``turn``
        (n,): the true heading change of the cycle (the gyro adds its noise)."""
        n, cfg, off = self.n, self.config, self._off
        rows = np.zeros((n, self._size))
        period = cfg.update_period_cycles
        fresh = cycle % period == 0
        if cfg.gyro_sigma_rad > 0:
            rows[:, off["gyro"][0]] = turn + cfg.gyro_sigma_rad * self.rng.standard_normal(n)
        else:
            rows[:, off["gyro"][0]] = turn
        if fresh:
            self._see(rows, poses, ball, attack_sign)
        a = off["vision"][0]
        rows[:, a] = 1.0 if fresh else 0.0
        rows[:, a + 1] = cycle % period
        a, b = off["odometry"]
        rows[:, a:b] = odometry
        rows[:, off["body"][0]] = fallen  # head pan (the next column) stays 0: fixed head

        modes = (int(mode), int(mode.for_team(1)))
        key = (modes, half, tuple(score))
        if key != self._block_key:
            self._block = play_mode_and_game_block(self.team_of, modes, half, score)
            self._block_key = key
            self._team_modes = [modes[t] for t in self._team_list]
        a, b = off["play_mode"][0], off["game"][1]
        rows[:, a:b] = self._block
        rows[:, off["game"][0]] = time_s
        a, b = off["heard"]
        rows[:, a:b] = heard_info.reshape(n, -1)
        return VisionFrame(rows.astype(np.float32), heard_texts, self._team_modes)

    def _see(self, rows: np.ndarray, poses: np.ndarray, ball: np.ndarray,
             attack_sign: Sequence[float]) -> None:
        """Fill the sightings and counts of an update cycle (one polar pass and one noise
        draw for every point and line endpoint of every agent)."""
        n, cfg, off = self.n, self.config, self._off
        height = cfg.camera_height_m
        sign = np.asarray(attack_sign, dtype=float)[self.team_of]  # (n,)
        calib = self.calibration
        # The camera in the team frame, shifted by the calibration error (the error is added
        # to every camera-relative vector: the same as moving the camera by minus it).
        cam_x = sign * poses[:, 0] - calib[:, 0]
        cam_y = sign * poses[:, 1] - calib[:, 1]
        cam_z = height - calib[:, 2]
        c, s = sign * np.cos(poses[:, 2]), sign * np.sin(poses[:, 2])  # team-frame heading
        cc, ss = c[:, None], s[:, None]

        # Points each agent may see, team frame: landmarks (K), the ball, then every player
        # (own team first, uniform order), then the clipped line endpoints (2L).
        k, m = len(self._lm), self.n_points
        segs = self._segments
        n_lines = len(segs)
        total = m + 2 * n_lines
        rx = np.empty((n, total))
        ry = np.empty((n, total))
        rx[:, :k] = self._lm[:, 0]
        ry[:, :k] = self._lm[:, 1]
        rx[:, k] = sign * ball[0]
        ry[:, k] = sign * ball[1]
        cols = self._cols
        rx[:, k + 1:m] = sign[:, None] * poses[:, 0][cols]
        ry[:, k + 1:m] = sign[:, None] * poses[:, 1][cols]
        if n_lines:
            rx[:, m:m + n_lines] = segs[:, 0]
            ry[:, m:m + n_lines] = segs[:, 1]
            rx[:, m + n_lines:] = segs[:, 2]
            ry[:, m + n_lines:] = segs[:, 3]
        rx -= cam_x[:, None]
        ry -= cam_y[:, None]
        fwd = cc * rx + ss * ry
        left = cc * ry - ss * rx
        rz = np.empty((n, total))
        rz[:, :k] = self._lm[:, 2]
        rz[:, k] = self.ball_radius
        rz[:, k + 1:m] = height
        rz[:, m:] = 0.0
        rz -= cam_z[:, None]

        if n_lines:  # clip each segment to the horizontal cone, in place
            a, b = slice(m, m + n_lines), slice(m + n_lines, total)
            af, al, bf, bl = fwd[:, a], left[:, a], fwd[:, b], left[:, b]
            t0, t1 = self._clip(af, al, bf, bl)
            present = t1 > t0
            t0 = np.where(present, t0, 0.0)
            t1 = np.where(present, t1, 1.0)
            df, dl = bf - af, bl - al
            fwd[:, b] = af + t1 * df
            left[:, b] = al + t1 * dl
            fwd[:, a] = af + t0 * df
            left[:, a] = al + t0 * dl

        noise = self.rng.standard_normal((3, n, total)) if self._noisy else None
        dist, az, el = self._polar(fwd, left, rz, noise)

        seen = self._in_cone(az[:, :m], el[:, :m]) & (dist[:, :m] >= cfg.min_distance_m)
        seen[:, k + 1:] &= ~self._self_col
        if cfg.occlusion:
            seen &= ~self._occluded(fwd[:, :m], left[:, :m], k)
        if self._errors:
            self._detection_errors(seen, dist, az, el, k)

        # Sightings: present, distance, azimuth, elevation (0 where not seen).
        sight = np.zeros((n, m, SIGHTING_DIM))
        sight[..., 0] = seen
        sight[..., 1] = np.where(seen, dist[:, :m], 0.0)
        sight[..., 2] = np.where(seen, az[:, :m], 0.0)
        sight[..., 3] = np.where(seen, el[:, :m], 0.0)
        a, b = off["landmarks"]
        rows[:, a:b] = sight[:, :k].reshape(n, -1)
        a, b = off["ball"]
        rows[:, a:b] = sight[:, k]
        a, b = off["teammates"][0], off["opponents"][1]
        rows[:, a:b] = sight[:, k + 1:].reshape(n, -1)
        a = off["counts"][0]
        rows[:, a] = seen[:, :k].sum(axis=1)
        rows[:, a + 1] = seen[:, k + 1:].sum(axis=1)
        rows[:, a + 3] = seen[:, k]

        if n_lines:
            out = np.zeros((n, n_lines, LINE_DIM))
            out[..., 0] = present
            for j, part in enumerate((dist, az, el)):
                out[..., 1 + j] = np.where(present, part[:, m:m + n_lines], 0.0)
                out[..., 4 + j] = np.where(present, part[:, m + n_lines:], 0.0)
            a, b = off["lines"]
            rows[:, a:b] = out.reshape(n, -1)
            rows[:, off["counts"][0] + 2] = present.sum(axis=1)

    def _detection_errors(self, seen: np.ndarray, dist: np.ndarray, az: np.ndarray,
                          el: np.ndarray, k: int) -> None:
        """A detector's errors, in place on the update's ``seen`` (n, M) and its polar values
        (columns 0..M-1: the ``k`` landmarks, the ball, the players): missed sightings, landmark
        and ball sightings reported under another world object's name, and false detections.
        A row holds one sighting: a genuine one keeps its row, a misclassified or false one
        only takes a row nothing else was seen in (the server would send both)."""
        cfg, rng, n = self.config, self.rng, self.n
        world = k + 1  # the world objects a name can be confused with: landmarks and the ball
        if cfg.missed_rate > 0:
            seen &= rng.random(seen.shape) >= cfg.missed_rate
        if cfg.misclassified_rate > 0 and world > 1:
            wrong = seen[:, :world] & (rng.random((n, world)) < cfg.misclassified_rate)
            draw = rng.integers(0, world - 1, (n, world))
            label = draw + (draw >= np.arange(world))  # uniform over the other objects
            agent, obj = np.nonzero(wrong)
            name = label[agent, obj]
            values = dist[agent, obj], az[agent, obj], el[agent, obj]
            seen[agent, obj] = False
            self._put(seen, dist, az, el, agent, name, values)
        if cfg.false_rate > 0 and cfg.false_max > 0:
            count = rng.binomial(cfg.false_max, cfg.false_rate, n)
            total = int(count.sum())
            if total:
                agent = np.repeat(np.arange(n), count)
                name = rng.integers(0, world, total)
                low, high = cfg.false_distance_m
                values = (rng.uniform(low, high, total),
                          rng.uniform(-self._half_h, self._half_h, total),
                          rng.uniform(-self._half_v, self._half_v, total))
                if self._scale is not None:
                    values = (_trunc(values[0], self._scale),
                              np.radians(_trunc(np.degrees(values[1]), self._scale)),
                              np.radians(_trunc(np.degrees(values[2]), self._scale)))
                self._put(seen, dist, az, el, agent, name, values)

    @staticmethod
    def _put(seen: np.ndarray, dist: np.ndarray, az: np.ndarray, el: np.ndarray,
             agent: np.ndarray, name: np.ndarray, values: tuple) -> None:
        """Report ``values`` (distance, azimuth, elevation) in rows ``name`` of ``agent``
        where nothing is seen yet (two landing on one free row: the later one)."""
        free = ~seen[agent, name]
        agent, name = agent[free], name[free]
        seen[agent, name] = True
        dist[agent, name] = values[0][free]
        az[agent, name] = values[1][free]
        el[agent, name] = values[2][free]

    def _occluded(self, fwd: np.ndarray, left: np.ndarray, k: int) -> np.ndarray:
        """(n, M): a nearer player's disc covers the point's azimuth (from the camera, without
        noise): the ray to the point passes within ``body_radius`` of the player's centre
        in front of the camera, i.e. ``|azimuth difference| <= asin(radius / distance)``."""
        ground = np.hypot(fwd, left)
        with np.errstate(divide="ignore", invalid="ignore"):
            uf, ul = fwd / ground, left / ground  # unit directions (n, M)
        pf, pl = fwd[:, None, k + 1:], left[:, None, k + 1:]  # occluders (n, 1, n)
        uf3, ul3 = uf[:, :, None], ul[:, :, None]
        along = uf3 * pf + ul3 * pl
        across = np.abs(uf3 * pl - ul3 * pf)
        covers = (across <= self.body_radius) & (along > 0.0)
        covers &= ground[:, None, k + 1:] < ground[:, :, None]
        covers &= ~self._self_col[:, None, :]  # an agent does not hide things from itself
        return covers.any(axis=2)

    # -- forms -----------------------------------------------------------------------------
    def as_flat(self, frame: VisionFrame) -> list[np.ndarray]:
        """The Box form: one float32 row per agent (views of the frame's rows)."""
        return list(frame.rows)

    def as_dicts(self, frame: VisionFrame) -> list[dict[str, Any]]:
        """The Dict form (values are views of the frame's rows; ``play_mode`` an int)."""
        parts = self.layout.dict_parts(frame.rows)
        keys, arrays = list(parts), list(parts.values())
        return [dict(zip(keys, values, strict=True), play_mode=mode, heard_text=texts)
                for *values, mode, texts in zip(*arrays, frame.team_modes, frame.heard_texts,
                                                strict=True)]
