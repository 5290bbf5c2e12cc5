"""teamenv.observation.team_frame gives, bit for bit, what the plain numpy rotation gives."""

from dataclasses import fields

import numpy as np

import teamenv
from teamenv.observation import TeamView, team_frame
from teamenv.sim.playmode import PlayMode


def _rotate(points, angle):
    c, s = np.cos(angle), np.sin(angle)
    return np.stack([c * points[..., 0] - s * points[..., 1],
                     s * points[..., 0] + c * points[..., 1]], axis=-1)


def reference_team_frame(obs) -> TeamView:
    """The straightforward implementation the fast one must match exactly."""
    me = np.asarray(obs["self"], dtype=float)
    pos, heading = me[:2], float(me[2])
    ball = np.asarray(obs["ball"], dtype=float)
    mates = np.asarray(obs["teammates"], dtype=float)
    opps = np.asarray(obs["opponents"], dtype=float)
    game = np.asarray(obs["game"], dtype=float)
    return TeamView(
        position=pos.copy(), heading=heading, velocity=me[3:5].copy(), fallen=bool(me[6] > 0.5),
        ball=pos + _rotate(ball[:2], heading), ball_velocity=_rotate(ball[2:4], heading),
        teammates=pos + _rotate(mates[:, :2], heading), teammates_present=mates[:, 4] > 0.5,
        teammates_fallen=mates[:, 3] > 0.5,
        opponents=pos + _rotate(opps[:, :2], heading), opponents_present=opps[:, 4] > 0.5,
        opponents_fallen=opps[:, 3] > 0.5,
        play_mode=PlayMode(int(obs["play_mode"])), time_s=float(game[0]), half=int(game[1]),
        score=(int(game[2]), int(game[3])),
    )


def assert_identical(a: TeamView, b: TeamView) -> None:
    for f in fields(TeamView):
        x, y = getattr(a, f.name), getattr(b, f.name)
        if isinstance(x, np.ndarray):
            assert isinstance(y, np.ndarray), f.name
            assert x.dtype == y.dtype and x.shape == y.shape, f.name
            assert x.tobytes() == y.tobytes(), f.name
        else:
            assert type(x) is type(y) and x == y, (f.name, x, y)


def test_matches_reference_on_env_observations():
    env = teamenv.parallel_env(team_size=5, left="chaser", right="chaser",
                               rules={"half_time_s": 2.0})
    env.reset(seed=7)
    checked = 0
    while not env.episode_over:
        env.step({})
        for side_obs in env.team_host.observations.values():
            for obs in side_obs.values():
                assert_identical(team_frame(obs), reference_team_frame(obs))
                checked += 1
    assert checked > 1000


def test_matches_reference_on_random_and_list_observations():
    rng = np.random.default_rng(3)
    for k in range(200):
        n = int(rng.integers(1, 12))
        obs = {
            "self": rng.uniform(-20, 20, 7).astype(np.float32),
            "ball": rng.uniform(-20, 20, 4).astype(np.float32),
            "teammates": rng.uniform(-20, 20, (n, 5)).astype(np.float32),
            "opponents": rng.uniform(-20, 20, (n, 5)).astype(np.float32),
            "play_mode": int(rng.integers(0, len(PlayMode))),
            "game": np.array([rng.uniform(0, 600), 1 + k % 2, k % 3, k % 4], np.float32),
        }
        obs["self"][6] = k % 2
        assert_identical(team_frame(obs), reference_team_frame(obs))
        # Hand-built scenes may use lists and float64.
        as_lists = {key: (v.astype(float).tolist() if isinstance(v, np.ndarray) else v)
                    for key, v in obs.items()}
        assert_identical(team_frame(as_lists), reference_team_frame(as_lists))


def test_view_is_a_regular_frozen_teamview():
    obs = {"self": np.zeros(7, np.float32), "ball": np.ones(4, np.float32),
           "teammates": np.zeros((2, 5), np.float32), "opponents": np.zeros((2, 5), np.float32),
           "play_mode": int(PlayMode.PlayOn), "game": np.array([1, 1, 0, 0], np.float32)}
    view = team_frame(obs)
    assert isinstance(view, TeamView) and view.play_mode is PlayMode.PlayOn
    try:
        view.heading = 1.0
    except AttributeError:
        pass
    else:
        raise AssertionError("TeamView must stay frozen")
    assert "TeamView(" in repr(view)
