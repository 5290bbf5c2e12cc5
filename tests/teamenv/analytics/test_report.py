"""teamenv report: one self-contained, well-formed HTML page with its images, for a match
replay and for a tournament database."""

from __future__ import annotations

import base64
from html.parser import HTMLParser

import pytest

from teamenv.cli import main
from teamenv.errors import ConfigError
from teamenv.match import MatchOptions
from teamenv.tournament import round_robin
from teamenv.tournament.report import write_report
from teamenv.tournament.runner import run_tournament
from teamenv.tournament.store import ResultStore
from tests.teamenv.analytics_replays import save_replay, story_arrays, story_metadata

VOID = {"meta", "img", "br", "hr", "link", "input"}
PNG = b"\x89PNG\r\n\x1a\n"


class _Checker(HTMLParser):
    """Collects images and checks that every element that opens also closes, in order."""

    def __init__(self) -> None:
        super().__init__()
        self.stack: list[str] = []
        self.images: list[str] = []
        self.tags: set[str] = set()
        self.external: list[str] = []

    def handle_starttag(self, tag, attrs):
        self.tags.add(tag)
        attrs = dict(attrs)
        if tag == "img":
            self.images.append(attrs["src"])
        if tag in ("script", "link") or (attrs.get("src") or "").startswith("http"):
            self.external.append(tag)
        if tag not in VOID:
            self.stack.append(tag)

    def handle_endtag(self, tag):
        assert self.stack and self.stack[-1] == tag, (self.stack, tag)
        self.stack.pop()


def check_page(text: str) -> _Checker:
    assert text.startswith("<!DOCTYPE html>")
    checker = _Checker()
    checker.feed(text)
    checker.close()
    assert checker.stack == []
    assert {"html", "head", "title", "body", "table"} <= checker.tags
    assert checker.external == []  # self-contained: no scripts, stylesheets or remote images
    for src in checker.images:
        prefix = "data:image/png;base64,"
        assert src.startswith(prefix)
        assert base64.b64decode(src[len(prefix):], validate=True).startswith(PNG)
    return checker


def test_match_report(tmp_path):
    replay = save_replay(tmp_path / "story.npz", story_arrays(), story_metadata())
    out = write_report(replay, tmp_path / "page.html")
    page = out.read_text()
    checker = check_page(page)
    assert len(checker.images) == 5  # heatmaps, pass networks, shots, timeline, messages
    assert "lefty 0 - 1 righty" in page and "expected goals" in page


def test_report_cli_and_bad_source(tmp_path, capsys):
    replay = save_replay(tmp_path / "story.npz", story_arrays(), story_metadata())
    assert main(["report", str(replay), "-o", str(tmp_path / "p.html")]) == 0
    check_page((tmp_path / "p.html").read_text())
    with pytest.raises(ConfigError, match="does not exist"):
        write_report(tmp_path / "nothing.npz", tmp_path / "x.html")
    bad = tmp_path / "bad.npz"
    bad.write_bytes(b"garbage")
    assert main(["report", str(bad), "-o", str(tmp_path / "b.html")]) == 2
    assert "bad.npz" in capsys.readouterr().err


def test_tournament_report_with_stored_statistics(tmp_path):
    db = tmp_path / "t.sqlite"
    t = round_robin("tiny", ["static", "chaser"], games_per_pairing=1,
                    options=MatchOptions(field="mj7v7", team_size=1, half_time_s=2.0))
    summary = run_tournament(t, db, jobs=1, progress=False)
    assert summary.complete
    with ResultStore(db) as store:
        stats = store.team_stats(summary.tournament_id)
        records = store.matches(summary.tournament_id)
    assert len(stats) == len(records) == 2
    assert all(set(s) == {"left", "right"} for s in stats.values())
    assert all(r.replay_path is None for r in records)  # scratch replays are not kept
    page = write_report(db, tmp_path / "t.html").read_text()
    checker = check_page(page)
    assert len(checker.images) == 2
    for metric in ("goals", "xg", "composite", "territory"):
        assert f"Ranked by {metric}" in page
