"""Egocentric player slots: the nearest teammates and opponents of each agent, sorted, masked
and of a fixed count whatever the team size; and the team that plays a policy file reading
them."""

from __future__ import annotations

import numpy as np
import pytest

import teamenv
from teamenv.egocentric import EgocentricObservation
from teamenv.errors import ConfigError
from teamenv.policy_team import PolicyFileError, load_policy, save_mlp_policy
from teamenv.selfplay.egocentric_team import (
    TEAM_SPEC_NAME,
    add_egocentric_slots,
    egocentric_slots,
)
from teamenv.slots import observation_slot_names


def _box_env(team_size: int, **opts):
    return teamenv.parallel_env(team_size=team_size, observation_format="box",
                                action_format="box", **opts)


def _stepped_rows(team_size: int, cycles: int = 40, seed: int = 3) -> tuple:
    """Raw Box rows of every agent after ``cycles`` random cycles (players spread out)."""
    env = _box_env(team_size)
    obs, _ = env.reset(seed=seed)
    rng = np.random.default_rng(seed)
    for _ in range(cycles):
        obs, *_ = env.step({a: rng.uniform(-1, 1, 9).astype(np.float32) for a in env.agents})
    return env, obs


def _players(row: np.ndarray, names: list[str], part: str, team_size: int) -> np.ndarray:
    """The raw (team_size, 5) block of ``part`` ("teammate" or "opponent") read by name."""
    index = {n: k for k, n in enumerate(names)}
    return np.array([[row[index[f"{part}_{u}.{c}"]] for c in
                      ("rel_x", "rel_y", "rel_heading", "fallen", "present")]
                     for u in range(1, team_size + 1)])


@pytest.mark.parametrize("team_size,teammates,opponents", [(3, 2, 3), (3, 4, 2), (5, 2, 3)])
def test_slots_hold_the_nearest_players_sorted_and_masked(team_size, teammates, opponents):
    env, obs = _stepped_rows(team_size)
    ego = EgocentricObservation.for_env(env, teammates, opponents)
    names = list(observation_slot_names(env))
    out_names = {n: k for k, n in enumerate(ego.names)}
    assert len(ego.names) == len(set(ego.names)) == ego.size
    for agent in env.agents:
        row = obs[agent]
        out = ego(row)
        assert out.dtype == np.float32 and out.shape == (ego.size,)
        for part, slots, own in (("teammate", teammates, True), ("opponent", opponents, False)):
            block = _players(row, names, part, team_size)
            dist = np.hypot(block[:, 0], block[:, 1])
            order = [k for k in np.argsort(dist, kind="stable") if not (own and dist[k] == 0)]
            for s in range(slots):
                got = [out[out_names[f"{part}_near_{s + 1}.{c}"]] for c in
                       ("rel_x", "rel_y", "rel_heading", "fallen", "present")]
                if s < len(order):
                    assert got == pytest.approx(block[order[s]].tolist()), (agent, part, s)
                else:  # nobody left for this slot: all zeros, present (the mask) 0
                    assert got == [0.0] * 5, (agent, part, s)
        # self, ball, play mode and game are kept as they are, the ball at the same columns
        for name in ("self.x", "self.heading", "ball.rel_x", "ball.rel_y", "game.time_s",
                     "play_mode.PlayOn"):
            assert out[out_names[name]] == row[names.index(name)]
        assert out_names["ball.rel_x"] == names.index("ball.rel_x") == 7


def test_the_length_does_not_depend_on_the_team_size():
    sizes = {n: EgocentricObservation.for_env(_box_env(n)).size for n in (1, 3, 7, 11)}
    assert set(sizes.values()) == {7 + 4 + 5 * (2 + 3) + 13 + 4}


def test_batches_equal_rows_and_bad_shapes_are_clear():
    env, obs = _stepped_rows(3, cycles=5)
    ego = EgocentricObservation.for_env(env)
    batch = np.stack([obs[a] for a in env.agents])
    assert np.array_equal(ego(batch), np.stack([ego(r) for r in batch]))
    with pytest.raises(ConfigError, match=r"expected \(n, \d+\)"):
        ego(batch[:, :-1])
    with pytest.raises(ConfigError, match="teammates must be an int >= 0"):
        EgocentricObservation(3, 2, teammates=-1)
    with pytest.raises(ConfigError, match="state-mode"):
        EgocentricObservation.for_env(teamenv.parallel_env(team_size=2,
                                                           observation_mode="vision"))


def _egocentric_file(path, size: int, seed: int = 0):
    rng = np.random.default_rng(seed)
    layers = [(rng.normal(0, 0.3, (size, 16)), rng.normal(0, 0.1, 16)),
              (rng.normal(0, 0.3, (16, 9)), rng.normal(0, 0.1, 9))]
    save_mlp_policy(path, layers, kick_gate_m=0.3)
    return add_egocentric_slots(path, 2, 3)


