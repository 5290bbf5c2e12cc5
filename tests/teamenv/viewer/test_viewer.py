"""The replay viewer's server without a browser: routes, the binary replay form, the tournament
match list, bad or truncated files (a clear 4xx and a clear CLI error)."""

from __future__ import annotations

import importlib.util
import json
import sqlite3
import subprocess
import sys
import urllib.error
import urllib.request
from pathlib import Path

import numpy as np
import pytest

from teamenv.cli import main
from teamenv.config import VISION_PROFILES
from teamenv.match import MatchOptions, play_match
from teamenv.replay import load_replay
from teamenv.tournament import ResultStore, round_robin, run_tournament
from teamenv.viewer.errors import ViewerError
from teamenv.viewer.payload import view_cone
from teamenv.viewer.server import ViewerServer
from teamenv.viewer.sources import open_source

SHORT = MatchOptions(team_size=3, half_time_s=5.0, halves=1, observation_mode="vision")


def record_replay(path: Path, options: MatchOptions = SHORT, seed: int = 3) -> Path:
    """Play a short real match (full v chaser: the ball is touched and kicked in the first
    seconds) and save its replay at ``path``."""
    play_match("full", "chaser", seed=seed, options=options, replay_path=path)
    return path


def record_tournament(db: Path, replay_dir: Path) -> Path:
    """A stored two-match tournament (full v chaser, both sides) with replays."""
    options = MatchOptions(team_size=2, half_time_s=2.0, halves=1)
    t = round_robin("mini", ["full", "chaser"], games_per_pairing=1, seed=0, options=options)
    run_tournament(t, db, backend="serial", replay_dir=replay_dir, progress=False)
    return db


def decode_arrays(header: dict, blobs: dict[str, bytes]) -> dict[str, np.ndarray]:
    """The page's view of the blobs, in numpy (little-endian typed arrays at their offsets)."""
    types = {"Float32Array": "<f4", "Int8Array": "i1", "Uint8Array": "u1", "Int16Array": "<i2",
             "Uint16Array": "<u2", "Int32Array": "<i4", "Uint32Array": "<u4"}
    out = {}
    for spec in header["arrays"]:
        count = int(np.prod(spec["shape"]))
        out[spec["name"]] = np.frombuffer(blobs[spec["group"]], types[spec["dtype"]], count,
                                          spec["offset"]).reshape(spec["shape"])
    return out


def get_arrays(url: str, header: dict) -> dict[str, np.ndarray]:
    """Both blobs of a match from the server, decoded; each has the size the header says."""
    blobs = {}
    for group in ("core", "overlays"):
        status, blobs[group], kind = get(url + f"/arrays/{group}")
        assert status == 200 and kind == "application/octet-stream"
        assert len(blobs[group]) == header["bytes"][group]
    return decode_arrays(header, blobs)


def get(url: str) -> tuple[int, bytes, str]:
    try:
        with urllib.request.urlopen(url, timeout=60) as res:
            return res.status, res.read(), res.headers["Content-Type"]
    except urllib.error.HTTPError as exc:
        return exc.code, exc.read(), exc.headers["Content-Type"]


@pytest.fixture(scope="module")
def replay_path(tmp_path_factory) -> Path:
    return record_replay(tmp_path_factory.mktemp("viewer") / "short.npz")


@pytest.fixture(scope="module")
def tournament_db(tmp_path_factory) -> Path:
    root = tmp_path_factory.mktemp("viewer-tournament")
    return record_tournament(root / "t.sqlite", root / "replays")


@pytest.fixture()
def replay_server(replay_path):
    with ViewerServer(open_source(replay_path)).start() as server:
        yield server


def test_replay_arrays_travel_exactly(replay_server, replay_path):
    replay = load_replay(replay_path)
    status, body, kind = get(replay_server.url + "api/matches/0/header")
    assert status == 200 and kind == "application/json"
    header = json.loads(body)
    assert header["cycles"] == len(replay) and header["team_size"] == 3
    assert header["field"]["length"] == 30.0 and header["left"] == "full"
    arrays = get_arrays(replay_server.url + "api/matches/0", header)
    core = {spec["name"] for spec in header["arrays"] if spec["group"] == "core"}
    assert core == {"players", "ball", "play_mode", "score", "time_s"}  # enough to play
    np.testing.assert_array_equal(arrays["players"], replay.players)
    np.testing.assert_array_equal(arrays["ball"], replay.ball)
    np.testing.assert_array_equal(arrays["play_mode"], replay.play_mode)
    np.testing.assert_array_equal(arrays["score"], replay.score)
    np.testing.assert_allclose(arrays["time_s"], replay.time_s, atol=1e-4)
    np.testing.assert_array_equal(arrays["heard_from"], replay.heard_from)
    np.testing.assert_array_equal(arrays["fallen"], replay.fallen)
    assert "belief_pose" not in arrays  # recorded without extras
    assert all(spec["offset"] % 8 == 0 for spec in header["arrays"])


