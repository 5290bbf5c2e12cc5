"""Monte Carlo localization (strategy.perception.localization) and the two-post closed form.

``synthetic_walk`` is a small scene generator: a player walking between random waypoints,
the odometry its walk engine would report (over-reported by 1.1, 1.1, 1.05 with 5 % noise),
a gyro, and every ``period`` cycles the landmark and line sightings of the league's vision
(``teamenv.landmarks.to_polar``, SimSpark's noise and camera calibration error, the ±60°
cone). The benchmark ``benchmarks/localization.py`` uses it too.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pytest

from strategy.perception.localization import (
    BatchLocalizer,
    LocalizationError,
    LocalizationParams,
    Localizer,
    PoseEstimate,
)
from strategy.perception.two_posts import two_landmark_candidates, two_post_pose
from teamenv.errors import TeamEnvError
from teamenv.field import FieldSpec, field_preset
from teamenv.landmarks import field_lines, from_polar, landmarks, to_polar

CYCLE_S = 0.02
HALF_CONE = math.radians(60.0)
OVER_REPORT = np.array([1.1, 1.1, 1.05])


@dataclass(frozen=True)
class Noise:
    """The camera's noise (SimSpark's by default; ``Noise.exact()`` for none)."""

    distance_rel: float = 0.000965
    azimuth_rad: float = math.radians(0.148)
    elevation_rad: float = math.radians(0.1225)
    calibration_m: float = 0.005
    gyro_rad: float = 0.002
    odometry_rel: float = 0.05

    @classmethod
    def exact(cls) -> Noise:
        return cls(0.0, 0.0, 0.0, 0.0, 0.0, 0.0)


@dataclass
class Walk:
    """A synthetic walk: ``poses[t]`` is the true pose at cycle t (team frame) and
    ``observations[t]`` what the agent gets at cycle t (Dict form of the env's vision mode:
    odometry of the step t-1 -> t, gyro, and on vision cycles landmarks and lines)."""

    poses: np.ndarray
    observations: list[dict]


def _clip_to_cone(fa, la, fb, lb):
    """Parameters t0 < t1 of the part of segment a -> b (camera frame) inside the cone, or
    None."""
    t0, t1 = 0.0, 1.0
    c, s = math.cos(HALF_CONE), math.sin(HALF_CONE)
    for k in (c, -c):  # left of the right boundary ray, right of the left one
        ga, gb = s * fa + k * la, s * fb + k * lb
        if ga < 0 and gb < 0:
            return None
        if ga < 0:
            t0 = max(t0, ga / (ga - gb))
        elif gb < 0:
            t1 = min(t1, ga / (ga - gb))
    return (t0, t1) if t1 > t0 else None


def sightings(pose, field: FieldSpec, kind: str, height: float, noise: Noise,
              calibration: np.ndarray, rng: np.random.Generator, lines: bool = True):
    """(K, 4) landmark and (L, 7) line sightings from ``pose`` (SimSpark's pipeline: camera
    offset, polar, noise, cone and minimum distance on the noisy values; lines clipped on
    the noise-free geometry)."""
    x, y, psi = pose
    cx, cy, cz = x - calibration[0], y - calibration[1], height - calibration[2]
    table = np.asarray(landmarks(field, kind).xyz)

    def noisy(polar):
        out = polar.copy()
        out[:, 0] += out[:, 0] * noise.distance_rel * rng.standard_normal(len(out))
        out[:, 1] += noise.azimuth_rad * rng.standard_normal(len(out))
        out[:, 2] += noise.elevation_rad * rng.standard_normal(len(out))
        return out

    pol = noisy(to_polar(table, cx, cy, psi, cz))
    seen = (np.abs(pol[:, 1]) <= HALF_CONE) & (np.abs(pol[:, 2]) <= HALF_CONE) & \
        (pol[:, 0] >= 0.1)
    lm = np.zeros((len(table), 4))
    lm[seen, 0] = 1.0
    lm[seen, 1:] = pol[seen]
    segs = np.asarray(field_lines(field)) if lines else np.zeros((0, 4))
    out = np.zeros((len(segs), 7))
    c, s = math.cos(psi), math.sin(psi)
    for j, (ax, ay, bx, by) in enumerate(segs):
        fa, la = c * (ax - cx) + s * (ay - cy), -s * (ax - cx) + c * (ay - cy)
        fb, lb = c * (bx - cx) + s * (by - cy), -s * (bx - cx) + c * (by - cy)
        t = _clip_to_cone(fa, la, fb, lb)
        if t is None:
            continue
        ends = [(fa + tt * (fb - fa), la + tt * (lb - la)) for tt in t]
        pts = np.array([(f, lf, 0.0) for f, lf in ends])
        pol2 = noisy(to_polar(pts, 0.0, 0.0, 0.0, cz))
        out[j] = (1.0, *pol2[0], *pol2[1])
    return lm, out


def synthetic_walk(seed: int, seconds: float, field: str | FieldSpec = "simspark",
                   kind: str = "simspark", height: float = 0.5, period: int = 3,
                   noise: Noise = Noise(), start=None, beams=(), pushes=(),
                   lines: bool = True, speed: float = 0.8, margin: float = 2.0,
                   aim=None) -> Walk:
    """A player walking between random waypoints ``margin`` inside the touch lines (or to the
    fixed point ``aim``), at up to ``speed`` m/s forward (a little sideways), turning toward
    the waypoint at up to 1.5 rad/s. ``beams``: ``(cycle, pose)``: the referee teleports the
    player at that cycle, ``pushes``: ``(cycle, (dx, dy, dpsi))``: something shoves it by that
    much (team frame) at that cycle; the odometry and gyro see neither."""
    field = field_preset(field)
    rng = np.random.default_rng(seed)
    hl, hw = field.half_length - margin, field.half_width - margin
    pose = np.array(start if start is not None else
                    (rng.uniform(-hl, hl), rng.uniform(-hw, hw), rng.uniform(-np.pi, np.pi)),
                    dtype=np.float64)
    target = np.array(aim) if aim is not None else rng.uniform((-hl, -hw), (hl, hw))
    calibration = rng.uniform(-1.0, 1.0, 3) * noise.calibration_m
    cycles = int(round(seconds / CYCLE_S))
    beams, pushes = dict(beams), dict(pushes)
    poses, observations = [], []
    delta = np.zeros(3)
    for t in range(cycles + 1):
        if t in beams:
            pose = np.array(beams[t], dtype=np.float64)
        if t in pushes:
            pose = pose + np.asarray(pushes[t], dtype=np.float64)
        odometry = delta * OVER_REPORT * (1.0 + noise.odometry_rel * rng.standard_normal(3))
        gyro = delta[2] + noise.gyro_rad * rng.standard_normal()
        obs = {"odometry": odometry, "gyro": np.array([gyro]),
               "vision": np.array([1.0 if t % period == 0 else 0.0, t % period])}
        if t % period == 0:
            obs["landmarks"], obs["lines"] = sightings(pose, field, kind, height, noise,
                                                       calibration, rng, lines)
        poses.append(pose.copy())
        observations.append(obs)
        # the command of this cycle: toward the waypoint
        dx, dy = target - pose[:2]
        if aim is None and math.hypot(dx, dy) < 1.0:
            target = rng.uniform((-hl, -hw), (hl, hw))
        err = (math.atan2(dy, dx) - pose[2] + math.pi) % (2 * math.pi) - math.pi
        turn = float(np.clip(3.0 * err, -1.5, 1.5))
        forward = speed * max(0.0, math.cos(err)) if math.hypot(dx, dy) > 0.3 else 0.0
        side = 0.1 * speed * math.sin(0.5 * t * CYCLE_S)
        delta = np.array([forward, side, turn]) * CYCLE_S
        c, s = math.cos(pose[2]), math.sin(pose[2])
        pose = pose + np.array([c * delta[0] - s * delta[1], s * delta[0] + c * delta[1],
                                delta[2]])
        pose[2] = (pose[2] + math.pi) % (2 * math.pi) - math.pi
    return Walk(np.array(poses), observations)


def run(walk: Walk, localizer: Localizer, beamed=None) -> np.ndarray:
    """(T, 3) the estimate after each cycle."""
    out = []
    for t, obs in enumerate(walk.observations):
        if beamed is not None and t in beamed:
            localizer.beamed(beamed[t])
        out.append(localizer.observe(obs).pose)
    return np.array(out)


def errors(walk: Walk, estimates: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Position (m) and heading (rad) errors per cycle."""
    pos = np.hypot(*(estimates[:, :2] - walk.poses[:, :2]).T)
    head = np.abs((estimates[:, 2] - walk.poses[:, 2] + np.pi) % (2 * np.pi) - np.pi)
    return pos, head


