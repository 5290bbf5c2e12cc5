"""Replays carry a SHA-256 of their content: a damaged replay that still parses is refused;
old (format 1-2) replays load; files that are not archives get a clear error, not numpy's
advice about pickles."""

from __future__ import annotations

import json

import numpy as np
import pytest

import teamenv
from teamenv.errors import ConfigError
from teamenv.policy_team import PolicyFileError, load_policy
from teamenv.replay import (
    CHECKSUM_KEY,
    REPLAY_FORMAT,
    ReplayRecorder,
    load_replay,
    replay_checksum,
)


@pytest.fixture(scope="module")
def replay_path(tmp_path_factory):
    env = teamenv.parallel_env(team_size=1)
    env.reset(seed=3)
    recorder = ReplayRecorder(env)
    recorder.record()
    for _ in range(20):
        env.step({a: {"walk": [0.5, 0.0, 0.0]} for a in env.agents})
        recorder.record()
    path = tmp_path_factory.mktemp("replay") / "m.npz"
    recorder.save(path, {"seed": 3})
    return path


def _arrays(path):
    with np.load(path) as data:
        arrays = {k: data[k] for k in data.files}
    meta = json.loads(arrays.pop("metadata").tobytes().decode())
    return arrays, meta


def _rewrite(path, arrays, meta):
    """A well-formed archive (fresh CRCs) of these arrays and metadata."""
    with open(path, "wb") as fh:
        np.savez_compressed(fh, **arrays,
                            metadata=np.frombuffer(json.dumps(meta).encode(), np.uint8))
    return path


def test_saved_replay_carries_its_checksum(replay_path):
    arrays, meta = _arrays(replay_path)
    assert meta["format"] == REPLAY_FORMAT == 3
    assert meta[CHECKSUM_KEY] == replay_checksum(arrays, meta)
    replay = load_replay(replay_path)
    assert replay.metadata["seed"] == 3 and len(replay) == 21


def test_changed_content_in_a_valid_archive_is_refused(replay_path, tmp_path):
    arrays, meta = _arrays(replay_path)
    arrays["players"] = arrays["players"].copy()
    arrays["players"][5, 0, 0] += 0.25  # a plausible position: nothing else could tell
    with pytest.raises(ConfigError, match=r"m2\.npz.*checksum mismatch.*damaged or changed"):
        load_replay(_rewrite(tmp_path / "m2.npz", arrays, meta))
    arrays, meta = _arrays(replay_path)
    meta["seed"] = 4  # the metadata is part of the content too
    with pytest.raises(ConfigError, match="checksum mismatch"):
        load_replay(_rewrite(tmp_path / "m3.npz", arrays, meta))


def test_format_3_without_a_checksum_is_refused_and_format_2_loads(replay_path, tmp_path):
    arrays, meta = _arrays(replay_path)
    del meta[CHECKSUM_KEY]
    with pytest.raises(ConfigError, match="format 3 but its metadata has no 'sha256'"):
        load_replay(_rewrite(tmp_path / "nosum.npz", arrays, meta))
    old = load_replay(_rewrite(tmp_path / "old.npz", arrays, dict(meta, format=2)))
    np.testing.assert_array_equal(old.players, load_replay(replay_path).players)


def test_bad_dtype_and_player_index_are_refused(replay_path, tmp_path):
    arrays, meta = _arrays(replay_path)
    meta = dict(meta, format=2)
    del meta[CHECKSUM_KEY]
    bad = dict(arrays, play_mode=arrays["play_mode"].astype(np.float32))
    with pytest.raises(ConfigError, match="play_mode has dtype float32, expected an integer"):
        load_replay(_rewrite(tmp_path / "dtype.npz", bad, meta))
    bad = dict(arrays, touch_cycle=np.array([1], np.int32), touch_player=np.array([9], np.int16))
    with pytest.raises(ConfigError, match=r"touch_player holds values outside \[0, 1\]"):
        load_replay(_rewrite(tmp_path / "who.npz", bad, meta))


@pytest.mark.parametrize("text", [b"just some notes\n", b"", b"PK"])
def test_a_text_file_named_npz_gets_a_clear_error(tmp_path, text):
    path = tmp_path / "notes.npz"
    path.write_bytes(text)
    with pytest.raises(ConfigError, match=r"notes\.npz.*not a teamenv replay file: not an "
                                          r"\.npz archive") as info:
        load_replay(path)
    assert "pickle" not in str(info.value)
    with pytest.raises(PolicyFileError, match=r"notes\.npz.*policy file: not an \.npz "
                                              r"archive") as info:
        load_policy(path)
    assert "pickle" not in str(info.value)


def test_an_npz_with_python_objects_is_refused(tmp_path):
    path = tmp_path / "objects.npz"
    with open(path, "wb") as fh:
        np.savez(fh, metadata=np.array([{"a": 1}], dtype=object))
    with pytest.raises(ConfigError, match="holds Python objects"):
        load_replay(path)