def test_vision_replay_carries_the_view_cone(replay_server):
    header = json.loads(get(replay_server.url + "api/matches/0/header")[1])
    fov = VISION_PROFILES["simspark"].fov_horizontal_deg
    assert header["view_cone"]["fov_deg"] == fov
    assert header["view_cone"]["half_angle"] == pytest.approx(np.radians(fov) / 2)
    assert view_cone({"observation_mode": "state"}) is None
    mj = view_cone({"observation_mode": "vision", "vision": "mj"})
    assert mj["fov_deg"] == VISION_PROFILES["mj"].fov_horizontal_deg


def test_page_and_static_files(replay_server):
    status, body, kind = get(replay_server.url)
    assert status == 200 and kind.startswith("text/html")
    assert b'<canvas id="pitch"' in body and b"/static/viewer.js" in body
    status, body, kind = get(replay_server.url + "static/viewer.js")
    assert status == 200 and kind.startswith("text/javascript")
    assert b"window.teamenvViewer" in body
    assert get(replay_server.url + "static/viewer.css")[0] == 200


def test_source_and_match_list_of_a_replay_file(replay_server, replay_path):
    source = json.loads(get(replay_server.url + "api/source")[1])
    assert source == {"kind": "replay", "path": str(replay_path), "default_match": 0}
    matches = json.loads(get(replay_server.url + "api/matches")[1])
    assert [(m["id"], m["left"], m["right"], m["replay"]) for m in matches] == [
        (0, "full", "chaser", "recorded")]


@pytest.mark.parametrize("path", ["api/matches/7/header", "api/matches/7/arrays/core",
                                  "api/matches/0/arrays/other", "nowhere",
                                  "static/secret.py", "static/../server.py"])
def test_unknown_pages_and_matches_are_404_with_a_message(replay_server, path):
    status, body, kind = get(replay_server.url + path)
    assert status == 404 and kind == "application/json"
    assert json.loads(body)["error"]


def test_stats_endpoint(replay_server):
    status, body, _ = get(replay_server.url + "api/matches/0/stats")
    if importlib.util.find_spec("teamenv.analytics") is None:
        assert status == 404 and "teamenv.analytics" in json.loads(body)["error"]
    else:
        assert status == 200
        stats = json.loads(body)
        assert set(stats["teams"]) == {"left", "right"}
        assert stats["teams"]["left"]["team"] == "full"


def test_tournament_lists_its_matches_and_serves_their_replays(tournament_db):
    with ResultStore(tournament_db) as store:
        records = store.matches(store.get_tournament("mini")[0])
    with ViewerServer(open_source(tournament_db)).start() as server:
        source = json.loads(get(server.url + "api/source")[1])
        assert source["kind"] == "tournament" and source["default_match"] is None
        matches = json.loads(get(server.url + "api/matches")[1])
        assert [m["id"] for m in matches] == [r.id for r in records]
        assert {m["tournament"] for m in matches} == {"mini"}
        assert all(m["replay"] == "recorded" for m in matches)
        for record in records:
            header = json.loads(get(server.url + f"api/matches/{record.id}/header")[1])
            assert (header["left"], header["right"]) == (record.left_team, record.right_team)
            players = get_arrays(server.url + f"api/matches/{record.id}", header)["players"]
            np.testing.assert_array_equal(players, load_replay(record.replay_path).players)


