"""The tutorials (docs/tutorials/*.md) and the README's quick start run as written.

Sybil reads each page and runs its fenced blocks in order, in one namespace per page, in a
fresh working folder:

- ```` ```python ```` blocks run as Python;
- ```` ```python title="my_team.py" ```` (any language with a title) are files the reader
  saves: they are written to the working folder under that name;
- ```` ```bash ```` blocks run in bash (``set -euo pipefail``) with this environment's
  ``teamenv`` and ``python`` first on PATH and the working folder on PYTHONPATH;
- a block after ``<!-- skip: next -->`` is shown but not run (long runs, commands that need a
  display or a second machine); other languages (``toml``, ``text``) are never run.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest
from sybil import Example, Sybil
from sybil.parsers.markdown import PythonCodeBlockParser, SkipParser
from sybil.parsers.markdown.lexers import FencedCodeBlockLexer

ROOT = Path(__file__).resolve().parents[1]
TUTORIALS = [p for p in sorted((ROOT / "docs" / "tutorials").glob("*.md")) if p.name != "index.md"]
PAGES = [*TUTORIALS, ROOT / "README.md"]
# Pages that need an optional extra; CI installs every extra (scripts/test.sh), so they run there.
MARKS = {"train_sb3.md": [pytest.mark.rl], "locomotion_fidelity.md": [pytest.mark.humanoid],
         "league_match.md": [pytest.mark.humanoid]}


def save_file(example: Example) -> None:
    name, source = example.parsed
    path = Path(name)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(source, encoding="utf-8")


def file_blocks(document):
    """Fenced blocks with a ``title="NAME"``: a file for the reader to save as NAME."""
    for region in FencedCodeBlockLexer(language=r'\w+ title="[^"]+"')(document):
        name = re.search(r'title="([^"]+)"', region.lexemes["language"]).group(1)
        region.parsed = (name, str(region.lexemes["source"]))
        region.evaluator = save_file
        yield region


def run_bash(example: Example) -> None:
    env = dict(os.environ)
    env["PATH"] = f"{Path(sys.executable).parent}{os.pathsep}{env.get('PATH', '')}"
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [os.getcwd(), env.get("PYTHONPATH")]))
    run = subprocess.run(["bash", "-euo", "pipefail", "-c", str(example.parsed)],
                         env=env, capture_output=True, text=True, timeout=600)
    if run.returncode != 0:
        raise AssertionError(
            f"{example.path} line {example.line}: the bash block exited {run.returncode}\n"
            f"--- stdout\n{run.stdout[-3000:]}\n--- stderr\n{run.stderr[-3000:]}"
        )


def bash_blocks(document):
    for region in FencedCodeBlockLexer(language="bash")(document):
        region.parsed = str(region.lexemes["source"])
        region.evaluator = run_bash
        yield region


SYBIL = Sybil(parsers=[PythonCodeBlockParser(), file_blocks, bash_blocks, SkipParser()])


@pytest.mark.parametrize(
    "page",
    [pytest.param(p, id=p.name, marks=MARKS.get(p.name, [])) for p in PAGES],
)
def test_page_runs_as_written(page: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    for name in ("no_proxy", "NO_PROXY"):  # the viewer page talks to its own local server
        monkeypatch.setenv(name, "127.0.0.1,localhost")
    monkeypatch.syspath_prepend(str(tmp_path))  # `my_team:MyTeam` as the page's reader names it
    document = SYBIL.parse(page)
    examples = list(document)
    assert examples, f"{page} has no code block to run"
    ran = 0
    for example in examples:
        example.evaluate()
        ran += 1
    assert ran == len(examples)


def test_every_tutorial_page_is_in_the_site_nav() -> None:
    nav = (ROOT / "mkdocs.yml").read_text(encoding="utf-8")
    assert len(TUTORIALS) >= 6
    for page in TUTORIALS:
        assert f"tutorials/{page.name}" in nav, f"{page.name} is not in mkdocs.yml's nav"
