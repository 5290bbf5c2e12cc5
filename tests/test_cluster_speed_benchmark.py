"""``benchmarks/cluster_speed.py`` records the clustering calls of a vision match and leaves the
modules as it found them."""

from __future__ import annotations

import strategy.perception.clustering as clustering
import strategy.perception.filtering as filtering
import strategy.perception.team_sightings as team_sightings
from tests.benchmark_scripts import load_benchmark


def test_recorded_calls_replay_to_the_same_statistics_and_the_hooks_are_removed():
    cluster_speed = load_benchmark("cluster_speed")
    calls = cluster_speed.record(60, 3, "mj7v7", 2, "mj")
    assert len(calls) > 10
    assert filtering.cluster_objects is clustering.cluster_objects
    assert team_sightings.cluster_objects is clustering.cluster_objects
    times, xy, weights, objects, n_objects = calls[-1][:5]
    assert len(times) == len(xy) == len(weights) == len(objects) and n_objects >= 1
    first = clustering.cluster_objects(*calls[-1])
    again = clustering.cluster_objects(*calls[-1])
    assert all(first[k].tobytes() == again[k].tobytes() for k in first)
