"""Formation model: exact at samples, continuous across edges, outside-hull rules, validation."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from strategy.positioning.formation import Formation, FormationError, Role
from tests.strategy.helpers import formations, grid_formation, roles


@settings(max_examples=60, deadline=None)
@given(formations())
def test_interpolation_is_exact_at_samples(f: Formation):
    for b, p in zip(f.ball_samples, f.sample_positions, strict=True):
        np.testing.assert_allclose(f.home_positions(b), p, atol=1e-9)
    np.testing.assert_allclose(f.home_positions_many(f.ball_samples), f.sample_positions,
                               atol=1e-9)


def _interior_edges(f: Formation) -> list[tuple[int, int]]:
    count: dict[tuple[int, int], int] = {}
    for tri in f.simplices:
        for a, b in ((tri[0], tri[1]), (tri[1], tri[2]), (tri[0], tri[2])):
            key = (int(min(a, b)), int(max(a, b)))
            count[key] = count.get(key, 0) + 1
    return [e for e, c in count.items() if c == 2]


@settings(max_examples=40, deadline=None)
@given(formations(), st.floats(0.05, 0.95))
def test_interpolation_is_continuous_across_triangle_edges(f: Formation, t: float):
    edges = _interior_edges(f)
    for i, j in edges:
        a, b = f.ball_samples[i], f.ball_samples[j]
        p = a + t * (b - a)
        d = b - a
        normal = np.array([-d[1], d[0]]) / np.hypot(*d)
        eps = 1e-9
        left = f.home_positions(p + eps * normal)
        right = f.home_positions(p - eps * normal)
        # both sides tend to the linear blend of the edge's two samples
        on_edge = (1 - t) * f.sample_positions[i] + t * f.sample_positions[j]
        np.testing.assert_allclose(left, on_edge, atol=1e-3)
        np.testing.assert_allclose(right, on_edge, atol=1e-3)


def test_interpolation_is_barycentric_inside_a_triangle():
    f = grid_formation(n=3)
    tri = f.simplices[0]
    w = np.array([0.2, 0.3, 0.5])
    ball = w @ f.ball_samples[tri]
    expected = np.einsum("k,kij->ij", w, f.sample_positions[tri])
    np.testing.assert_allclose(f.home_positions(ball), expected, atol=1e-9)


def test_outside_hull_nearest_sample_as_agent2d():
    ball = np.array([[0.0, 0.0], [4.0, 0.0], [0.0, 4.0]])
    pos = np.array([[[1.0, 1.0]], [[2.0, 2.0]], [[3.0, 3.0]]])
    f = Formation([Role("G", "G")], ball, pos, field="simspark")
    # far beyond sample 1 (4, 0): nearest sample is 1
    np.testing.assert_allclose(f.home_positions([9.0, -1.0]), [[2.0, 2.0]])
    # left of the hull, nearest is sample 0
    np.testing.assert_allclose(f.home_positions([-3.0, 1.0]), [[1.0, 1.0]])
    # equidistant from samples 1 and 2: the lower index wins
    np.testing.assert_allclose(f.home_positions([5.0, 5.0]), [[2.0, 2.0]])
    many = f.home_positions_many([[9.0, -1.0], [-3.0, 1.0], [1.0, 1.0]])
    np.testing.assert_allclose(many[:2, 0], [[2.0, 2.0], [1.0, 1.0]])


def test_outside_hull_project_is_continuous_at_the_hull():
    f = grid_formation(n=2, outside="project")
    # a ball just outside every hull edge matches the value just inside
    for tri_edge in f._hull:  # noqa: SLF001 - the hull edges are what we probe
        a, b = f.ball_samples[tri_edge[0]], f.ball_samples[tri_edge[1]]
        mid = (a + b) / 2
        centre = f.ball_samples.mean(axis=0)
        out = mid + (mid - centre) * 1e-7
        inn = mid - (mid - centre) * 1e-7
        np.testing.assert_allclose(f.home_positions(out), f.home_positions(inn), atol=1e-4)
    # far away: the value at the nearest hull point
    far = f.home_positions([100.0, 0.0])
    assert np.isfinite(far).all()


def test_static_formation_ignores_the_ball():
    f = Formation(roles(2), [[0.0, 0.0]], [[[-14.0, 0.0], [-5.0, 1.0]]], field="simspark")
    assert f.is_static
    for b in ([0, 0], [10, 5], [-30, 40]):
        np.testing.assert_allclose(f.home_positions(b), [[-14.0, 0.0], [-5.0, 1.0]])
    assert f.home_positions_many([[0, 0], [1, 1]]).shape == (2, 2, 2)


def test_mirror_rotates_by_pi_by_default():
    f = grid_formation(n=3)
    m = f.mirrored()
    for b in ([3.0, 2.0], [-7.0, 5.5], [20.0, 0.0]):
        np.testing.assert_allclose(m.home_positions(-np.array(b)), -f.home_positions(b),
                                   atol=1e-9)
    wings = f.mirrored(flip_x=False, flip_y=True)
    np.testing.assert_allclose(wings.home_positions([3.0, -2.0]),
                               f.home_positions([3.0, 2.0]) * [1, -1], atol=1e-9)
    assert m.mirrored().home_positions([1, 1]) == pytest.approx(f.home_positions([1, 1]))


def test_scaling_to_another_pitch():
    f = grid_formation(n=2)
    g = f.scaled_to("fifa")
    assert g.field_size == (105.0, 68.0)
    sx, sy = 105.0 / 30.0, 68.0 / 20.0
    np.testing.assert_allclose(g.home_positions([3 * sx, 2 * sy]),
                               f.home_positions([3, 2]) * [sx, sy], atol=1e-9)
    assert f.scaled_to("simspark") is f


# ------------------------------------------------------------------------------ validation
def _ball3():
    return np.array([[0.0, 0.0], [5.0, 0.0], [0.0, 5.0]])


def _pos3(n=2):
    return np.zeros((3, n, 2))


def test_duplicate_sample_is_an_error_naming_it():
    ball = np.array([[0.0, 0.0], [5.0, 0.0], [0.0, 5.0], [5.0, 0.0004]])
    with pytest.raises(FormationError, match=r"samples\[3\]\.ball.*duplicates samples\[1\]"):
        Formation(roles(2), ball, np.zeros((4, 2, 2)))


def test_degenerate_collinear_samples_are_an_error():
    ball = np.array([[0.0, 0.0], [1.0, 1.0], [2.0, 2.0], [3.0, 3.0]])
    with pytest.raises(FormationError, match="degenerate"):
        Formation(roles(2), ball, np.zeros((4, 2, 2)))
    with pytest.raises(FormationError, match="2 samples cannot be triangulated"):
        Formation(roles(2), ball[:2], np.zeros((2, 2, 2)))


def test_wrong_player_count_is_an_error():
    with pytest.raises(FormationError, match="3 players per sample but 2 roles"):
        Formation(roles(2), _ball3(), _pos3(3))
    with pytest.raises(FormationError, match="shape"):
        Formation(roles(2), _ball3(), np.zeros((2, 2, 2)))


def test_positions_off_the_field_are_an_error_naming_field_and_value():
    pos = _pos3()
    pos[2, 1] = [16.6, 0.0]  # simspark half-length 15 + margin 1.5
    with pytest.raises(FormationError, match=r"samples\[2\]\.players\[1\] = \(16\.6, 0\.0\)"):
        Formation(roles(2), _ball3(), pos)
    ball = _ball3()
    ball[1] = [0.0, 11.6]
    with pytest.raises(FormationError, match=r"samples\[1\]\.ball .* off the field"):
        Formation(roles(2), ball, _pos3())
    pos = _pos3()
    pos[0, 0] = [np.nan, 0.0]
    with pytest.raises(FormationError, match="not finite"):
        Formation(roles(2), _ball3(), pos)
    # within the margin is fine (agent2d puts samples 2 m beyond the lines of 105 x 68)
    pos = _pos3()
    pos[0, 0] = [16.4, 0.0]
    Formation(roles(2), _ball3(), pos)


def test_roles_are_validated():
    with pytest.raises(FormationError, match=r"roles\[1\]\.type must be one of"):
        Formation([Role("G", "G"), Role("X", "striker")], _ball3(), _pos3())
    with pytest.raises(FormationError, match="goalie must be role 0"):
        Formation([Role("A", "DF"), Role("G", "G")], _ball3(), _pos3())
    with pytest.raises(FormationError, match="more than one goalie"):
        Formation([Role("G", "G"), Role("G2", "G")], _ball3(), _pos3())
    with pytest.raises(FormationError, match="outside must be one of"):
        Formation(roles(2), _ball3(), _pos3(), outside="clamp")  # type: ignore[arg-type]
    with pytest.raises(FormationError, match="unknown preset"):
        Formation(roles(2), _ball3(), _pos3(), field="moon")


def test_lookup_rejects_bad_ball():
    f = grid_formation()
    with pytest.raises(FormationError, match="ball must be a finite"):
        f.home_positions([np.nan, 0.0])
    with pytest.raises(FormationError, match="ball must be a finite"):
        f.home_positions([1.0, 2.0, 3.0])
    with pytest.raises(FormationError, match="shape"):
        f.home_positions_many([1.0, 2.0])


def test_arrays_are_read_only():
    f = grid_formation()
    with pytest.raises(ValueError):
        f.sample_positions[0, 0, 0] = 1.0
    with pytest.raises(ValueError):
        f.ball_samples[0, 0] = 1.0


@pytest.mark.parametrize("outside", ["project", "nearest"])
def test_many_balls_get_the_bits_each_gets_alone(outside):
    # balls on triangle edges and at samples (Qhull's search for the next ball starts where
    # the last one was found, so such a ball may land in the other triangle), inside, outside
    from strategy.positioning.formation.builtin import builtin_formation

    f = builtin_formation("11v11-attack", "simspark")
    f = Formation(f.roles, f.ball_samples, f.sample_positions, field=f.field_size,
                  name=f.name, outside=outside)
    rng = np.random.default_rng(3)
    corners = f.ball_samples[f.simplices]
    balls = np.concatenate([rng.uniform(-17, 17, (200, 2)), f.ball_samples,
                            (corners[:, 0] + corners[:, 1]) / 2, np.zeros((2, 2))])
    rng.shuffle(balls)
    for chunk in np.array_split(balls, len(balls) // 11):
        many = f.home_positions_many(chunk)
        for k, ball in enumerate(chunk):
            alone = f.home_positions(ball)
            assert many[k].tobytes() == alone.tobytes()
