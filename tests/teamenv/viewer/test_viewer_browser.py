"""The replay viewer end to end in a real headless browser: Playwright driving Debian's chromium.

Loads a recorded replay, plays, pauses, seeks with the slider, checks what the page drew
against the replay's arrays (numbers and pixels), the view cone and belief overlays, opens a
tournament's match from its list, and saves screenshots as CI artifacts
(``$TEAMENV_ARTIFACTS``, default ``out/artifacts``). ``scripts/test.sh`` installs chromium when
it is missing; without it these tests fail (they are the viewer's point), they do not skip.
"""

from __future__ import annotations

import dataclasses
import importlib.util
import os
import shutil
import time
from pathlib import Path

import numpy as np
import pytest

from teamenv.match import MatchOptions
from teamenv.replay import Replay, load_replay
from teamenv.tournament import ResultStore, round_robin, run_tournament
from teamenv.viewer.server import ViewerServer
from teamenv.viewer.sources import ViewerSource, open_source

from .test_viewer import record_replay, record_tournament

ROOT = Path(__file__).resolve().parents[3]
ARTIFACTS = Path(os.environ.get("TEAMENV_ARTIFACTS") or ROOT / "out" / "artifacts")
SEEK_CYCLE = 180
GRASS = (30, 120, 40)
READY = "window.teamenvViewer && teamenvViewer.state.ready"
PIXELS_JS = """(points) => {
  const ctx = document.getElementById('pitch').getContext('2d');
  return points.map(([x, y]) => {
    const [px, py] = teamenvViewer.toPixel(x, y);
    return Array.from(ctx.getImageData(Math.round(px), Math.round(py), 1, 1).data);
  });
}"""
BOX_JS = """([x, y, half]) => {
  const ctx = document.getElementById('pitch').getContext('2d');
  const [px, py] = teamenvViewer.toPixel(x, y);
  return Array.from(ctx.getImageData(Math.round(px - half), Math.round(py - half),
                                     2 * half, 2 * half).data);
}"""
COLOURS_JS = """() => {
  const c = document.getElementById('pitch'), ctx = c.getContext('2d');
  const data = ctx.getImageData(0, 0, c.width, c.height).data, seen = new Set();
  for (let k = 0; k < data.length; k += 4 * 7) seen.add(data[k] << 16 | data[k + 1] << 8 | data[k + 2]);
  return {width: c.width, height: c.height, colours: seen.size};
}"""


@pytest.fixture(scope="module")
def browser():
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        pytest.fail("the viewer's browser test needs Playwright: pip install -e '.[dev]'")
    chromium = shutil.which("chromium")
    if chromium is None:
        pytest.fail("the viewer's browser test needs Debian's chromium on PATH: "
                    "apt-get install -y chromium (scripts/test.sh does it when run as root)")
    with sync_playwright() as playwright:
        # root (CI containers) needs --no-sandbox; a small /dev/shm in containers crashes tabs
        args = ["--disable-dev-shm-usage"] + (["--no-sandbox"] if os.geteuid() == 0 else [])
        browser = playwright.chromium.launch(executable_path=chromium, headless=True, args=args)
        yield browser
        browser.close()


@pytest.fixture()
def page(browser):
    page = browser.new_page(viewport={"width": 1400, "height": 900}, device_scale_factor=1)
    errors: list[str] = []
    page.on("pageerror", lambda exc: errors.append(str(exc)))
    page.set_default_timeout(60_000)
    yield page
    page.close()
    assert not errors, f"JavaScript errors on the page: {errors}"


@pytest.fixture(scope="module")
def replay_path(tmp_path_factory) -> Path:
    return record_replay(tmp_path_factory.mktemp("viewer-browser") / "short.npz")


@pytest.fixture(scope="module")
def replay(replay_path) -> Replay:
    return load_replay(replay_path)


def pixels(page, points) -> list[tuple[int, ...]]:
    return [tuple(p) for p in page.evaluate(PIXELS_JS, [list(map(float, p)) for p in points])]


