"""The evaluation protocol's seed ranges are disjoint and hand out the seeds they promise."""

from __future__ import annotations

import pytest

from teamenv.seeds import (
    EVALUATION_SEEDS,
    TUNING_SEEDS,
    evaluation_seeds,
    purpose_of,
    tuning_seeds,
)


def test_ranges_are_disjoint():
    assert TUNING_SEEDS.end <= EVALUATION_SEEDS.first
    assert not set(tuning_seeds(50, offset=TUNING_SEEDS.end - TUNING_SEEDS.first - 50)) & set(
        evaluation_seeds(50))


def test_take_counts_from_the_start_of_the_range():
    assert evaluation_seeds(3) == (100_000, 100_001, 100_002)
    assert evaluation_seeds(2, offset=10) == (100_010, 100_011)
    assert tuning_seeds(2) == (0, 1)


def test_purpose_names_the_range():
    assert purpose_of(5000) == "tuning"
    assert purpose_of(100_039) == "evaluation"
    with pytest.raises(ValueError, match="no reserved range"):
        purpose_of(-1)


@pytest.mark.parametrize("count, offset", [(-1, 0), (1, -1), (2, 99_999)])
def test_bad_requests_name_the_range_and_values(count, offset):
    with pytest.raises(ValueError, match="evaluation seeds"):
        evaluation_seeds(count, offset)