def localizer(seed=0, field="simspark", kind="simspark", height=0.5, **params):
    return Localizer(field, kind, height, LocalizationParams(**params),
                     np.random.default_rng(seed))


# -- convergence, tracking, kidnapping ------------------------------------------------------
@pytest.mark.parametrize("seed", range(5))
def test_converges_from_a_uniform_prior_within_3_s(seed):
    # walking toward the opponent goal: its posts and corner flags are in view
    walk = synthetic_walk(seed, 3.0, start=(-4.0 + seed, -3.0 + 1.5 * seed, 0.3 * seed - 0.6),
                          aim=(15.0, 0.0))
    loc = localizer(seed)
    assert loc.estimate().spread > 3.0  # the uniform prior: nowhere in particular
    pos, head = errors(walk, run(walk, loc))
    assert pos[-1] < 0.3 and head[-1] < math.radians(10.0), (pos[-1], head[-1])
    # and it got there before the end: the last second is all within the bounds
    assert pos[-50:].max() < 0.3 and head[-50:].max() < math.radians(10.0)


@pytest.mark.parametrize("seed", range(3))
def test_tracks_a_walking_player(seed):
    walk = synthetic_walk(100 + seed, 30.0)
    loc = localizer(seed)
    loc.beamed(walk.poses[0], spread=(0.5, 0.2))
    pos, head = errors(walk, run(walk, loc))
    rms = math.sqrt(np.mean(pos ** 2))
    assert rms < 0.2, (rms, np.percentile(pos, [50, 95, 100]))
    assert math.sqrt(np.mean(head ** 2)) < math.radians(5.0)