def test_truncated_replay_of_a_tournament_match_is_a_422(tournament_db, tmp_path):
    with ResultStore(tournament_db) as store:
        record = store.matches(store.get_tournament("mini")[0])[0]
    data = Path(record.replay_path).read_bytes()
    try:
        Path(record.replay_path).write_bytes(data[: len(data) // 3])
        with ViewerServer(open_source(tournament_db)).start() as server:
            status, body, _ = get(server.url + f"api/matches/{record.id}/arrays/core")
            assert status == 422
            error = json.loads(body)["error"]
            assert record.replay_path in error and "not a readable teamenv replay" in error
            assert get(server.url + "api/matches/999/header")[0] == 404
    finally:
        Path(record.replay_path).write_bytes(data)


def test_a_match_without_its_replay_file_is_played_again(tournament_db):
    with ResultStore(tournament_db) as store:
        record = store.matches(store.get_tournament("mini")[0])[-1]
    recorded = load_replay(record.replay_path)
    path, moved = Path(record.replay_path), Path(record.replay_path + ".away")
    path.rename(moved)
    try:
        with ViewerServer(open_source(tournament_db)).start() as server:
            listed = {m["id"]: m["replay"] for m in json.loads(get(server.url + "api/matches")[1])}
            assert listed[record.id] == "played again from its seed"
            status, body, _ = get(server.url + f"api/matches/{record.id}/header")
            assert status == 200
            header = json.loads(body)
            again = get_arrays(server.url + f"api/matches/{record.id}", header)
            np.testing.assert_array_equal(again["players"], recorded.players)
    finally:
        moved.rename(path)


def test_a_format_1_replay_plays_without_overlays_or_stats(replay_path, tmp_path):
    old = tmp_path / "format1.npz"
    with np.load(replay_path) as data:
        meta = json.loads(bytes(data["metadata"]).decode())
        arrays = {k: data[k] for k in ("ball", "players", "play_mode", "score", "time_s")}
    meta["format"] = 1
    np.savez_compressed(old, **arrays, metadata=np.frombuffer(json.dumps(meta).encode(),
                                                              dtype=np.uint8))
    with ViewerServer(open_source(old)).start() as server:
        header = json.loads(get(server.url + "api/matches/0/header")[1])
        assert header["bytes"]["overlays"] == 0
        np.testing.assert_array_equal(get_arrays(server.url + "api/matches/0", header)["players"],
                                      arrays["players"])
        status, body, _ = get(server.url + "api/matches/0/stats")
        if importlib.util.find_spec("teamenv.analytics") is not None:
            assert status == 422 and "format" in json.loads(body)["error"]


def test_bad_files_are_clear_errors(replay_path, tmp_path):
    with pytest.raises(ViewerError, match="no such file"):
        open_source(tmp_path / "missing.npz")
    truncated = tmp_path / "truncated.npz"
    truncated.write_bytes(replay_path.read_bytes()[:500])
    with pytest.raises(ViewerError, match="not a readable teamenv replay file"):
        open_source(truncated)
    text = tmp_path / "notes.npz"
    text.write_text("not a replay")
    with pytest.raises(ViewerError, match="notes.npz"):
        open_source(text)
    bad_shape = tmp_path / "bad_shape.npz"
    with np.load(replay_path) as data:
        arrays = {k: data[k] for k in data.files}
    arrays["players"] = arrays["players"][:, :, :2]
    np.savez(bad_shape, **arrays)
    with pytest.raises(ViewerError, match=r"players'? has shape"):
        open_source(bad_shape)


def test_a_foreign_sqlite_file_is_refused_and_left_as_it_was(tmp_path):
    db = tmp_path / "other.sqlite"
    conn = sqlite3.connect(db)
    conn.execute("CREATE TABLE notes (text TEXT)")
    conn.commit()
    conn.close()
    before = db.read_bytes()
    with pytest.raises(ViewerError, match="not a teamenv tournament database"):
        open_source(db)
    assert db.read_bytes() == before


def test_cli_reports_a_bad_replay_and_exits_2(replay_path, tmp_path, capsys):
    truncated = tmp_path / "truncated.npz"
    truncated.write_bytes(replay_path.read_bytes()[:500])
    assert main(["view", str(truncated), "--no-browser"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("teamenv: error: replay ") and "truncated.npz" in err
    assert main(["view", str(tmp_path / "nothing.sqlite"), "--no-browser"]) == 2
    assert "no such file" in capsys.readouterr().err
    assert main(["view", str(replay_path), "--no-browser", "--port", "70000"]) == 2
    assert "--port: 70000" in capsys.readouterr().err


def test_cli_serves_until_stopped(replay_path):
    proc = subprocess.Popen([sys.executable, "-m", "teamenv", "view", str(replay_path),
                             "--no-browser"], stdout=subprocess.PIPE, text=True)
    try:
        line = proc.stdout.readline()
        assert "teamenv viewer: replay" in line, line
        url = line.split(" at ")[1].split()[0]
        assert url.startswith("http://127.0.0.1:")
        status, body, _ = get(url + "api/source")
        assert status == 200 and json.loads(body)["kind"] == "replay"
    finally:
        proc.terminate()
        proc.wait(timeout=30)
