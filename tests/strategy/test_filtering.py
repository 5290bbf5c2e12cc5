"""DBSCAN filtering of noisy sightings (strategy.perception.filtering) and the ball belief
that merges own sightings with teammates' reports (strategy.perception.ball_belief)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import strategy.perception.clustering as clustering
from strategy.perception.ball_belief import BallBelief
from strategy.perception.filtering import (
    FilterParams,
    FilterParamsError,
    MultiObjectWindow,
    SightingError,
    SightingWindow,
)
from teamenv.errors import TeamEnvError

CYCLE_S = 0.02


@pytest.fixture
def sklearn_calls(monkeypatch):
    """Counts the DBSCAN fits (the expensive part) while still running them."""
    calls = []
    real = clustering._dbscan_labels

    def counting(points, *args):
        calls.append(len(points))
        return real(points, *args)

    monkeypatch.setattr(clustering, "_dbscan_labels", counting)
    return calls


def noisy_still(window, centre, times, sigma, rng):
    for t in times:
        window.add(t, np.asarray(centre) + rng.normal(0.0, sigma, 2))


def test_dbscan_drops_injected_outliers():
    rng = np.random.default_rng(3)
    window = SightingWindow(FilterParams(max_age_s=2.0, max_len=64))
    centre = np.array([3.0, 1.0])
    outliers = [(-8.0, 5.0), (10.0, -6.0), (0.0, 9.0), (-12.0, -3.0), (7.0, 7.0)]
    added = []
    for k in range(30):
        added.append(centre + rng.normal(0.0, 0.1, 2))
        window.add(k * 0.04, added[-1])
        if k % 6 == 3:  # a bad pose now and then
            added.append(np.array(outliers[k // 6]))
            window.add(k * 0.04 + 0.02, added[-1])
    est = window.estimate(1.2)
    assert est is not None
    assert est.n == 30 and est.outliers == 5 and est.rejected == 0
    assert np.linalg.norm(est.position - centre) < 0.05
    assert 0.05 < est.spread < 0.2  # the noise, sigma * sqrt(2) ~ 0.14
    assert np.linalg.norm(np.mean(added, axis=0) - centre) > 0.3  # where a plain mean is


def test_age_limit_and_length_cap_drop_old_sightings():
    rng = np.random.default_rng(4)
    params = FilterParams(max_age_s=0.6, max_len=32)
    window = SightingWindow(params)
    noisy_still(window, (5.0, 5.0), np.arange(0.0, 0.4, 0.04), 0.05, rng)
    assert window.estimate(0.5) is not None
    assert window.estimate(1.1) is None  # all older than 0.6 s
    noisy_still(window, (-2.0, 1.0), np.arange(1.0, 1.4, 0.04), 0.05, rng)
    est = window.estimate(1.4)
    assert est is not None and est.n == 10 and est.outliers == 0
    assert np.linalg.norm(est.position - (-2.0, 1.0)) < 0.05
    assert len(window) == 20
    window.prune(1.4)
    assert len(window) == 10
    noisy_still(window, (0.0, 0.0), 1.4 + np.arange(40) * 0.001, 0.05, rng)
    assert len(window) == params.max_len  # the oldest were dropped


def test_estimate_follows_a_moving_object_not_a_stale_mean():
    rng = np.random.default_rng(5)
    window = SightingWindow()
    velocity = np.array([2.0, 0.5])
    times = np.arange(0.0, 3.0, 0.05)
    for t in times:
        window.add(t, velocity * t + rng.normal(0.0, 0.05, 2))
    now = float(times[-1])
    est = window.estimate(now)
    assert est is not None
    assert np.linalg.norm(est.position - velocity * est.time_s) < 0.1
    assert np.linalg.norm(est.latest_position - velocity * now) < 0.1
    assert np.linalg.norm(est.position - velocity * times.mean()) > 2.0  # not the whole run


def test_a_jump_is_followed_before_the_new_cluster_outnumbers_the_old():
    rng = np.random.default_rng(6)
    window = SightingWindow(FilterParams(max_age_s=1.0, recency_half_life_s=0.2))
    noisy_still(window, (0.0, 0.0), np.arange(0.0, 0.8, 0.05), 0.05, rng)  # 16
    noisy_still(window, (4.0, 0.0), np.arange(0.8, 1.1, 0.05), 0.05, rng)  # 6, after a kick
    est = window.estimate(1.1)
    assert est is not None
    assert np.linalg.norm(est.position - (4.0, 0.0)) < 0.1
    assert est.rejected > est.n  # the old spot still has more sightings in the window


def test_velocity_of_a_constant_velocity_object_within_ten_percent():
    rng = np.random.default_rng(7)
    window = SightingWindow()
    velocity = np.array([3.0, -1.5])
    for t in np.arange(0.0, 0.6, 0.04):
        window.add(t, np.array([-1.0, 2.0]) + velocity * t + rng.normal(0.0, 0.05, 2))
    est = window.estimate(0.6)
    assert est is not None and est.velocity is not None
    assert np.linalg.norm(est.velocity - velocity) < 0.1 * np.linalg.norm(velocity)


def test_no_velocity_from_too_few_or_too_close_sightings():
    params = FilterParams(min_samples=2, min_velocity_span_s=0.1)
    two = SightingWindow(params)
    two.add(0.0, (0.0, 0.0))
    two.add(0.2, (0.2, 0.0))
    short = SightingWindow(params)
    for t in (0.0, 0.02, 0.04, 0.06):
        short.add(t, (t, 0.0))
    assert two.estimate(0.2).velocity is None
    assert short.estimate(0.06).velocity is None
    short.add(0.12, (0.12, 0.0))
    assert short.estimate(0.12).velocity == pytest.approx([1.0, 0.0])


def test_unchanged_window_does_not_call_sklearn_again(sklearn_calls):
    rng = np.random.default_rng(8)
    window = SightingWindow()
    noisy_still(window, (1.0, 1.0), [0.0, 0.04, 0.08, 0.12], 0.05, rng)
    first = window.estimate(0.12)
    for k in range(1, 4):  # cycles with no new sighting and nothing aged out
        again = window.estimate(0.12 + k * CYCLE_S)
        assert np.array_equal(again.position, first.position)
        assert again.age_s == pytest.approx(k * CYCLE_S)
    assert len(sklearn_calls) == 1
    window.add(0.2, (1.0, 1.0))
    window.estimate(0.2)
    assert len(sklearn_calls) == 2


def test_a_window_too_light_for_a_core_point_skips_sklearn(sklearn_calls):
    window = SightingWindow(FilterParams(min_samples=3))
    window.add(0.0, (0.0, 0.0))
    window.add(0.04, (0.0, 0.0))
    assert window.estimate(0.04) is None
    assert sklearn_calls == []


def test_multi_object_window_matches_one_window_per_object_in_one_sklearn_call(sklearn_calls):
    rng = np.random.default_rng(9)
    n_objects = 11
    seen = np.array([0, 2, 3, 7, 10])
    centres = rng.uniform(-10.0, 10.0, (n_objects, 2))
    centres[3] = centres[2] + (0.1, 0.0)  # two opponents closer than eps stay apart
    multi = MultiObjectWindow(n_objects)
    singles = [SightingWindow() for _ in range(n_objects)]
    for k, t in enumerate(np.arange(0.0, 0.5, 0.05)):
        xy = centres[seen] + rng.normal(0.0, 0.08, (len(seen), 2))
        if k == 4:
            xy[1] += (6.0, 0.0)  # one wrong sighting of object 2
        multi.add(t, seen, xy)
        for i, obj in enumerate(seen):
            singles[obj].add(t, xy[i])
    multi.add(0.45, [5], [[1.0, 1.0]])  # a single glimpse: no cluster
    est = multi.estimate(0.5)
    assert len(sklearn_calls) == 1
    expected_known = np.isin(np.arange(n_objects), seen)
    assert np.array_equal(est.known, expected_known)
    assert np.isnan(est.positions[~expected_known]).all()
    assert np.isinf(est.age_s[~expected_known]).all()
    assert est.outliers[2] == 1 and est.n[2] == 9 and est.n[3] == 10
    for obj in seen:
        one = singles[obj].estimate(0.5)
        np.testing.assert_allclose(est.positions[obj], one.position, rtol=0, atol=1e-12)
        assert est.n[obj] == one.n and est.outliers[obj] == one.outliers
        assert est.get(obj).spread == pytest.approx(one.spread)
    assert est.get(5) is None
    assert np.linalg.norm(est.positions[seen] - centres[seen], axis=1).max() < 0.1


def run_scripted_belief() -> list:
    rng = np.random.default_rng(10)
    belief = BallBelief()
    out = []
    for cycle in range(150):
        t = cycle * CYCLE_S
        ball = np.array([1.0 + 1.5 * t, -0.5 * t])
        if cycle % 3 == 0 and cycle < 60:
            belief.see(t, ball + rng.normal(0.0, 0.1, 2))
        if cycle % 10 == 5 and cycle > 40:
            belief.hear(t, ball + rng.normal(0.0, 0.1, 2), 0.04, sender=cycle % 4)
        b = belief.belief(t)
        out.append((b.source, b.age_s, b.confidence,
                    None if b.position is None else b.position.tobytes(),
                    None if b.velocity is None else b.velocity.tobytes()))
    return out


def test_same_inputs_give_the_same_outputs_bit_for_bit():
    first, second = run_scripted_belief(), run_scripted_belief()
    assert first == second
    assert {row[0] for row in first} == {"none", "own", "heard"}

    def multi_run():
        rng = np.random.default_rng(11)
        window = MultiObjectWindow(4)
        for t in np.arange(0.0, 0.5, 0.04):
            window.add(t, [0, 1, 3], rng.normal(0.0, 0.3, (3, 2)))
        est = window.estimate(0.5)
        return [getattr(est, f).tobytes() for f in ("positions", "velocities", "spread", "n")]

    assert multi_run() == multi_run()


def test_ball_belief_prefers_fresh_own_sightings():
    rng = np.random.default_rng(12)
    belief = BallBelief()
    assert belief.belief(0.0).source == "none" and belief.belief(0.0).position is None
    for t in np.arange(0.0, 0.3, 0.05):
        belief.see(t, np.array([2.0, 2.0]) + rng.normal(0.0, 0.1, 2))
    # fresher teammates' reports elsewhere do not override fresh own sightings
    belief.hear(0.3, (-5.0, 0.0), 0.0, sender=2)
    belief.hear(0.3, (-5.1, 0.1), 0.0, sender=3)
    b = belief.belief(0.3)
    assert b.source == "own"
    assert np.linalg.norm(b.position - (2.0, 2.0)) < 0.15
    assert b.age_s == pytest.approx(0.05)
    assert 0.0 < b.confidence <= 1.0


def test_ball_belief_uses_heard_reports_when_own_sightings_are_stale():
    rng = np.random.default_rng(13)
    belief = BallBelief(FilterParams(own_trust_s=0.3))
    for t in np.arange(0.0, 0.3, 0.05):
        belief.see(t, np.array([2.0, 2.0]) + rng.normal(0.0, 0.1, 2))
    stale_own = belief.belief(0.8)  # looked away: nothing fresher to go on
    assert stale_own.source == "own" and stale_own.age_s == pytest.approx(0.55)
    belief.hear(0.8, (-5.0, 0.0), 0.1, sender=2)  # seen at 0.7 s
    b = belief.belief(0.8)
    assert b.source == "heard"
    assert b.position == pytest.approx([-5.0, 0.0])
    assert b.age_s == pytest.approx(0.1) and b.velocity is None
    assert b.confidence < stale_own.confidence + 0.5  # a heard ball is trusted less
    later = belief.belief(1.3)
    assert later.source == "heard" and later.age_s == pytest.approx(0.6)
    assert later.confidence < b.confidence
    # after the report is too old, the ball is remembered, then forgotten
    remembered = belief.belief(5.0)
    assert remembered.source == "heard" and remembered.age_s == pytest.approx(4.3)
    assert belief.belief(20.0).source == "none"


def test_a_wrong_heard_report_is_outvoted_by_two_consistent_ones():
    belief = BallBelief()
    belief.hear(1.0, (4.0, -2.0), 0.02, sender=5)
    belief.hear(1.0, (4.2, -2.1), 0.04, sender=6)
    for k in range(5):  # the wrong teammate speaks most often and most recently
        belief.hear(1.0 + k * 0.02, (-6.0, 3.0), 0.0, sender=9)
    b = belief.belief(1.1)
    assert b.source == "heard" and b.support == 2
    assert np.linalg.norm(b.position - (4.1, -2.05)) < 0.1
    assert b.confidence < belief.params.heard_confidence  # one in three disagreed


def test_ball_belief_velocity_and_optional_roll_model():
    rng = np.random.default_rng(14)
    velocity = np.array([2.0, 1.0])
    calls = []

    def constant_velocity(position, v, dt):
        calls.append(dt)
        return position + v * dt, v

    plain, rolled = BallBelief(), BallBelief(roll=constant_velocity)
    for t in np.arange(0.0, 0.5, 0.05):
        xy = velocity * t + rng.normal(0.0, 0.03, 2)
        plain.see(t, xy)
        rolled.see(t, xy)
    now = 0.45 + 0.1
    a, b = plain.belief(now), rolled.belief(now)
    assert np.linalg.norm(a.velocity - velocity) < 0.1 * np.linalg.norm(velocity)
    assert np.linalg.norm(a.position - velocity * 0.45) < 0.1  # at the newest sighting
    assert np.linalg.norm(b.position - velocity * now) < 0.1  # rolled forward to now
    assert calls == [pytest.approx(0.1)]


def test_velocity_sigma_is_the_spread_of_the_fitted_velocity():
    fitted, sigmas = [], []
    for seed in range(100):
        rng = np.random.default_rng(seed)
        window = SightingWindow()
        for t in np.arange(0.0, 0.6, 0.05):
            window.add(t, rng.normal(0.0, 0.1, 2))
        est = window.estimate(0.6)
        fitted.append(est.velocity)
        sigmas.append(est.velocity_sigma)
    ratio = np.std(fitted, axis=0) / np.mean(sigmas)
    assert (0.75 < ratio).all() and (ratio < 1.33).all()


def test_a_still_ball_does_not_roll_on_noise():
    rng = np.random.default_rng(15)
    belief = BallBelief()
    for t in np.arange(0.0, 0.6, 0.05):
        belief.see(t, np.array([-3.0, 4.0]) + rng.normal(0.0, 0.1, 2))
    fitted = belief.own_estimate(0.6)
    assert np.hypot(*fitted.velocity) > 0.05  # the raw slope is noise of this size
    assert fitted.velocity_sigma > 0.05
    b = belief.belief(0.6)
    assert np.array_equal(b.velocity, [0.0, 0.0])
    assert np.array_equal(b.position, fitted.position)  # the mean, not the extrapolation


@pytest.mark.parametrize("overrides, field", [
    ({"eps_m": -1.0}, "eps_m"),
    ({"eps_m": math.nan}, "eps_m"),
    ({"max_age_s": math.inf}, "max_age_s"),
    ({"min_samples": 0}, "min_samples"),
    ({"min_samples": 2.5}, "min_samples"),
    ({"max_len": True}, "max_len"),
    ({"recency_half_life_s": 0.0}, "recency_half_life_s"),
    ({"heard_confidence": 1.5}, "heard_confidence"),
    ({"heard_confidence": 0.0}, "heard_confidence"),
    ({"forget_after_s": -math.inf}, "forget_after_s"),
    ({"still_sigmas": "2"}, "still_sigmas"),
])
def test_bad_params_give_clear_errors(overrides, field):
    with pytest.raises(FilterParamsError) as caught:
        FilterParams.from_overrides(overrides)
    assert isinstance(caught.value, ValueError) and isinstance(caught.value, TeamEnvError)
    message = str(caught.value)
    assert field in message and repr(next(iter(overrides.values()))) in message


def test_unknown_param_keys_are_named():
    with pytest.raises(FilterParamsError, match=r"unknown key\(s\) \['eps'\].*'eps_m'"):
        FilterParams.from_overrides({"eps": 0.5})


def test_infinite_half_life_and_forgetting_are_allowed():
    params = FilterParams(recency_half_life_s=math.inf, forget_after_s=math.inf)
    window = SightingWindow(params)
    for t in (0.0, 0.1, 0.2):
        window.add(t, (t, 0.0))
    assert window.estimate(0.2).position == pytest.approx([0.1, 0.0])


def test_bad_sightings_give_clear_errors():
    window = SightingWindow()
    with pytest.raises(SightingError, match="finite"):
        window.add(0.0, (math.nan, 0.0))
    with pytest.raises(SightingError, match="shape"):
        window.add(0.0, (1.0, 2.0, 3.0))
    with pytest.raises(SightingError, match="weights"):
        window.add(0.0, (1.0, 2.0), weight=0.0)
    multi = MultiObjectWindow(3)
    with pytest.raises(SightingError, match="distinct"):
        multi.add(0.0, [1, 1], [[0.0, 0.0], [1.0, 1.0]])
    with pytest.raises(SightingError, match=r"\[0, 3\)"):
        multi.add(0.0, [3], [[0.0, 0.0]])
    with pytest.raises(SightingError, match="age_s"):
        BallBelief().hear(1.0, (0.0, 0.0), -0.5, sender=1)
    with pytest.raises(FilterParamsError, match="n_objects"):
        MultiObjectWindow(0)


@settings(max_examples=40, deadline=None)
@given(offset=st.tuples(st.floats(-20, 20), st.floats(-12, 12)),
       n=st.integers(3, 25), seed=st.integers(0, 2**16))
def test_a_tight_cluster_is_kept_whole_and_moves_with_the_sightings(offset, n, seed):
    # every pairwise distance < eps: one cluster of all, estimate inside their bounding box,
    # and translating every sighting translates the estimate
    rng = np.random.default_rng(seed)
    params = FilterParams(max_len=32)
    points = rng.uniform(-0.16, 0.16, (n, 2))  # diagonal 0.45 m < eps_m = 0.5
    times = np.sort(rng.uniform(0.0, 0.5, n))
    base, shifted = SightingWindow(params), SightingWindow(params)
    for t, p in zip(times, points, strict=True):
        base.add(float(t), p)
        shifted.add(float(t), p + np.asarray(offset))
    a, b = base.estimate(0.5), shifted.estimate(0.5)
    assert a.n == n and a.outliers == 0 and a.rejected == 0
    assert (a.position >= points.min(axis=0) - 1e-9).all()
    assert (a.position <= points.max(axis=0) + 1e-9).all()
    np.testing.assert_allclose(b.position, a.position + np.asarray(offset), atol=1e-9)


def test_min_samples_one_fast_path_labels_like_sklearn_dbscan():
    from sklearn.cluster import DBSCAN

    from strategy.perception.clustering import _dbscan_labels

    rng = np.random.default_rng(7)
    for _ in range(200):
        n = int(rng.integers(1, 15))
        pts = rng.normal(size=(n, 3)) * rng.uniform(0.2, 3.0)
        expected = DBSCAN(eps=1.0, min_samples=1).fit(pts).labels_
        np.testing.assert_array_equal(_dbscan_labels(pts, np.ones(n), 1.0, 1), expected)


def test_dropping_stale_objects_equals_clustering_again():
    from strategy.perception.filtering import FilterParams, MultiObjectWindow

    rng = np.random.default_rng(11)
    params = FilterParams(max_age_s=0.2)
    fast, slow = MultiObjectWindow(12, params), MultiObjectWindow(12, params)
    slow.derive_stale = False
    for cycle in range(400):
        t = cycle * 0.02
        if cycle % 3 == 0 and rng.random() < 0.7:
            ids = np.flatnonzero(rng.random(12) < 0.3)
            xy = rng.normal(size=(len(ids), 2)) * 0.2 + ids[:, None]
            for w in (fast, slow):
                w.add(t, ids, xy)
        a, b = fast.estimate(t), slow.estimate(t)
        for name in ("known", "positions", "newest_s", "spread", "n", "outliers", "rejected",
                     "velocities", "velocity_sigma", "age_s"):
            np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)
    assert fast.clusterings < 0.7 * slow.clusterings, (fast.clusterings, slow.clusterings)


def test_clustering_only_changed_objects_equals_clustering_all():
    """Objects seen now and then, with outliers, two clusters and moving objects: keeping
    the unchanged objects' statistics gives every value of clustering all of them again."""
    from strategy.perception.filtering import FilterParams, MultiObjectWindow

    rng = np.random.default_rng(12)
    params = FilterParams(max_age_s=0.5, min_samples=2)
    fast, slow = MultiObjectWindow(10, params), MultiObjectWindow(10, params)
    slow.derive_stale = False
    for cycle in range(600):
        t = cycle * 0.02
        if cycle % 2 == 0:
            ids = np.flatnonzero(rng.random(10) < 0.4)
            xy = ids[:, None] * 5.0 + t * np.array([0.5, -0.2]) + \
                rng.normal(size=(len(ids), 2)) * 0.1
            jump = rng.random(len(ids)) < 0.2  # outliers and a second cluster
            xy[jump] += rng.choice([1.5, 3.0], size=(int(jump.sum()), 1))
            for w in (fast, slow):
                w.add(t, ids, xy)
        if cycle % 97 == 0:
            for w in (fast, slow):
                w.clear_objects([cycle % 10])
        if cycle % 13 == 0:
            for w in (fast, slow):
                w.prune(t)
        a, b = fast.estimate(t), slow.estimate(t)
        for name in ("known", "positions", "time_s", "newest_s", "spread", "n", "outliers",
                     "rejected", "velocities", "velocity_sigma", "age_s"):
            np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)
    assert (slow.estimate(t).rejected > 0).any() or (slow.estimate(t).outliers > 0).any()


