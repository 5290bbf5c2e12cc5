"""No Python file over 500 lines outside tests without a reason written at its top.

A long file is usually two concepts grown together; split it by concept. Where one concept
really needs the length, say why in its first ``HEAD_LINES`` lines (above the module
docstring, say) with a comment of the form ``# Over 500 lines because ...``. The packages,
benchmarks, examples and scripts are checked; ``tests/`` is not.
"""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
LIMIT = 500
HEAD_LINES = 10
REASON = re.compile(r"^# Over 500 lines because \S")
SKIP_DIRS = {"tests", "build", "dist", "site", "node_modules", "__pycache__"}


def source_files() -> list[Path]:
    """Every .py file of the checkout outside tests/ and outside hidden or build folders."""
    out = []
    for path in ROOT.rglob("*.py"):
        parts = path.relative_to(ROOT).parts
        if any(p in SKIP_DIRS or p.startswith(".") or "site-packages" in p for p in parts[:-1]):
            continue
        out.append(path)
    return sorted(out)


def lines_and_reason(path: Path) -> tuple[int, bool]:
    lines = path.read_text(encoding="utf-8").splitlines()
    return len(lines), any(REASON.match(line) for line in lines[:HEAD_LINES])


def test_the_packages_are_checked():
    names = {p.relative_to(ROOT).as_posix() for p in source_files()}
    assert {"teamenv/env.py", "comms/channel.py", "strategy/teams/full.py"} <= names
    assert not any(n.startswith("tests/") for n in names)


def test_no_file_over_500_lines_without_a_reason():
    over = []
    for path in source_files():
        count, reason = lines_and_reason(path)
        if count > LIMIT and not reason:
            over.append(f"{path.relative_to(ROOT)} ({count} lines)")
    assert not over, (
        f"over {LIMIT} lines with no '# Over 500 lines because ...' in the first {HEAD_LINES} "
        f"lines: {over}; split by concept, or write why at the top")


def test_no_reason_left_on_a_file_that_no_longer_needs_it():
    stale = [f"{path.relative_to(ROOT)} ({count} lines)" for path in source_files()
             for count, reason in [lines_and_reason(path)] if reason and count <= LIMIT]
    assert not stale, f"these files are within {LIMIT} lines again: drop the reason: {stale}"
