"""observation_mode="vision": the league's restricted vision (teamenv.sim.vision)."""

from __future__ import annotations

import hashlib
import math

import numpy as np
import pytest

import teamenv
from teamenv import VISION_PROFILES, PerceptionConfig
from teamenv.box_layout import N_PLAY_MODES
from teamenv.errors import ConfigError
from teamenv.landmarks import field_lines, from_polar, landmarks, to_polar
from teamenv.match import MatchOptions, play_match
from teamenv.sim.playmode import PlayMode

EXACT = dict(distance_sigma_rel=0.0, azimuth_sigma_deg=0.0, elevation_sigma_deg=0.0,
             calibration_error_m=0.0, gyro_sigma_rad=0.0)
TEAM = "tests.teamenv.vision_teams:BallTurner"
DICT_KEYS = {"landmarks", "ball", "teammates", "opponents", "lines", "vision", "counts",
             "odometry", "gyro", "body", "play_mode", "game", "heard_text", "heard"}


def vision_env(team_size=2, seed=0, **kwargs):
    env = teamenv.parallel_env(team_size=team_size, observation_mode="vision", **kwargs)
    env.reset(seed=seed)
    return env


def park(env, keep=()):
    """Every player not in ``keep`` far behind the camera of player 0 (x < -10, facing -x)."""
    for i in range(env.sim.n):
        if i not in keep:
            env.sim.world.place_player(i, -12.0 + 0.6 * (i % 6), -8.0 + 1.5 * (i // 6), math.pi)


def look(env):
    """A new look (Dict form) of every agent at the current cycle."""
    return env.sim.observations()


def team_frame_pose(env, i):
    x, y, h = env.sim.world.player_poses()[i]
    sign = env.sim.referee.attack_sign[int(env.sim.team_of[i])]
    return sign * x, sign * y, (h if sign > 0 else h + math.pi), sign


def random_walk_actions(env, rng):
    return {a: {"walk": rng.uniform([-0.5, -0.3, -1.0], [1.2, 0.3, 1.0]).astype(np.float32)}
            for a in env.agents}


# -- the observation ---------------------------------------------------------------------
def test_keys_shapes_and_no_own_pose():
    env = vision_env(team_size=3)
    obs = look(env)[0]
    assert set(obs) == DICT_KEYS
    assert "self" not in obs
    shapes = {k: np.shape(v) for k, v in obs.items() if k not in ("play_mode", "heard_text")}
    assert shapes == {"landmarks": (8, 4), "ball": (4,), "teammates": (3, 4),
                      "opponents": (3, 4), "lines": (len(field_lines(env.field)), 7),
                      "vision": (2,), "counts": (4,), "odometry": (3,), "gyro": (1,),
                      "body": (2,), "game": (4,), "heard": (3, 4)}
    # No own position anywhere: an odd pose does not appear in the flat vector.
    box = vision_env(team_size=3, observation_format="box", perception=EXACT)
    box.sim.world.place_player(0, -7.123457, 3.217654, 0.4321)
    flat = box.sim.observations(flat=True)[0]
    for value in (-7.123457, 3.217654, 0.4321):
        assert not np.any(np.isclose(flat, value, atol=1e-4)), value
    # The own row is never present (every teammate is in view: they stand in front).
    for k in range(3):
        box.sim.world.place_player(k, -5.0 + 2.0 * k, 0.0, 0.0)
    rows = box.sim.observations()
    for k in range(3):
        mates = rows[k]["teammates"]
        assert mates[k, 0] == 0.0 and not mates[k].any()
    assert rows[0]["teammates"][1, 0] == 1.0 and rows[0]["teammates"][2, 0] == 1.0
    assert rows[0]["body"][1] == 0.0  # the fixed head: pan 0


def test_exact_sightings_are_to_polar_of_the_true_state():
    env = vision_env(team_size=2, perception=EXACT)
    sim = env.sim
    sim.world.place_ball(3.0, 1.0)
    obs = look(env)
    lm = landmarks(env.field, "simspark")
    for i in range(sim.n):
        x, y, h, sign = team_frame_pose(env, i)
        want = to_polar(lm.xyz, x, y, h, 0.5)
        got = obs[i]["landmarks"]
        for k in range(len(lm)):
            if got[k, 0]:
                np.testing.assert_allclose(got[k, 1:], want[k], rtol=1e-6, atol=1e-6)
            else:
                assert abs(math.degrees(want[k, 1])) > 60 or abs(math.degrees(want[k, 2])) > 60
        ball = np.array([[sign * 3.0, sign * 1.0, sim.physics.ball_radius]])
        want_ball = to_polar(ball, x, y, h, 0.5)[0]
        if obs[i]["ball"][0]:
            np.testing.assert_allclose(obs[i]["ball"][1:], want_ball, rtol=1e-6, atol=1e-6)
        assert obs[i]["counts"][0] == got[:, 0].sum()


@pytest.mark.parametrize("side_sign", [1.0, -1.0])
def test_horizontal_cone(side_sign):
    env = vision_env(perception=EXACT)
    park(env, keep=(0,))
    env.sim.world.place_player(0, 0.0, 0.0, 0.0)
    for deg, seen in ((59.0, True), (61.0, False), (0.0, True), (119.0, False)):
        a = math.radians(deg) * side_sign
        env.sim.world.place_ball(3.0 * math.cos(a), 3.0 * math.sin(a))
        ball = look(env)[0]["ball"]
        assert bool(ball[0]) is seen, deg
        if seen:
            assert ball[2] == pytest.approx(a, abs=1e-6)
        else:
            assert not ball.any()


def test_vertical_cone_and_min_distance():
    env = vision_env(perception=EXACT)
    park(env, keep=(0, 1))
    env.sim.world.place_player(0, 0.0, 0.0, 0.0)
    drop = 0.5 - env.sim.physics.ball_radius  # the camera is 0.5 m above the ball's centre
    for ground, seen in ((drop / math.tan(math.radians(59)), True),
                         (drop / math.tan(math.radians(61)), False)):
        env.sim.world.place_ball(ground, 0.0)
        assert bool(look(env)[0]["ball"][0]) is seen, ground
    # Players are points at camera height: a teammate 0.08 m away is dropped, 0.15 m is seen.
    env.sim.world.place_ball(5.0, 0.0)
    for gap, seen in ((0.08, False), (0.15, True)):
        env.sim.world.players[1].position = (gap, 0.0)
        env.sim.world._invalidate()
        row = look(env)[0]["teammates"][1]
        assert bool(row[0]) is seen, gap
        if seen:
            assert row[1] == pytest.approx(gap, abs=1e-6)


@pytest.mark.parametrize("vision, period", [("simspark", 3), ("mj", 2)])
def test_update_period(vision, period):
    env = vision_env(team_size=2, vision=vision, field="simspark")
    rng = np.random.default_rng(0)
    obs = env.reset(seed=1)[0]
    sightings = ("landmarks", "ball", "teammates", "opponents", "lines", "counts")
    for cycle in range(13):
        assert env.sim.cycle == cycle
        for o in obs.values():
            fresh = cycle % period == 0
            assert o["vision"][0] == (1.0 if fresh else 0.0)
            assert o["vision"][1] == cycle % period
            if not fresh:
                assert all(not o[k].any() for k in sightings)
        if cycle % period == 0:
            assert sum(o["counts"][0] for o in obs.values()) > 0
        obs = env.step(random_walk_actions(env, rng))[0]


def test_mj_values_are_truncated_and_noise_free():
    env = vision_env(team_size=3, vision="mj", field="mj7v7", seed=4)
    rng = np.random.default_rng(4)
    lm = landmarks(env.field, "mj")
    assert env.observation_space("left_1")["lines"].shape == (0, 7)
    checked = 0

    def trunc2(v):
        return np.trunc(v * 100.0) / 100.0

    for _ in range(40):
        obs = env.step(random_walk_actions(env, rng))[0]
        if env.sim.cycle % 2:
            continue
        ball = env.sim.world.ball_state()
        for agent, o in obs.items():
            i = env._row[agent]
            x, y, h, sign = team_frame_pose(env, i)
            points = np.vstack([lm.xyz, [sign * ball[0], sign * ball[1], 0.042]])
            want = to_polar(points, x, y, h, 1.1)
            deg = trunc2(np.degrees(want[:, 1:]))
            visible = (np.abs(deg) <= 60.0).all(axis=1)
            got = np.vstack([o["landmarks"], o["ball"]])
            np.testing.assert_array_equal(got[:, 0], visible.astype(np.float32))
            np.testing.assert_allclose(got[visible, 1], trunc2(want[visible, 0]), atol=1e-5)
            np.testing.assert_allclose(got[visible, 2:], np.radians(deg[visible]), atol=1e-6)
            # Two decimals of a degree / of a metre, nothing finer.
            cents = np.degrees(got[visible, 2:].astype(np.float64)) * 100.0
            np.testing.assert_allclose(cents, np.round(cents), atol=1e-3)
            checked += int(visible.sum())
    assert checked > 100


def test_right_team_sees_the_mirrored_world():
    env = vision_env(team_size=3, perception=EXACT)
    world, n = env.sim.world, 3
    rng = np.random.default_rng(0)
    for k in range(n):  # right player k stands where left player k would, rotated by pi
        x, y, h = rng.uniform(-10, 10), rng.uniform(-7, 7), rng.uniform(-3, 3)
        world.place_player(k, x, y, h)
        world.place_player(n + k, -x, -y, h + math.pi)
    world.place_ball(1.5, -2.0)
    obs = look(env)
    for k in range(n):
        left, right = obs[k], obs[n + k]
        for key in ("landmarks", "ball", "teammates", "opponents", "lines", "counts"):
            np.testing.assert_allclose(left[key], right[key], atol=2e-5, err_msg=key)
    assert sum(obs[k]["counts"][0] for k in range(n)) > 0


@pytest.mark.parametrize("occlusion", [True, False])
def test_occlusion(occlusion):
    env = vision_env(perception=dict(EXACT, occlusion=occlusion))
    park(env, keep=(0, 1, 2))
    world = env.sim.world
    world.place_player(0, 0.0, 0.0, 0.0)
    world.place_player(1, 2.0, 0.0, 0.0)    # a teammate 2 m ahead
    world.place_player(2, 4.0, 0.05, 0.0)   # an opponent right behind it
    world.place_ball(6.0, -0.03)            # the ball behind both
    o = look(env)[0]
    assert o["teammates"][1, 0] == 1.0  # the nearer one is always seen
    assert o["opponents"][0, 0] == (0.0 if occlusion else 1.0)
    assert o["ball"][0] == (0.0 if occlusion else 1.0)
    # Beside the disc it is seen either way.
    world.place_player(2, 4.0, 1.5, 0.0)
    assert look(env)[0]["opponents"][0, 0] == 1.0


def test_odometry_is_the_bodies_and_gyro_the_heading_change():
    env = vision_env(team_size=2, perception={"gyro_sigma_rad": 0.0})
    sim = env.sim
    reported = []
    step = sim.bodies.step

    def spy(*args, **kwargs):
        res = step(*args, **kwargs)
        reported.append(np.array(res.odometry))
        return res

    sim.bodies.step = spy
    rng = np.random.default_rng(2)
    moved = 0
    for _ in range(60):
        before = sim.world.player_poses()[:, 2].copy()
        obs = env.step(random_walk_actions(env, rng))[0]
        after_physics = sim.turn
        for agent, o in obs.items():
            i = env._row[agent]
            np.testing.assert_allclose(o["odometry"], reported[-1][i], rtol=1e-6, atol=1e-7)
            assert o["gyro"][0] == pytest.approx(after_physics[i], abs=1e-6)
        if not env.sim.referee.mode == PlayMode.BeforeKickOff:
            turned = sim.world.player_poses()[:, 2] - before
            moved += int(np.abs(turned).max() > 1e-4)
    assert moved > 0
    assert np.abs(np.concatenate(reported)).max() > 0.0


def test_gyro_noise():
    env = vision_env(team_size=11, perception={"gyro_sigma_rad": 0.002})
    errs = []
    for _ in range(250):
        obs = env.step({a: {} for a in env.agents})[0]
        for agent, o in obs.items():
            errs.append(o["gyro"][0] - env.sim.turn[env._row[agent]])
    assert np.std(errs) == pytest.approx(0.002, rel=0.1)


# -- noise -------------------------------------------------------------------------------
def test_noise_statistics_and_calibration():
    profile = VISION_PROFILES["simspark"]
    env = vision_env(team_size=1)
    sim = env.sim
    calib = sim.vision.calibration.copy()
    assert np.all(np.abs(calib) <= profile.calibration_error_m) and np.any(calib != 0)
    park(env, keep=(0,))
    sim.world.place_player(0, 0.0, 0.0, 0.0)
    sim.world.place_ball(4.0, 1.0)
    samples = np.array([look(env)[0]["ball"] for _ in range(5000)], dtype=np.float64)
    assert samples[:, 0].all()
    true = to_polar(np.array([[4.0, 1.0, sim.physics.ball_radius]]), 0, 0, 0, 0.5)[0]
    # The spread is the stated sigma (within 10 %) ...
    rel = samples[:, 1] / true[0] - 1.0
    assert rel.std() == pytest.approx(profile.distance_sigma_rel, rel=0.1)
    assert samples[:, 2].std() == pytest.approx(math.radians(profile.azimuth_sigma_deg), rel=0.1)
    assert samples[:, 3].std() == pytest.approx(math.radians(profile.elevation_sigma_deg),
                                                rel=0.1)
    # ... around the calibrated view: the sighting of the point seen from the camera moved
    # by minus the calibration error (bounded: <= 0.005 m per axis).
    shifted = to_polar(np.array([[4.0, 1.0, sim.physics.ball_radius]]), -calib[0, 0],
                       -calib[0, 1], 0.0, 0.5 - calib[0, 2])[0]
    mean = samples[:, 1:].mean(axis=0)
    n = len(samples)
    assert abs(mean[0] - shifted[0]) < 4 * true[0] * profile.distance_sigma_rel / math.sqrt(n)
    assert abs(mean[1] - shifted[1]) < 4 * math.radians(profile.azimuth_sigma_deg) / math.sqrt(n)
    assert abs(mean[0] - true[0]) <= math.sqrt(3) * 0.005 + 1e-3
    # Constant within a match, redrawn (differently) for another seed.
    for _ in range(30):
        env.step({a: {} for a in env.agents})
    np.testing.assert_array_equal(sim.vision.calibration, calib)
    env.reset(seed=1)
    assert not np.array_equal(sim.vision.calibration, calib)


def test_lines_are_clipped_to_the_cone():
    rng = np.random.default_rng(5)
    for fov in (120.0, 60.0, 270.0):
        env = vision_env(team_size=1, perception=dict(EXACT, fov_horizontal_deg=fov))
        segs = field_lines(env.field)
        half = math.radians(fov / 2)
        seen_any = 0
        for _ in range(25):
            x, y, h = rng.uniform(-14, 14), rng.uniform(-9, 9), rng.uniform(-np.pi, np.pi)
            env.sim.world.place_player(0, x, y, h)
            x, y, h = env.sim.world.player_poses()[0]
            lines = look(env)[0]["lines"]
            for k, (x1, y1, x2, y2) in enumerate(segs):
                t = np.linspace(0.0, 1.0, 2001)
                px, py = x1 + t * (x2 - x1), y1 + t * (y2 - y1)
                az = np.arctan2(py - y, px - x) - h
                az = (az + np.pi) % (2 * np.pi) - np.pi
                inside = np.abs(az) <= half
                row = lines[k]
                if bool(row[0]) != bool(inside.any()):  # only where it grazes the edge
                    assert np.min(np.abs(np.abs(az) - half)) < 2e-3, (fov, k)
                if not row[0]:
                    assert not row.any()
                    continue
                seen_any += 1
                ends = from_polar(np.array([row[1:4], row[4:7]], dtype=np.float64), 0.5)
                c, s = math.cos(h), math.sin(h)
                wx = x + c * ends[:, 0] - s * ends[:, 1]
                wy = y + s * ends[:, 0] + c * ends[:, 1]
                # Both ends lie on the segment, inside the cone, on the ground ...
                np.testing.assert_allclose(ends[:, 2], 0.0, atol=1e-4)
                d = np.array([x2 - x1, y2 - y1])
                along = ((wx - x1) * d[0] + (wy - y1) * d[1]) / (d @ d)
                cross = ((wx - x1) * d[1] - (wy - y1) * d[0]) / math.sqrt(d @ d)
                np.testing.assert_allclose(cross, 0.0, atol=1e-3)
                assert np.all(np.abs(row[[2, 5]]) <= half + 1e-5)
                # ... and (in a convex cone) they span every visible sample of it.
                if fov <= 180:
                    lo, hi = sorted(along)
                    assert t[inside].min() >= lo - 1e-3 and t[inside].max() <= hi + 1e-3
        assert seen_any > 20


# -- determinism -------------------------------------------------------------------------
def _feed(h, value):
    if isinstance(value, dict):
        for k in sorted(value):
            h.update(str(k).encode())
            _feed(h, value[k])
    elif isinstance(value, (tuple, list)):
        for v in value:
            _feed(h, v)
    elif isinstance(value, str):
        h.update(value.encode() + b"\0")
    else:
        h.update(np.asarray(value).tobytes())


def trajectory(seed, steps=300, **kwargs):
    """(digest of observations and rewards, digest of env.state() per cycle)."""
    env = teamenv.parallel_env(team_size=3, action_format="box", **kwargs)
    obs, _ = env.reset(seed=seed)
    rng = np.random.default_rng(seed)
    h, world = hashlib.sha256(), hashlib.sha256()
    _feed(h, obs)
    for _ in range(steps):
        obs, rew, *_ = env.step({a: rng.uniform(-1, 1, 9).astype(np.float32)
                                 for a in env.agents})
        _feed(h, obs)
        _feed(h, rew)
        world.update(env.state().tobytes())
    return h.hexdigest(), world.hexdigest()


@pytest.mark.parametrize("vision", ["simspark", "mj"])
def test_same_seed_same_vision_match(vision):
    a = trajectory(3, observation_mode="vision", vision=vision)
    assert a == trajectory(3, observation_mode="vision", vision=vision)
    assert a[0] != trajectory(4, observation_mode="vision", vision=vision)[0]
    # Vision draws from its own generator: the world moves exactly as in state mode.
    assert a[1] == trajectory(3)[1]


# Digests of state-mode trajectories computed before vision existed (commit 89170c1):
# state mode must stay bit for bit what it was.
STATE_DIGESTS = {
    "dict": "4293e4b28385ba1fdab1b892266e78fcb33cdfff76aaf2d2e24e1791aa6f7931",
    "box": "82c05b494ac38dd5844b93d4cb0c8ad15462bfdd0f575e46cf9601460557b6eb",
}


@pytest.mark.parametrize("fmt", ["dict", "box"])
def test_state_mode_unchanged(fmt):
    env = teamenv.parallel_env(team_size=3, action_format="box", observation_format=fmt)
    obs, _ = env.reset(seed=11)
    rng = np.random.default_rng(11)
    h = hashlib.sha256()
    _feed(h, obs)
    for _ in range(600):
        obs, rew, *_ = env.step({a: rng.uniform(-1, 1, 9).astype(np.float32)
                                 for a in env.agents})
        _feed(h, obs)
        _feed(h, rew)
    _feed(h, env.state())
    assert h.hexdigest() == STATE_DIGESTS[fmt]


# -- forms and spaces --------------------------------------------------------------------
@pytest.mark.parametrize("vision, field", [("simspark", "simspark"), ("mj", "mj7v7")])
def test_box_and_dict_forms_agree_and_lie_in_their_spaces(vision, field):
    envs = {fmt: teamenv.parallel_env(team_size=2, observation_mode="vision", vision=vision,
                                      field=field, observation_format=fmt)
            for fmt in ("dict", "box")}
    obs = {fmt: env.reset(seed=9)[0] for fmt, env in envs.items()}
    rng = np.random.default_rng(9)
    layout = envs["dict"].sim.vision.layout
    order = [key for key, _ in layout.parts]
    assert order[:5] == ["landmarks", "ball", "teammates", "opponents", "lines"]
    for _ in range(8):
        for agent in envs["dict"].agents:
            d, b = obs["dict"][agent], obs["box"][agent]
            assert envs["dict"].observation_space(agent).contains(d)
            assert envs["box"].observation_space(agent).contains(b)
            assert b.dtype == np.float32 and b.shape == (layout.size,)
            parts = []
            for key in order:
                if key == "play_mode":
                    one_hot = np.zeros(N_PLAY_MODES, np.float32)
                    one_hot[d["play_mode"]] = 1.0
                    parts.append(one_hot)
                else:
                    parts.append(np.asarray(d[key], np.float32).ravel())
            np.testing.assert_array_equal(np.concatenate(parts), b)
        actions = random_walk_actions(envs["dict"], rng)
        obs = {fmt: env.step(actions)[0] for fmt, env in envs.items()}


def test_timings_cover_vision():
    env = vision_env(team_size=2)
    env.reset_timings()
    for _ in range(30):
        env.step({a: {} for a in env.agents})
    assert env.timings()["perception"] > 0.0
    assert env.sim.phase_s["perception"] > 0.0


# -- options -----------------------------------------------------------------------------
@pytest.mark.parametrize("kwargs, words", [
    (dict(vision="moon"), ["vision", "'moon'"]),
    (dict(perception={"fov_wide": 3}), ["perception", "fov_wide"]),
    (dict(perception={"azimuth_sigma_deg": -1.0}), ["azimuth_sigma_deg", "-1.0"]),
    (dict(perception={"distance_sigma_rel": float("nan")}), ["distance_sigma_rel", "nan"]),
    (dict(perception={"fov_horizontal_deg": 0.0}), ["fov_horizontal_deg", "0.0"]),
    (dict(perception={"fov_vertical_deg": 400}), ["fov_vertical_deg", "400"]),
    (dict(perception={"update_period_cycles": 0}), ["update_period_cycles", "0"]),
    (dict(perception={"update_period_cycles": 1.5}), ["update_period_cycles", "1.5"]),
    (dict(perception={"truncate_decimals": "2"}), ["truncate_decimals", "'2'"]),
    (dict(perception={"landmark_kind": "flags"}), ["landmark_kind", "'flags'"]),
    (dict(perception={"camera_height_m": 0}), ["camera_height_m", "0"]),
    (dict(perception={"lines": 1}), ["lines", "1"]),
    (dict(perception=[1, 2]), ["PerceptionConfig", "[1, 2]"]),
])
def test_bad_options_name_field_and_value(kwargs, words):
    with pytest.raises(ConfigError) as err:
        teamenv.parallel_env(team_size=1, observation_mode="vision", **kwargs)
    for word in words:
        assert word in str(err.value), (word, str(err.value))


@pytest.mark.parametrize("kwargs, word", [(dict(vision="mj"), "vision"),
                                          (dict(perception={"occlusion": True}), "perception")])
def test_vision_options_in_state_mode_are_an_error(kwargs, word):
    with pytest.raises(ConfigError, match=f"{word}: .*observation_mode is 'state'"):
        teamenv.parallel_env(team_size=1, **kwargs)


def test_profiles_and_overrides():
    env = teamenv.parallel_env(team_size=1, observation_mode="vision", vision="mj",
                               perception={"occlusion": True})
    cfg = env.perception
    assert cfg.update_period_cycles == 2 and cfg.truncate_decimals == 2 and not cfg.lines
    assert cfg.occlusion and cfg.camera_height_m == 1.1 and cfg.landmark_kind == "mj"
    assert env.vision == "mj"
    simspark = VISION_PROFILES["simspark"]
    assert simspark == PerceptionConfig()
    assert (simspark.update_period_cycles, simspark.fov_horizontal_deg,
            simspark.fov_vertical_deg, simspark.min_distance_m) == (3, 120.0, 120.0, 0.1)
    assert simspark.distance_sigma_rel == pytest.approx(0.0965 / 100)
    assert (simspark.azimuth_sigma_deg, simspark.elevation_sigma_deg) == (0.1480, 0.1225)
    assert simspark.calibration_error_m == 0.005 and simspark.camera_height_m == 0.5
    given = PerceptionConfig(update_period_cycles=5)
    assert teamenv.parallel_env(team_size=1, observation_mode="vision",
                                perception=given).perception is given


# -- teams, matches, tournaments ---------------------------------------------------------
def test_team_context_and_a_vision_team_plays():
    env = teamenv.parallel_env(team_size=2, observation_mode="vision", vision="mj",
                               right=TEAM, rules={"half_time_s": 4.0, "halves": 1})
    team = env.teams["right"]
    ctx = team.context
    assert ctx.perception == VISION_PROFILES["mj"] and ctx.vision == "mj"
    assert ctx.landmark_kind == "mj" and ctx.observation_mode == "vision"
    env.reset(seed=0)
    while not env.episode_over:
        env.step({a: {} for a in env.agents})
    assert team.seen_ball > 0


def test_state_context_has_no_camera():
    env = teamenv.parallel_env(team_size=1)
    from teamenv.teams import TeamContext

    ctx = TeamContext(side="left", agents=("left_1",), team_size=1, field=env.field,
                      cycle_s=0.02, channel="simspark", observation_mode="state", seed=0)
    assert ctx.perception is None and ctx.landmark_kind is None and ctx.vision is None


def test_match_and_cli_in_vision_mode(capsys):
    options = MatchOptions(team_size=2, half_time_s=2.0, halves=1, observation_mode="vision",
                           vision="mj")
    result = play_match(TEAM, TEAM, seed=3, options=options)
    assert result.forfeit is None and result.cycles > 50
    assert result.options.vision == "mj"
    assert play_match(TEAM, TEAM, seed=3, options=options).score == result.score
    from teamenv.cli import main

    assert main(["match", TEAM, TEAM, "--team-size", "1", "--half-time", "1", "--halves", "1",
                 "--observation", "vision", "--vision", "mj", "--json"]) == 0
    assert '"vision": "mj"' in capsys.readouterr().out
    assert main(["match", TEAM, TEAM, "--team-size", "1", "--half-time", "1",
                 "--observation", "vision", "--vision", "moon"]) == 2
    assert "vision" in capsys.readouterr().err


def test_tournament_option():
    from teamenv.tournament.errors import TournamentConfigError
    from teamenv.tournament.schedule import Tournament
    from teamenv.tournament.spec import parse_team_spec, validate_specs

    options = MatchOptions(team_size=1, half_time_s=1.0, halves=1, observation_mode="vision",
                           vision="mj")
    validate_specs([parse_team_spec(TEAM)], options)
    with pytest.raises(TournamentConfigError, match="vision"):
        validate_specs([], MatchOptions(observation_mode="vision", vision="moon"))
    with pytest.raises(TournamentConfigError, match="vision"):
        validate_specs([], MatchOptions(vision="mj"))  # state mode
    t = Tournament(name="v", teams=("chaser", "static"), options=options)
    stored = t.to_json()
    assert stored["options"]["vision"] == "mj"
    assert Tournament.from_json(stored).options == options
    keys = {task.key for task in t.schedule()}
    plain = Tournament(name="v", teams=("chaser", "static"),
                       options=MatchOptions(team_size=1, half_time_s=1.0, halves=1,
                                            observation_mode="vision"))
    assert keys.isdisjoint({task.key for task in plain.schedule()})
    # Without vision the stored options are what they were before the option existed.
    assert "vision" not in MatchOptions().to_dict()
    assert Tournament.from_json(plain.to_json()).options.vision is None