def test_compiled_dbscan_labels_like_sklearn_dbscan():
    """The compiled DBSCAN gives sklearn's labels exactly: noise, border points reachable from
    two clusters (the first cluster wins), points exactly eps apart, integer weights, and
    groups kept apart as by a third coordinate of 2 eps per group."""
    from sklearn.cluster import DBSCAN

    from strategy.perception.clustering import _dbscan_labels, _exact_dbscan_labels

    rng = np.random.default_rng(5)
    for _ in range(250):
        n = int(rng.integers(1, 40))
        eps = float(rng.choice([0.3, 0.5, 1.0]))
        min_samples = int(rng.integers(1, 6))
        weights = rng.integers(1, 4, size=n).astype(float) if rng.random() < 0.3 else None
        unit = np.ones(n) if weights is None else weights
        pts = rng.normal(size=(n, 2)) * rng.uniform(0.1, 3.0)
        if rng.random() < 0.3:  # on a half-metre lattice: many distances exactly eps
            pts = np.round(pts * 2.0) / 2.0
        expected = DBSCAN(eps=eps, min_samples=min_samples, algorithm="ball_tree").fit(
            pts, sample_weight=weights).labels_
        np.testing.assert_array_equal(_exact_dbscan_labels(pts, unit, eps, min_samples),
                                      expected)
        groups = rng.integers(0, 4, size=n)
        expected = DBSCAN(eps=eps, min_samples=min_samples, algorithm="ball_tree").fit(
            np.column_stack([pts, groups * 2.0 * eps]), sample_weight=weights).labels_
        np.testing.assert_array_equal(_dbscan_labels(pts, unit, eps, min_samples, groups),
                                      expected)
    # every group a clique (the usual windows): one cluster or noise per group
    for _ in range(100):
        n = int(rng.integers(1, 40))
        min_samples = int(rng.integers(1, 6))
        groups = rng.integers(0, 6, size=n)
        pts = groups[:, None] * 5.0 + rng.normal(size=(n, 2)) * 0.1
        expected = DBSCAN(eps=0.5, min_samples=min_samples, algorithm="ball_tree").fit(
            np.column_stack([pts, groups * 1.0])).labels_
        np.testing.assert_array_equal(_dbscan_labels(pts, np.ones(n), 0.5, min_samples,
                                                     groups), expected)
    # points of one or three coordinates, and no points
    for shape in ((30,), (30, 1), (30, 3)):
        pts = np.round(rng.normal(size=shape) * 2.0) / 2.0
        expected = DBSCAN(eps=0.5, min_samples=3).fit(pts.reshape(30, -1)).labels_
        np.testing.assert_array_equal(_exact_dbscan_labels(pts, np.ones(30), 0.5, 3), expected)
    assert _exact_dbscan_labels(np.zeros((0, 2)), np.zeros(0), 0.5, 3).shape == (0,)
    # non-integer weights go to sklearn itself
    pts = rng.normal(size=(20, 2))
    w = rng.uniform(0.5, 2.0, 20)
    np.testing.assert_array_equal(
        _dbscan_labels(pts, w, 0.5, 3),
        DBSCAN(eps=0.5, min_samples=3, algorithm="ball_tree").fit(pts, sample_weight=w).labels_)