@pytest.mark.parametrize("seed", range(4))
def test_recovers_from_a_beam_to_an_unknown_pose_within_2_s(seed):
    rng = np.random.default_rng(50 + seed)
    kidnap = 301  # after 6 s of good tracking, between two looks
    target = (rng.uniform(-10, 10), rng.uniform(-6, 6), rng.uniform(-np.pi, np.pi))
    walk = synthetic_walk(200 + seed, 9.0, beams=[(kidnap, target)])
    loc = localizer(seed)
    loc.beamed(walk.poses[0])
    pos, head = errors(walk, run(walk, loc))
    assert pos[kidnap - 50:kidnap].max() < 0.3  # tracking before
    assert pos[kidnap] > 1.0  # the beam moved it away from its belief
    after = slice(kidnap + 100, None)  # 2 s later and on
    assert pos[after].max() < 0.3 and head[after].max() < math.radians(10.0), \
        (pos[after].max(), head[after].max())


def test_recovers_from_pushes_the_odometry_missed():
    rng = np.random.default_rng(8)
    pushes = [(int(t), (rng.uniform(-0.4, 0.4), rng.uniform(-0.4, 0.4), rng.normal(0, 0.15)))
              for t in (200, 420, 640, 860)]
    walk = synthetic_walk(9, 20.0, pushes=pushes)
    loc = localizer(3)
    loc.beamed(walk.poses[0])
    pos, head = errors(walk, run(walk, loc))
    for t, _ in pushes:  # within 1 s of each push it is back
        assert pos[t + 50:t + 200].max() < 0.3 and head[t + 50:t + 200].max() < 0.1


