"""Bad or truncated replay files, old formats and bad annotations give clear errors."""

from __future__ import annotations

import numpy as np
import pytest

from teamenv.analytics.stats import match_stats, replay_stats
from teamenv.analytics.xg import XGModel
from teamenv.cli import main
from teamenv.errors import ConfigError
from teamenv.replay import ReplayRecorder, load_replay
from tests.teamenv.analytics_replays import save_replay, story_arrays, story_metadata


@pytest.fixture
def good(tmp_path):
    return save_replay(tmp_path / "good.npz", story_arrays(), story_metadata())


def test_truncated_file(tmp_path, good):
    cut = tmp_path / "cut.npz"
    cut.write_bytes(good.read_bytes()[: good.stat().st_size // 2])
    with pytest.raises(ConfigError, match=r"cut\.npz.*not a readable teamenv replay"):
        load_replay(cut)


def test_not_a_replay(tmp_path):
    junk = tmp_path / "junk.npz"
    junk.write_bytes(b"hello, not a zip file at all")
    with pytest.raises(ConfigError, match="junk.npz"):
        load_replay(junk)
    with pytest.raises(ConfigError, match="missing.npz"):
        load_replay(tmp_path / "missing.npz")
    other = tmp_path / "other.npz"
    np.savez(other, x=np.zeros(3))
    with pytest.raises(ConfigError, match=r"no metadata.*\['x'\]"):
        load_replay(other)


def test_unknown_format_and_missing_arrays(tmp_path):
    meta = dict(story_metadata(), format=99)
    with pytest.raises(ConfigError, match="format 99"):
        load_replay(save_replay(tmp_path / "f99.npz", story_arrays(), meta))
    arrays = story_arrays()
    del arrays["kick_cycle"]
    with pytest.raises(ConfigError, match=r"\['kick_cycle'\] are missing"):
        load_replay(save_replay(tmp_path / "nokicks.npz", arrays, story_metadata()))


def test_inconsistent_lengths_and_event_rows(tmp_path):
    arrays = story_arrays()
    arrays["fallen"] = arrays["fallen"][:-3]
    with pytest.raises(ConfigError, match="fallen has 97 rows but time_s has 100"):
        load_replay(save_replay(tmp_path / "short.npz", arrays, story_metadata()))
    arrays = story_arrays()
    arrays["kick_cycle"] = np.array([10, 40, 500], np.int32)
    with pytest.raises(ConfigError, match="kick_cycle points outside the 100 recorded cycles"):
        load_replay(save_replay(tmp_path / "late.npz", arrays, story_metadata()))


def test_format_1_loads_but_has_no_statistics(tmp_path):
    arrays = {k: v for k, v in story_arrays().items()
              if k in ("ball", "players", "play_mode", "score", "time_s")}
    old = save_replay(tmp_path / "old.npz", arrays, {"format": 1, "team_size": 2})
    replay = load_replay(old)
    assert len(replay) == 100 and not replay.has_events and replay.fallen is None
    with pytest.raises(ConfigError, match="format 1 replay has no kicks"):
        match_stats(replay)


def test_cli_reports_the_error(tmp_path, capsys):
    cut = tmp_path / "cut.npz"
    cut.write_bytes(b"PK\x03\x04 truncated")
    assert main(["stats", str(cut)]) == 2
    assert "cut.npz" in capsys.readouterr().err


def test_bad_xg_model_file(tmp_path, good):
    bad = tmp_path / "xg.json"
    bad.write_text('{"model": "logistic", "features": ["distance_m"], "intercept": 0}')
    with pytest.raises(ConfigError, match="expected a logistic model over"):
        XGModel.load(bad)
    with pytest.raises(ConfigError, match="3 coefficients|one per feature"):
        XGModel(0.0, (1.0,))
    assert replay_stats(good).right.xg > 0  # the shipped model loads


class _Team:
    def __init__(self, annotations):
        self._annotations = annotations

    def annotations(self):
        return self._annotations


class _Env:
    """Just what ReplayRecorder._annotate reads."""

    team_size = 2

    def __init__(self, left):
        self.teams = {"left": _Team(left)}


@pytest.mark.parametrize("annotations, message", [
    ({"left_3": {"role": 0}}, "left team named agent 'left_3'"),
    ({"right_1": {"role": 0}}, "left team named agent 'right_1'"),
    ({"left_1": {"mood": 1}}, r"'left_1': unknown key\(s\) \['mood'\]"),
    ({"left_1": {"role_vector": [0, 1, 2]}}, "role_vector has 3 entries, expected 2"),
])
def test_bad_annotations_name_the_agent(annotations, message):
    recorder = ReplayRecorder(_Env(annotations), extras=True)
    with pytest.raises(ConfigError, match=message):
        recorder._annotate([1.0, -1.0])


def test_annotations_go_to_the_world_frame():
    recorder = ReplayRecorder(_Env({"left_2": {"pose": (1.0, 2.0, 0.5), "ball": (3.0, -1.0),
                                               "role": 1, "role_vector": [1, 0]}}), extras=True)
    recorder._annotate([-1.0, 1.0])  # the left side attacks -x (second half)
    pose, ball = recorder._pose[0], recorder._belief_ball[0]
    assert pose[1] == pytest.approx([-1.0, -2.0, 0.5 - np.pi])
    assert ball[1] == pytest.approx([-3.0, 1.0])
    assert np.isnan(pose[0]).all() and recorder._role[0].tolist() == [-1, 1, -1, -1]
    assert recorder._role_vector[0][1].tolist() == [1, 0]