def test_clique_means_equal_the_clustering_bit_for_bit():
    """The heard reports' shortcut (every object's points within eps: one cluster each)
    gives cluster_objects' n, positions and newest_s exactly, and declines otherwise."""
    from strategy.perception.clustering import clique_means, cluster_objects

    rng = np.random.default_rng(9)
    used = declined = 0
    for _ in range(300):
        rows = []
        for obj in range(int(rng.integers(1, 8))):
            count = int(rng.integers(1, 11))
            times = np.sort(rng.uniform(0.0, 2.0, count))
            xy = rng.normal(0.0, rng.choice([0.2, 0.8]), (count, 2)) + 3.0 * obj
            rows += [(obj, t, *p) for t, p in zip(times, xy, strict=True)]
        a = np.array(rows)
        times, xy, objects = a[:, 1].copy(), a[:, 2:4].copy(), a[:, 0].astype(np.int64)
        got = clique_means(times, xy, objects, 1.0, 0.3)
        if got is None:
            declined += 1
            continue
        used += 1
        ref = cluster_objects(times, xy, np.ones(len(times)), objects, int(objects[-1]) + 1,
                              1.0, 1, 0.3, math.inf)
        for name, value in got.items():
            np.testing.assert_array_equal(value, ref[name], err_msg=name)
            assert value.dtype == ref[name].dtype
    assert used > 50 and declined > 50