def test_sensor_resetting_uses_the_two_post_closed_form(monkeypatch):
    import strategy.perception.localization as module

    calls = []
    real = module.two_post_candidates

    def counting(*args):
        calls.append(len(np.atleast_1d(args[0])))
        return real(*args)

    monkeypatch.setattr(module, "two_post_candidates", counting)
    walk = synthetic_walk(0, 1.0, start=(8.0, 0.5, 0.0), aim=(15.0, 0.0))
    loc = localizer(0)  # the uniform prior: lost, so it resets from what it sees
    pos, _ = errors(walk, run(walk, loc))
    assert calls and sum(calls) > 0  # posts pairs were solved in closed form
    assert pos[-1] < 0.3


def test_known_beam_is_taken_at_once():
    walk = synthetic_walk(7, 1.0)
    loc = localizer(1)
    loc.beamed(walk.poses[0], spread=(0.05, 0.02))
    est = loc.estimate()
    assert np.hypot(*(est.pose[:2] - walk.poses[0, :2])) < 0.05
    assert est.spread < 0.15
    pos, _ = errors(walk, run(walk, loc))
    assert pos.max() < 0.3


def test_mj_profile_on_the_big_field():
    # RCSSServerMJ: no noise, 2-decimal truncation, 30 landmarks, no lines, every 2nd cycle
    walk = synthetic_walk(3, 20.0, field="mj7v7", kind="mj", height=1.1, period=2,
                          noise=Noise(0.0, 0.0, 0.0, 0.0, 0.0, 0.05), lines=False, speed=1.0)
    for obs in walk.observations:  # truncation toward zero (degrees / metres)
        if "landmarks" in obs:
            lm = obs["landmarks"]
            lm[:, 1] = np.trunc(lm[:, 1] * 100) / 100
            lm[:, 2:] = np.radians(np.trunc(np.degrees(lm[:, 2:]) * 100) / 100)
    loc = localizer(2, field="mj7v7", kind="mj", height=1.1)
    pos, head = errors(walk, run(walk, loc))
    assert pos[150:].max() < 0.3 and math.sqrt(np.mean(pos[150:] ** 2)) < 0.2


# -- pieces ---------------------------------------------------------------------------------
def test_two_post_pose_is_exact_and_rejects_the_off_field_candidate():
    field = field_preset("simspark")
    table = landmarks(field)
    rng = np.random.default_rng(0)
    for end in ("their", "own"):
        i, j = table.index(f"post_{end}_left"), table.index(f"post_{end}_right")
        posts = table.xyz[[i, j]]
        for _ in range(50):
            pose = np.array((rng.uniform(-14, 14), rng.uniform(-9.5, 9.5),
                             rng.uniform(-np.pi, np.pi)))
            seen = from_polar(to_polar(posts, *pose, 0.5), 0.5)[:, :2]  # (u, v) of each
            both = two_post_pose(seen[0], seen[1], posts[0, :2], posts[1, :2])
            assert len(both) == 2
            mirror = both[1]
            assert abs(mirror[0]) > field.half_length  # behind the goal line
            got = two_post_pose(seen[0], seen[1], posts[0, :2], posts[1, :2], field)
            assert got.shape == (1, 3)  # the off-field candidate is gone
            np.testing.assert_allclose(got[0, :2], pose[:2], atol=1e-9)
            assert abs((got[0, 2] - pose[2] + np.pi) % (2 * np.pi) - np.pi) < 1e-9
            np.testing.assert_allclose(both[0], got[0])  # best first without the field too