def seek_with_slider(page, cycle: int) -> None:
    page.eval_on_selector("#seek", "(e, c) => { e.value = String(c); "
                          "e.dispatchEvent(new Event('input')); }", cycle)


def isolated_players(players: np.ndarray, ball: np.ndarray, clearance_m: float = 1.0) -> list:
    """Players with nobody (and no ball) within ``clearance_m``: their disc centre is theirs."""
    out = []
    for i, (x, y, _) in enumerate(players):
        others = np.delete(players[:, :2], i, axis=0)
        if np.min(np.hypot(*(others - (x, y)).T)) > clearance_m and \
                np.hypot(ball[0] - x, ball[1] - y) > clearance_m:
            out.append(i)
    return out


def test_plays_pauses_seeks_and_draws_the_replay(page, replay_path, replay):
    with ViewerServer(open_source(replay_path)).start() as server:
        page.goto(server.url)
        page.wait_for_function(READY)
        assert page.evaluate("teamenvViewer.state.cycle") == 0
        assert page.evaluate("teamenvViewer.state.nCycles") == len(replay)

        page.click("#play")
        page.wait_for_function("teamenvViewer.state.cycle >= 25")
        assert page.evaluate("teamenvViewer.state.playing") is True
        assert page.text_content("#play") == "Pause"
        page.click("#play")
        paused_at = page.evaluate("teamenvViewer.state.cycle")
        time.sleep(0.3)  # frames keep coming; a paused viewer must not move
        assert page.evaluate("[teamenvViewer.state.cycle, teamenvViewer.state.playing]") == [
            paused_at, False]

        seek_with_slider(page, SEEK_CYCLE)
        drawn = page.evaluate("teamenvViewer.state.drawn")
        assert drawn["cycle"] == SEEK_CYCLE
        np.testing.assert_array_equal(np.asarray(drawn["players"], np.float32),
                                      replay.players[SEEK_CYCLE])
        np.testing.assert_array_equal(np.asarray(drawn["ball"], np.float32),
                                      replay.ball[SEEK_CYCLE, :2])
        assert drawn["score"] == replay.score[SEEK_CYCLE].tolist()
        assert page.text_content("#cycle-display").startswith(f"cycle {SEEK_CYCLE} / ")
        page.evaluate("document.activeElement.blur()")
        page.keyboard.press("ArrowRight")
        assert page.evaluate("teamenvViewer.state.drawn.cycle") == SEEK_CYCLE + 1
        page.keyboard.press("ArrowLeft")
        assert page.evaluate("teamenvViewer.state.drawn.cycle") == SEEK_CYCLE

        canvas = page.evaluate(COLOURS_JS)
        assert canvas["width"] > 500 and canvas["colours"] >= 5, canvas  # not blank
        players, ball = replay.players[SEEK_CYCLE], replay.ball[SEEK_CYCLE]
        checked = isolated_players(players, ball)
        assert len(checked) >= 2, "the seek cycle should have players standing apart"
        colours = page.evaluate("teamenvViewer.teamColours")
        centres = pixels(page, players[checked, :2])
        for i, rgba in zip(checked, centres, strict=True):
            team = i // replay.team_size
            assert rgba == (*colours[team], 255), f"player {i} at {players[i]}: {rgba}"
        (ball_rgba,) = pixels(page, [ball[:2]])
        assert min(ball_rgba[:3]) >= 230, ball_rgba

        if importlib.util.find_spec("teamenv.analytics") is None:
            page.wait_for_function("document.getElementById('stats-body').textContent"
                                   ".startsWith('not available')")
        else:  # the match statistics beside the pitch, one column per side
            page.wait_for_function("teamenvViewer.state.stats !== null")
            stats = page.text_content("#stats-body")
            assert "possession" in stats and "full" in stats and "chaser" in stats

        ARTIFACTS.mkdir(parents=True, exist_ok=True)
        page.screenshot(path=str(ARTIFACTS / "viewer.png"))
        assert (ARTIFACTS / "viewer.png").stat().st_size > 10_000


