"""The reference pages (docs/*.md) run as written, like the tutorials (tests/test_tutorials.py).

Same parsers and rules as the tutorials: ``python`` and ``bash`` blocks run in order in one
namespace per page, ``title=`` blocks are files the reader saves, a block after
``<!-- skip: next -->`` is shown but not run (the page says why next to it), ``text``/``toml``/
``json`` blocks are never run.

The reference pages are read from the repository root (``python benchmarks/...``,
``.venv/bin/python ...``), so the fresh working folder gets a copy of ``benchmarks/`` and
``examples/`` and a ``.venv`` link to this environment; nothing a page writes lands in the
repository.
"""

from __future__ import annotations

import shutil
import sys
from pathlib import Path

import pytest

from tests.test_tutorials import SYBIL

ROOT = Path(__file__).resolve().parents[1]
PAGES = sorted((ROOT / "docs").glob("*.md"))
# The pages with a code block to run (comms, vision and benchmarks have none today).
REFERENCE = [p for p in PAGES if list(SYBIL.parse(p))]
# Pages that need an optional extra; CI installs every extra (scripts/test.sh), so they run there.
MARKS = {"league.md": [pytest.mark.humanoid], "selfplay.md": [pytest.mark.rl]}
COPIED = ("benchmarks", "examples")


@pytest.mark.parametrize(
    "page",
    [pytest.param(p, id=p.name, marks=MARKS.get(p.name, [])) for p in REFERENCE],
)
def test_reference_page_runs_as_written(
    page: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    for name in COPIED:
        shutil.copytree(ROOT / name, tmp_path / name,
                        ignore=shutil.ignore_patterns("__pycache__", "results"))
    (tmp_path / "benchmarks" / "results").mkdir()
    (tmp_path / ".venv").symlink_to(Path(sys.prefix), target_is_directory=True)
    monkeypatch.chdir(tmp_path)
    for name in ("no_proxy", "NO_PROXY"):  # the viewer page talks to its own local server
        monkeypatch.setenv(name, "127.0.0.1,localhost")
    monkeypatch.syspath_prepend(str(tmp_path))
    examples = list(SYBIL.parse(page))
    assert examples, f"{page} has no code block to run"
    for example in examples:
        example.evaluate()


def test_every_reference_page_is_in_the_site_nav() -> None:
    nav = (ROOT / "mkdocs.yml").read_text(encoding="utf-8")
    assert len(REFERENCE) >= 15
    for page in PAGES:
        assert page.name in nav, f"{page.name} is not in mkdocs.yml's nav"


def test_every_skipped_block_says_why() -> None:
    """A block the docs test does not run says so, with the reason, just before it."""
    for page in PAGES:
        lines = page.read_text(encoding="utf-8").splitlines()
        for number, line in enumerate(lines):
            if line.strip() == "<!-- skip: next -->":
                before = " ".join(" ".join(lines[max(0, number - 8):number]).split()).lower()
                assert "docs test" in before or "not run" in before, (
                    f"{page.name} line {number + 1}: a skipped block with no reason before it "
                    "(write why the docs test does not run it)"
                )