def test_two_landmark_candidates_contain_the_true_pose():
    field = field_preset("simspark")
    table = landmarks(field)
    rng = np.random.default_rng(1)
    for _ in range(50):
        i, j = rng.choice(len(table), 2, replace=False)
        pose = np.array((rng.uniform(-14, 14), rng.uniform(-9.5, 9.5),
                         rng.uniform(-np.pi, np.pi)))
        pol = to_polar(table.xyz[[i, j]], *pose, 0.5)
        ground = pol[:, 0] * np.cos(pol[:, 2])
        cand, residual = two_landmark_candidates(table.xyz[i, :2], table.xyz[j, :2],
                                                 ground[0], pol[0, 1], ground[1], pol[1, 1])
        best = cand[np.argmin(residual)]
        np.testing.assert_allclose(best, pose, atol=1e-7)


def test_motion_update_applies_the_scaled_odometry_in_each_particles_frame():
    loc = localizer(0, motion_noise_rel=(0.0, 0.0, 0.0), motion_noise_abs=(1e-12,) * 3,
                    gyro_noise_rad=1e-12)
    loc.beamed((1.0, 2.0, math.pi / 2), spread=(0.0, 0.0))
    loc.predict((0.11, 0.0, 0.0))  # 0.11 reported = 0.1 made (alpha = 1/1.1)
    np.testing.assert_allclose(loc.estimate().pose, (1.0, 2.1, math.pi / 2), atol=1e-9)
    loc.predict((0.0, 0.0, 0.5), gyro=0.2)  # the gyro replaces the odometry's turn
    assert loc.estimate().pose[2] == pytest.approx(math.pi / 2 + 0.2)
    no_gyro = localizer(0, use_gyro=False, motion_noise_rel=(0.0, 0.0, 0.0),
                        motion_noise_abs=(1e-12,) * 3)
    no_gyro.beamed((0.0, 0.0, 0.0), spread=(0.0, 0.0))
    no_gyro.predict((0.0, 0.0, 0.105), gyro=0.2)
    assert no_gyro.estimate().pose[2] == pytest.approx(0.1)


def test_resampling_is_systematic_and_keeps_the_count():
    loc = localizer(0, n_particles=8)
    batch = loc.batch
    w = np.array([[0.5, 0.0, 0.25, 0.25, 0.0, 0.0, 0.0, 0.0]])
    p = batch._p.copy()
    logw = np.log(np.maximum(w, 1e-300))
    batch._resample(p, logw, w, np.array([0]))
    # copies are N * w up to one: 4, 0, 2, 2, 0...
    src = [int(np.flatnonzero(batch._p[0, 0] == v)[0]) for v in p[0, 0]]
    assert np.bincount(src, minlength=8).tolist() == [4, 0, 2, 2, 0, 0, 0, 0]
    np.testing.assert_allclose(np.exp(logw[0]), 1 / 8)


def test_estimate_is_the_weighted_mean_with_a_circular_heading():
    loc = localizer(0, n_particles=4)
    b = loc.batch
    b._p[:, 0] = np.array([[0.0, 2.0, 0.0, 2.0], [0.0, 0.0, 1.0, 1.0],
                           [np.pi - 0.1, -np.pi + 0.1, np.pi - 0.1, -np.pi + 0.1]])
    b._logw[0] = np.log(0.25)
    b._estimate = None
    est = loc.estimate()
    assert isinstance(est, PoseEstimate)
    np.testing.assert_allclose(est.pose[:2], (1.0, 0.5))
    assert abs(abs(est.pose[2]) - np.pi) < 1e-9  # not 0: the circular mean
    np.testing.assert_allclose(np.diag(est.covariance), (1.0, 0.25, 0.01), atol=1e-9)
    assert est.spread == pytest.approx(math.sqrt(1.25))