def cone_points(pose, half_angle: float) -> tuple[list, list]:
    """Points 1.5-3.5 m ahead of ``pose`` (on its heading and near the cone's edge) and behind."""
    x, y, heading = (float(v) for v in pose)

    def along(angle: float) -> list[tuple[float, float]]:
        return [(x + d * np.cos(angle), y + d * np.sin(angle)) for d in (1.5, 2.5, 3.5)]

    return along(heading) + along(heading + 0.8 * half_angle), along(heading + np.pi)


def test_view_cone_of_a_clicked_agent(page, replay_path, replay):
    players = replay.players[SEEK_CYCLE]
    half_angle = np.radians(120.0) / 2
    # an agent standing apart whose cone and back both lie on the pitch (15 x 10 m half sizes)
    agent = next(i for i in isolated_players(players, replay.ball[SEEK_CYCLE], 0.6)
                 if all(abs(px) < 14.5 and abs(py) < 9.5
                        for px, py in sum(cone_points(players[i], half_angle), [])))
    with ViewerServer(open_source(replay_path)).start() as server:
        page.goto(server.url + f"?cycle={SEEK_CYCLE}")
        page.wait_for_function(READY + f" && teamenvViewer.state.cycle === {SEEK_CYCLE}")
        header_cone = page.evaluate("teamenvViewer.state.header.view_cone")
        assert header_cone["fov_deg"] == 120.0
        assert header_cone["half_angle"] == pytest.approx(half_angle)
        px, py = page.evaluate("([x, y]) => teamenvViewer.toPixel(x, y)",
                               [float(players[agent, 0]), float(players[agent, 1])])
        box = page.locator("#pitch").bounding_box()
        page.mouse.click(box["x"] + px, box["y"] + py)  # a click selects the nearest player
        assert page.evaluate("teamenvViewer.state.selected") == agent

        inside, behind = cone_points(players[agent], half_angle)
        with_cone = pixels(page, inside + behind)
        page.uncheck("#ov-cone")
        without_cone = pixels(page, inside + behind)
        n = len(inside)
        changed = [a != b for a, b in zip(with_cone, without_cone, strict=True)]
        assert sum(changed[:n]) >= n - 1, (with_cone, without_cone)  # tinted inside
        assert not any(changed[n:]), (with_cone, without_cone)  # untouched behind
        assert sum(p[:3] == GRASS for p in without_cone[:n]) >= n - 1


class InMemorySource(ViewerSource):
    """One Replay object (with hand-made overlay arrays) served as match 0."""

    kind = "replay"

    def __init__(self, replay: Replay) -> None:
        super().__init__(Path("in-memory"))
        self._replay = replay

    def matches(self) -> list[dict]:
        return [{"id": 0, "label": "in memory", "replay": "recorded"}]

    def default_match(self) -> int:
        return 0

    def _load(self, match_id: int) -> Replay:
        return self._replay


def with_overlays(replay: Replay) -> Replay:
    """``replay`` plus beliefs (agent 1 believes itself 1 m ahead and 0.5 m left), roles and
    heard messages (agent 1 heard agents 0 and 2 on every cycle)."""
    t, n2 = replay.players.shape[:2]
    pose = replay.players.astype(np.float32).copy()
    pose[:, 1, 0] += 1.0
    pose[:, 1, 1] += 0.5
    pose[:, 3:] = np.nan  # the right team gave nothing
    ball = np.repeat(replay.ball[:, None, :2], n2, axis=1).astype(np.float32)
    role = np.tile(np.arange(n2, dtype=np.int8) % replay.team_size, (t, 1))
    heard = np.zeros((t, n2), np.uint32)
    heard[:, 1] = 0b101
    said = np.zeros((t, n2), np.uint8)
    said[:, [0, 2]] = 7
    return dataclasses.replace(replay, belief_pose=pose, belief_ball=ball, role=role,
                               heard_from=heard, say_bytes=said)


