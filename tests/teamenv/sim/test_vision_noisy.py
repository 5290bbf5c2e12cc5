"""The ``mj_noisy`` vision profile: the detection model of the league server's next vision
(noise sigma 1 % of the distance and 0.5 degrees, 1 % missed, 5 % misclassified, false
detections, occlusion), measured on many samples against the noiseless ``mj`` camera, seeded,
and played by the teams."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

import teamenv
from teamenv.config import VISION_PROFILES, PerceptionConfig
from teamenv.errors import ConfigError
from teamenv.field import field_preset
from teamenv.sim.playmode import PlayMode
from teamenv.sim.vision import VisionPerception

FIELD = field_preset("mj7v7")
NOISY = VISION_PROFILES["mj_noisy"]
QUIET = replace(NOISY, distance_sigma_rel=0.0, azimuth_sigma_deg=0.0, elevation_sigma_deg=0.0,
                missed_rate=0.0, misclassified_rate=0.0, false_rate=0.0)
N = 7  # per side


def sightings(config: PerceptionConfig, updates: int, seed: int = 0) -> np.ndarray:
    """(updates, 2N, K + 1, 4) every agent's landmark and ball rows over ``updates`` vision
    updates, the players at random poses (the same poses for every config: pose seed 99)."""
    vision = VisionPerception(FIELD, N, 8, config, 0.2, 0.042)
    vision.reset(np.random.default_rng(seed))
    poses_rng = np.random.default_rng(99)
    out = []
    for u in range(updates):
        poses = np.column_stack([poses_rng.uniform(-25, 25, 2 * N),
                                 poses_rng.uniform(-16, 16, 2 * N),
                                 poses_rng.uniform(-math.pi, math.pi, 2 * N)])
        ball = np.array([poses_rng.uniform(-20, 20), poses_rng.uniform(-12, 12), 0.0, 0.0])
        frame = vision.observe(u * config.update_period_cycles, poses, ball,
                               np.zeros(2 * N), np.zeros((2 * N, 3)), np.zeros(2 * N),
                               PlayMode.PlayOn, 0.0, 1, (0, 0), (1.0, -1.0),
                               np.zeros((2 * N, 8, 4)), [("",) * 8] * (2 * N))
        rows = vision.as_dicts(frame)
        out.append([np.vstack([r["landmarks"], r["ball"][None, :]]) for r in rows])
    return np.asarray(out, dtype=np.float64)


@pytest.fixture(scope="module")
def truth():
    return sightings(QUIET, 1500)


def test_the_profile_is_the_servers_next_vision_on_top_of_mj():
    mj = VISION_PROFILES["mj"]
    assert replace(QUIET, occlusion=False) == mj  # the rest is the 0.2.1 camera
    assert (NOISY.distance_sigma_rel, NOISY.azimuth_sigma_deg, NOISY.elevation_sigma_deg) == \
        (0.01, 0.5, 0.5)
    assert (NOISY.missed_rate, NOISY.misclassified_rate, NOISY.false_rate, NOISY.false_max) == \
        (0.01, 0.05, 0.001, 5)
    assert NOISY.occlusion and NOISY.fov_horizontal_deg == NOISY.fov_vertical_deg == 120.0
    assert not mj.detection_errors and NOISY.detection_errors


def test_noise_has_the_profiles_standard_deviations(truth):
    noisy = sightings(replace(NOISY, missed_rate=0.0, misclassified_rate=0.0, false_rate=0.0),
                      1500)
    both = (truth[..., 0] > 0) & (noisy[..., 0] > 0)
    assert both.sum() > 50_000
    rel = (noisy[..., 1] - truth[..., 1])[both] / truth[..., 1][both]
    d_az = np.degrees(noisy[..., 2] - truth[..., 2])[both]
    d_el = np.degrees(noisy[..., 3] - truth[..., 3])[both]
    # 2-decimal truncation adds a little (< 0.01 m, < 0.01 degrees) to each
    assert 0.0095 < rel.std() < 0.0108 and abs(rel.mean()) < 0.0005
    assert 0.48 < d_az.std() < 0.53 and abs(d_az.mean()) < 0.02
    assert 0.48 < d_el.std() < 0.53 and abs(d_el.mean()) < 0.02


def test_missed_sightings_are_one_percent(truth):
    missed = sightings(replace(QUIET, missed_rate=NOISY.missed_rate), 1500)
    seen = truth[..., 0] > 0
    assert not (missed[..., 0] > 0)[~seen].any()           # nothing appears
    lost = 1.0 - (missed[..., 0] > 0)[seen].mean()
    assert 0.0088 < lost < 0.0112                           # 1 % +- 3.5 s.e. (n > 80 000)
    kept = seen & (missed[..., 0] > 0)
    np.testing.assert_array_equal(missed[kept], truth[kept])  # the rest is untouched


def test_misclassified_sightings_leave_their_row_five_percent_of_the_time(truth):
    mixed = sightings(replace(QUIET, misclassified_rate=NOISY.misclassified_rate), 1500)
    seen = truth[..., 0] > 0
    moved = ~np.all(mixed == truth, axis=-1) & seen
    share = moved.sum() / seen.sum()
    assert 0.046 < share < 0.054                            # 5 % +- 4 s.e.
    appeared = (mixed[..., 0] > 0) & ~seen                  # landed in a row not seen
    assert appeared.any()
    # what appears is a true sighting of another object: the same values seen elsewhere
    u, a, r = np.argwhere(appeared)[0]
    assert any(np.array_equal(mixed[u, a, r], truth[u, a, j]) for j in range(truth.shape[2]))
    assert appeared.sum() <= moved.sum()


def test_false_detections_come_at_the_profiles_rate_inside_the_cone(truth):
    made_up = sightings(replace(QUIET, false_rate=0.02), 1500)   # 20x: enough to count
    seen = truth[..., 0] > 0
    extra = (made_up[..., 0] > 0) & ~seen
    np.testing.assert_array_equal(made_up[seen], truth[seen])  # a true sighting keeps its row
    per_update = extra.sum() / (truth.shape[0] * truth.shape[1])
    expected = 5 * 0.02                                     # false_max tries of false_rate
    assert 0.6 * expected < per_update < 1.05 * expected    # some land on occupied rows
    d, az, el = (made_up[..., i][extra] for i in (1, 2, 3))
    assert d.min() >= 0.5 and d.max() <= 15.0
    assert np.abs(np.degrees(az)).max() <= 60.0 and np.abs(np.degrees(el)).max() <= 60.0


def test_same_seed_same_noisy_vision_and_another_seed_differs():
    a, b, c = (sightings(NOISY, 40, seed=s) for s in (5, 5, 6))
    np.testing.assert_array_equal(a, b)
    assert not np.array_equal(a, c)


def test_env_runs_are_reproducible_with_noisy_vision():
    def run(seed):
        env = teamenv.parallel_env(field="mj7v7", team_size=3, observation_mode="vision",
                                   vision="mj_noisy", channel="mj")
        obs, _ = env.reset(seed=seed)
        out = [obs["left_1"]["landmarks"].copy()]
        for _ in range(30):
            obs, *_ = env.step({a: {"walk": np.array([0.3, 0.0, 0.5], dtype=np.float32)}
                                for a in env.agents})
            out.append(obs["left_1"]["landmarks"].copy())
        env.close()
        return np.array(out)

    np.testing.assert_array_equal(run(3), run(3))
    assert not np.array_equal(run(3), run(4))


def test_teams_play_with_noisy_vision():
    env = teamenv.parallel_env(left="full", right="chaser", field="mj7v7", team_size=3,
                               observation_mode="vision", vision="mj_noisy", channel="mj",
                               rules={"half_time_s": 4.0})
    env.reset(seed=2)
    start = env.sim.world.player_poses()[:3, :2].copy()
    cycles = 0
    while not env.episode_over:
        env.step({})
        cycles += 1
    assert cycles >= 400  # both halves played, no team fault
    moved = np.hypot(*(env.sim.world.player_poses()[:3, :2] - start).T)
    assert moved.max() > 1.0  # the full team localized, found the ball and walked
    env.close()


@pytest.mark.parametrize("key, value", [("missed_rate", 1.5), ("misclassified_rate", -0.1),
                                        ("false_rate", float("nan")), ("false_max", 2.5),
                                        ("false_distance_m", (3.0, 1.0))])
def test_bad_detection_settings_name_the_field(key, value):
    with pytest.raises(ConfigError, match=key):
        teamenv.parallel_env(observation_mode="vision", vision="mj_noisy",
                             perception={key: value})
