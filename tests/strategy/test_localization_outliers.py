"""Localization against a camera that misnames sightings (the ``mj_noisy`` vision): with the
outlier cap a misnamed landmark cannot pull the estimate away; the team fits its filter to the
camera it is told about."""

from __future__ import annotations

import math

import numpy as np
import pytest

from strategy.perception.localization import (
    OUTLIER_CAP,
    LocalizationError,
    LocalizationParams,
    Localizer,
    for_camera,
)
from teamenv.config import VISION_PROFILES
from teamenv.field import field_preset
from teamenv.landmarks import landmarks, to_polar

FIELD = field_preset("mj7v7")
TABLE = landmarks(FIELD, "mj")
CAMERA = 1.1
TRUTH = (-8.0, 4.0, 0.4)


def misnamed_sightings() -> np.ndarray:
    """(K, 4) what a camera at ``TRUTH`` sees, with its nearest landmark reported under the
    name of an unseen one (the same mistake every update: the worst case)."""
    polar = to_polar(TABLE.xyz, *TRUTH, camera_height=CAMERA)
    seen = np.abs(polar[:, 1]) <= math.radians(60.0)
    rows = np.zeros((len(TABLE), 4))
    rows[seen] = np.column_stack([np.ones(seen.sum()), polar[seen]])
    nearest = int(np.argmin(np.where(seen, polar[:, 0], np.inf)))
    unseen = int(np.flatnonzero(~seen)[0])
    rows[unseen], rows[nearest] = rows[nearest], 0.0
    assert seen.sum() >= 4
    return rows


def error_after(params: LocalizationParams) -> float:
    loc = Localizer(FIELD, "mj", CAMERA, params, np.random.default_rng(0))
    loc.beamed(TRUTH)
    rows = misnamed_sightings()
    for cycle in range(100):
        loc.predict(np.zeros(3), 0.0)
        if cycle % 2 == 0:
            loc.correct(rows)
    pose = loc.estimate().pose
    return math.hypot(pose[0] - TRUTH[0], pose[1] - TRUTH[1])


def test_a_misnamed_landmark_does_not_pull_the_capped_estimate():
    capped = error_after(LocalizationParams(landmark_outlier_cap=OUTLIER_CAP))
    uncapped = error_after(LocalizationParams())
    assert capped < 0.15
    assert uncapped > 3 * capped  # without the cap the one wrong name drags the pose


def test_the_team_fits_its_filter_to_the_camera():
    plain = LocalizationParams()
    assert for_camera(plain, VISION_PROFILES["mj"]) == plain
    assert for_camera(plain, VISION_PROFILES["simspark"]) == plain
    assert for_camera(plain, None) == plain
    noisy = for_camera(plain, VISION_PROFILES["mj_noisy"])
    assert noisy.landmark_outlier_cap == OUTLIER_CAP
    assert noisy.sigma_distance_rel == pytest.approx(1.2 * 0.01)
    chosen = LocalizationParams(landmark_outlier_cap=3.0)
    assert for_camera(chosen, VISION_PROFILES["mj_noisy"]).landmark_outlier_cap == 3.0


@pytest.mark.parametrize("cap", [0.0, -1.0, float("nan"), True])
def test_bad_cap_is_named(cap):
    with pytest.raises(LocalizationError, match="landmark_outlier_cap"):
        LocalizationParams(landmark_outlier_cap=cap)