def test_batch_filters_are_independent():
    walks = [synthetic_walk(s, 2.0) for s in (11, 12, 13)]
    batch = BatchLocalizer(3, "simspark", "simspark", 0.5, LocalizationParams(),
                           np.random.default_rng(9))
    for k, w in enumerate(walks):
        batch.beamed(k, w.poses[0])
    for t in range(len(walks[0].observations)):
        batch.observe([w.observations[t] for w in walks])
    est = batch.estimate()
    for k, w in enumerate(walks):
        assert np.hypot(*(est.pose[k, :2] - w.poses[-1, :2])) < 0.3
    # an agent whose sightings change does not move another agent's filter
    a = BatchLocalizer(2, "simspark", params=LocalizationParams(), rng=np.random.default_rng(1))
    b = BatchLocalizer(2, "simspark", params=LocalizationParams(), rng=np.random.default_rng(1))
    obs = walks[0].observations[0]
    a.correct([0], obs["landmarks"][None], obs["lines"][None])
    b.correct([0], obs["landmarks"][None], obs["lines"][None])
    a.correct([1], walks[1].observations[0]["landmarks"][None])
    np.testing.assert_array_equal(a.particles[0], b.particles[0])
    assert not np.array_equal(a.particles[1], b.particles[1])


# -- determinism, errors --------------------------------------------------------------------
def test_same_seed_same_result_bit_for_bit():
    walk = synthetic_walk(5, 3.0, beams=[(100, (3.0, -2.0, 1.0))])

    def once(seed):
        loc = localizer(seed)
        est = run(walk, loc)
        return est, loc.particles, loc.weights

    first, again, other = once(4), once(4), once(5)
    for x, y in zip(first, again, strict=True):
        np.testing.assert_array_equal(x, y)
    assert not np.array_equal(first[1], other[1])


@pytest.mark.parametrize("kwargs, words", [
    ({"n_particles": 0}, ["n_particles", "0"]),
    ({"n_particles": 2.5}, ["n_particles", "2.5"]),
    ({"sigma_bearing_deg": -1.0}, ["sigma_bearing_deg", "-1.0"]),
    ({"sigma_distance_m": float("nan")}, ["sigma_distance_m", "nan"]),
    ({"odometry_scale": (1.0, 0.0, 1.0)}, ["odometry_scale", "(1.0, 0.0, 1.0)"]),
    ({"motion_noise_abs": (0.1, 0.1)}, ["motion_noise_abs", "(0.1, 0.1)"]),
    ({"resample_ess": 1.5}, ["resample_ess", "1.5"]),
    ({"alpha_slow": 0.6, "alpha_fast": 0.5}, ["alpha_slow", "0.6"]),
    ({"distance_model": "polar"}, ["distance_model", "polar"]),
    ({"use_gyro": 1}, ["use_gyro", "1"]),
    ({"lost_share": 0.9, "max_reset_share": 0.5}, ["lost_share", "0.9"]),
])
def test_bad_params_name_field_and_value(kwargs, words):
    with pytest.raises(LocalizationError) as info:
        LocalizationParams(**kwargs)
    assert isinstance(info.value, TeamEnvError) and isinstance(info.value, ValueError)
    for word in words:
        assert word in str(info.value)


def test_bad_arguments_are_clear_errors():
    with pytest.raises(LocalizationError, match="rng"):
        Localizer("simspark")
    with pytest.raises(LocalizationError, match="landmark_kind"):
        Localizer("simspark", "flags", rng=np.random.default_rng(0))
    with pytest.raises(LocalizationError, match="unknown key"):
        LocalizationParams.from_overrides({"particles": 10})
    batch = BatchLocalizer(2, "simspark", rng=np.random.default_rng(0))
    with pytest.raises(LocalizationError, match="agents"):
        batch.predict([2], np.zeros((1, 3)))
    with pytest.raises(LocalizationError, match="once"):
        batch.predict([1, 1], np.zeros((2, 3)))
    with pytest.raises(LocalizationError, match="pose"):
        batch.beamed(0, (1.0, float("nan"), 0.0))
    assert LocalizationParams.from_overrides({"odometry_scale": [1, 1, 1]}).odometry_scale \
        == (1, 1, 1)