def test_an_egocentric_file_plays_any_team_size_through_its_team(tmp_path):
    size = EgocentricObservation(3, 2).size
    path = _egocentric_file(tmp_path / "ego.npz", size)
    assert egocentric_slots(path) == (2, 3)
    assert load_policy(path).observation_size == size  # the format's reader takes it as is
    for team_size in (3, 5):
        env = teamenv.parallel_env(team_size=team_size, left=TEAM_SPEC_NAME,
                                   left_config={"path": str(path)}, right="chaser")
        env.reset(seed=1)
        for _ in range(30):
            env.step({a: {} for a in env.agents} if env.agents else {})
        assert env.sim.cycle == 30
    # the plain policy team would feed it raw rows: it refuses, naming the sizes
    with pytest.raises(PolicyFileError, match=f"takes observations of {size}"):
        teamenv.parallel_env(team_size=3, left="policy", left_config={"path": str(path)})


def test_the_team_acts_as_the_network_on_egocentric_rows(tmp_path):
    env, obs = _stepped_rows(3, cycles=10)
    ego = EgocentricObservation.for_env(env)
    path = _egocentric_file(tmp_path / "ego.npz", ego.size, seed=4)
    network = load_policy(path)
    team_env = teamenv.parallel_env(team_size=3, left=TEAM_SPEC_NAME,
                                    left_config={"path": str(path)})
    team = team_env.teams["left"]
    raw = np.stack([obs[a] for a in env.agents if a.startswith("left_")])
    assert np.array_equal(team.team.policy(raw), network(ego(raw)))


def test_a_raw_file_plays_as_the_policy_team_and_bad_entries_are_clear(tmp_path):
    raw_size = _box_env(2).observation_space("left_1").shape[0]
    rng = np.random.default_rng(0)
    path = save_mlp_policy(tmp_path / "raw.npz", [(rng.normal(0, 0.3, (raw_size, 9)),
                                                   np.zeros(9))])
    assert egocentric_slots(path) is None
    results = []
    for left in (TEAM_SPEC_NAME, "policy"):
        env = teamenv.parallel_env(team_size=2, left=left, left_config={"path": str(path)},
                                   right="chaser")
        env.reset(seed=2)
        for _ in range(50):
            env.step({})
        results.append(env.state())
    assert np.array_equal(*results)
    arrays = dict(np.load(path))
    arrays["egocentric_teammates"] = np.asarray(2)
    with (tmp_path / "half.npz").open("wb") as fh:
        np.savez(fh, **arrays)
    with pytest.raises(PolicyFileError, match="both"):
        egocentric_slots(tmp_path / "half.npz")
    with pytest.raises(PolicyFileError, match="'path'"):
        teamenv.parallel_env(team_size=2, left=TEAM_SPEC_NAME)


def test_the_ball_race_columns_say_who_is_nearest_the_ball():
    """In world coordinates: each agent's distance to the ball, and the nearest upright
    teammate's and opponent's distance minus its own; the other columns unchanged."""
    env, obs = _stepped_rows(3, cycles=60)
    plain = EgocentricObservation.for_env(env, 2, 3)
    race = EgocentricObservation.for_env(env, 2, 3, ball_race=True)
    assert race.size == plain.size + 3
    assert race.names[-3:] == ("ball_race.distance", "ball_race.teammate_gap",
                               "ball_race.opponent_gap")
    world = env.unwrapped.sim.world
    ball = world.ball_state()[:2]
    distance = np.hypot(*(world.player_poses()[:, :2] - ball).T)
    down = env.unwrapped.sim.fallen()
    for k, agent in enumerate(env.agents):
        out = race(obs[agent])
        np.testing.assert_array_equal(out[:-3], plain(obs[agent]))
        side = slice(0, 3) if k < 3 else slice(3, 6)
        other = slice(3, 6) if k < 3 else slice(0, 3)
        mates = [j for j in range(*side.indices(6)) if j != k and not down[j]]
        opps = [j for j in range(*other.indices(6)) if not down[j]]
        assert out[-3] == pytest.approx(distance[k], abs=1e-3)
        assert out[-2] == pytest.approx(min(distance[mates]) - distance[k], abs=1e-3)
        assert out[-1] == pytest.approx(min(distance[opps]) - distance[k], abs=1e-3)
    with pytest.raises(ConfigError, match="ball_race must be true or false"):
        EgocentricObservation(3, 4, 2, 3, ball_race="yes")


def test_without_the_game_state_the_clock_and_score_are_left_out(tmp_path):
    env, obs = _stepped_rows(3)
    full = EgocentricObservation.for_env(env, 2, 3)
    short = EgocentricObservation.for_env(env, 2, 3, ball_race=True, game_state=False)
    kept = [n for n in full.names if not n.startswith("game.")]
    assert len(kept) == full.size - 4
    assert list(short.names) == kept + ["ball_race.distance", "ball_race.teammate_gap",
                                        "ball_race.opponent_gap"]
    row = obs["left_2"]
    np.testing.assert_array_equal(short(row)[:-3], full(row)[[full.names.index(n)
                                                               for n in kept]])
    with pytest.raises(ConfigError, match="game_state must be true or false"):
        EgocentricObservation(3, 4, 2, 3, game_state=None)