def test_belief_role_and_heard_overlays(page, replay):
    rich = with_overlays(replay)
    with ViewerServer(InMemorySource(rich)).start() as server:
        page.goto(server.url + f"?cycle={SEEK_CYCLE}")
        page.wait_for_function(READY + f" && teamenvViewer.state.cycle === {SEEK_CYCLE}"
                               " && teamenvViewer.state.overlaysLoaded")
        # nobody selected: a dot on each speaker, no speaker -> listener lines (docs/viewer.md)
        assert page.evaluate("teamenvViewer.state.drawn.heard") == []
        page.evaluate("teamenvViewer.select(1)")
        drawn = page.evaluate("teamenvViewer.state.drawn")
        (belief,) = drawn["beliefs"]
        assert belief["agent"] == 1
        np.testing.assert_array_equal(np.asarray(belief["pose"], np.float32),
                                      rich.belief_pose[SEEK_CYCLE, 1])
        assert sorted(drawn["heard"]) == [[0, 1], [2, 1]]
        agent = page.text_content("#agent-body")
        assert "error 1.12 m" in agent and "left_1" in agent and "left_3 (7 B)" in agent
        assert "role1" in agent.replace(" ", "")

        bx, by = (float(v) for v in rich.belief_pose[SEEK_CYCLE, 1, :2])
        shown = page.evaluate(BOX_JS, [bx, by, 12])
        page.uncheck("#ov-belief")
        hidden = page.evaluate(BOX_JS, [bx, by, 12])
        assert shown != hidden  # the believed pose is drawn where the agent believes it is
        assert page.evaluate("teamenvViewer.state.drawn.beliefs") == []


def test_tournament_match_list_opens_a_match(page, tmp_path):
    db = record_tournament(tmp_path / "t.sqlite", tmp_path / "replays")
    with ResultStore(db) as store:
        records = store.matches(store.get_tournament("mini")[0])
    with ViewerServer(open_source(db)).start() as server:
        page.goto(server.url)
        page.wait_for_function("document.querySelectorAll('#matches-body tr.match-row')"
                               f".length === {len(records)}")
        assert page.evaluate("teamenvViewer.state.ready") is False  # nothing opened yet
        wanted = records[-1]
        page.click(f"#matches-body tr[data-match-id='{wanted.id}']")
        page.wait_for_function(READY + f" && teamenvViewer.state.matchId === {wanted.id}")
        drawn = page.evaluate("teamenvViewer.state.drawn")
        replay = load_replay(wanted.replay_path)
        np.testing.assert_array_equal(np.asarray(drawn["players"], np.float32), replay.players[0])
        assert f"{wanted.left_team} vs {wanted.right_team}" in page.text_content("#match-title")
        assert "current" in page.get_attribute(
            f"#matches-body tr[data-match-id='{wanted.id}']", "class")

        ARTIFACTS.mkdir(parents=True, exist_ok=True)
        page.screenshot(path=str(ARTIFACTS / "viewer_tournament.png"))


def test_match_list_headers_stay_on_one_line_beside_long_team_labels(page, tmp_path):
    """The headers broke letter by letter when a long team label squeezed their columns."""
    long_spec = ("full:ball_pull=0.2974,dribble_speed=1.148,kick_goal_weight=43.55,"
                 "kick_possession_weight=5.184,pressure_m=3.8")
    t = round_robin("long-labels", [long_spec, "chaser"], games_per_pairing=1, seed=0,
                    options=MatchOptions(team_size=1, half_time_s=1.0, halves=1))
    db = tmp_path / "t.sqlite"
    run_tournament(t, db, backend="serial", replay_dir=tmp_path / "replays", progress=False)
    with ViewerServer(open_source(db)).start() as server:
        page.goto(server.url)
        page.wait_for_function("document.querySelectorAll('#matches-body tr.match-row')"
                               ".length === 2")
        cells = page.evaluate("[...document.querySelectorAll('#matches-body th')].map("
                              "th => [th.textContent, th.getBoundingClientRect().height,"
                              " parseFloat(getComputedStyle(th).lineHeight)])")
        assert len(cells) == 6
        for text, height, line in cells:   # one line of text, its padding and border
            assert height < 1.5 * line + 6, (text, height, line)