# -- in the env -----------------------------------------------------------------------------
def _team_frame(poses: np.ndarray, sign: float) -> np.ndarray:
    out = poses.copy()
    if sign < 0:  # the right team's frame: the world rotated by pi
        out[:, :2] *= -1.0
        out[:, 2] = (out[:, 2] + 2.0 * np.pi) % (2.0 * np.pi) - np.pi
    return out


@pytest.mark.parametrize("vision", ["simspark", "mj"])
def test_localizes_every_agent_in_the_env_vision_mode(vision):
    import teamenv

    env = teamenv.parallel_env(observation_mode="vision", vision=vision, field="mj7v7",
                               team_size=2, profile_phases=False)
    obs, _ = env.reset(seed=3)
    cam = env.perception
    teams = {side: [a for a in env.agents if a.startswith(side)] for side in ("left", "right")}
    locs = {side: BatchLocalizer(2, env.field, cam.landmark_kind, cam.camera_height_m,
                                 LocalizationParams(), np.random.default_rng(k))
            for k, side in enumerate(teams)}
    kidnap, victim = 451, 1  # the second left player, teleported between two looks
    pos_err, head_err = [], []
    for t in range(900):
        world = env.sim.world.player_poses()
        errs, heads = [], []
        for side, agents in teams.items():
            est = locs[side].observe([obs[a] for a in agents])
            sign = env.sim.referee.attack_sign[0 if side == "left" else 1]
            rows = slice(0, 2) if side == "left" else slice(2, 4)
            truth = _team_frame(world[rows], sign)
            errs.append(np.hypot(*(est.pose[:, :2] - truth[:, :2]).T))
            heads.append(np.abs((est.pose[:, 2] - truth[:, 2] + np.pi) % (2 * np.pi) - np.pi))
        pos_err.append(np.concatenate(errs))
        head_err.append(np.concatenate(heads))
        actions = {a: {"walk": np.array([0.8, 0.1 * math.sin(t / 20.0),
                                         0.6 * math.sin(t / 70.0 + i)], dtype=np.float32)}
                   for i, a in enumerate(env.agents)}
        if t == kidnap - 1:  # moved before the step: odometry and gyro do not feel it
            env.sim.world.place_player(victim, 5.0, -8.0, 2.5)
        obs, *_ = env.step(actions)
    pos_err, head_err = np.array(pos_err), np.array(head_err)
    assert env.sim.referee.mode.name == "PlayOn"  # the walk went on through the kick-off
    settled = np.r_[50:kidnap, kidnap + 100:900]
    assert math.sqrt(np.mean(pos_err[settled] ** 2)) < 0.2, np.percentile(pos_err, [50, 95])
    assert pos_err[settled].max() < 0.5 and head_err[settled].max() < math.radians(10.0)
    assert pos_err[kidnap, victim] > 5.0  # the teleport was news to it


def test_bad_input_shapes_are_clear_errors():
    batch = BatchLocalizer(2, "simspark", rng=np.random.default_rng(0))
    with pytest.raises(LocalizationError, match=r"odometry must have shape \(2, 3\)"):
        batch.predict(None, np.zeros(3))
    with pytest.raises(LocalizationError, match="landmarks must have shape"):
        batch.correct(None, np.zeros((2, 5, 4)))
    with pytest.raises(LocalizationError, match="lines must have shape"):
        batch.correct(None, np.zeros((2, 8, 4)), np.zeros((2, 3, 6)))
    before = batch.particles
    batch.correct(None, np.zeros((2, 8, 4)), np.zeros((2, 0, 7)))  # nothing seen: no change
    np.testing.assert_array_equal(batch.particles, before)
