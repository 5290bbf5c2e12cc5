"""Kept envs: a match on an env kept from earlier matches is the match on a fresh env, bit for
bit (every recorded array of its replay), and a tournament whose workers keep their envs stores
the rows of one that builds an env per match."""

from __future__ import annotations

import numpy as np
import pytest

from teamenv.match import MatchOptions, play_match
from teamenv.match_envs import MatchEnvs
from teamenv.tournament import ResultStore, backends, round_robin, run_tournament

STATE = MatchOptions(field="mj7v7", team_size=3, half_time_s=12.0, halves=1)
VISION = MatchOptions(field="mj7v7", team_size=3, half_time_s=6.0, halves=1,
                      observation_mode="vision", vision="mj", channel="mj")


def _replay_arrays(path):
    with np.load(path) as data:
        return {name: data[name] for name in data.files if name != "metadata"}


def _same_arrays(a, b):
    assert a.keys() == b.keys()
    for name in a:
        assert a[name].dtype == b[name].dtype and np.array_equal(a[name], b[name]), name


@pytest.mark.parametrize("options", [STATE, VISION], ids=["state", "vision"])
def test_a_kept_env_plays_the_match_of_a_fresh_one(tmp_path, options):
    # full talks, votes, filters and localises (vision): every kind of team state a reset
    # must restore; chaser's left side is the other team's
    seeds = (11, 12, 11)
    fresh = {seed: play_match("full", "chaser", seed, options,
                              replay_path=tmp_path / f"fresh{seed}.npz", replay_extras=True)
             for seed in set(seeds)}
    envs = MatchEnvs(size=2)
    for k, seed in enumerate(seeds):
        kept = play_match("full", "chaser", seed, options, envs=envs,
                          replay_path=tmp_path / f"kept{k}.npz", replay_extras=True)
        assert (kept.score, kept.goals, kept.cycles) == \
            (fresh[seed].score, fresh[seed].goals, fresh[seed].cycles)
        assert kept.team_time_s[0] <= kept.wall_s  # counted from this match on
        _same_arrays(_replay_arrays(tmp_path / f"kept{k}.npz"),
                     _replay_arrays(tmp_path / f"fresh{seed}.npz"))
    assert (envs.built, envs.reused, len(envs)) == (1, 2, 1)


def test_only_an_env_built_the_same_way_is_taken():
    envs = MatchEnvs(size=2)
    short = MatchOptions(team_size=1, half_time_s=1.0, halves=1)
    play_match("chaser", "static", 1, short, envs=envs)
    play_match("static", "chaser", 1, short, envs=envs)  # other sides: another env
    play_match("chaser", "static", 1, short, envs=envs, left_config={"all_chase": True})
    assert (envs.built, envs.reused, len(envs)) == (3, 0, 2)  # the oldest was closed
    play_match("chaser", "static", 1, short, envs=envs, left_config={"all_chase": True})
    assert (envs.built, envs.reused) == (3, 1)


def test_an_env_whose_match_ended_in_a_fault_is_not_kept():
    envs = MatchEnvs()
    result = play_match("chaser", "tests.teamenv.faulty_teams:RaisingTeam", 1,
                        MatchOptions(team_size=1, half_time_s=3.0, halves=1), envs=envs)
    assert result.forfeit is not None and result.forfeit.reason == "raised"
    assert (envs.built, len(envs)) == (1, 0)


def test_size_must_be_positive():
    with pytest.raises(ValueError, match="size must be a positive int, got 0"):
        MatchEnvs(size=0)


def _rows(db, summary):
    with ResultStore(db) as store:
        return [r.comparable() for r in store.matches(summary.tournament_id)]


def test_a_tournament_on_kept_envs_stores_the_rows_of_fresh_envs(tmp_path, monkeypatch):
    short = MatchOptions(field="mj7v7", team_size=3, half_time_s=5.0, halves=1)
    tournament = round_robin("kept", ["full", "chaser", "static"], games_per_pairing=2, seed=5,
                             options=short)
    monkeypatch.setattr(backends, "MATCH_ENVS", None)  # an env per match
    s = run_tournament(tournament, tmp_path / "fresh.sqlite", backend="serial", progress=False)
    fresh = _rows(tmp_path / "fresh.sqlite", s)
    kept_envs = MatchEnvs()
    monkeypatch.setattr(backends, "MATCH_ENVS", kept_envs)
    s = run_tournament(tournament, tmp_path / "kept.sqlite", backend="serial", progress=False)
    assert kept_envs.reused == 6 and kept_envs.built == 6  # each pairing's second game
    assert len(fresh) == 12 and _rows(tmp_path / "kept.sqlite", s) == fresh
