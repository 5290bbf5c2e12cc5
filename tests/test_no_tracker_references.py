"""Docs, code and data say what they refer to, not which tracker issue asked for it (a reader
of the repository has no tracker: "issue 15, parts 3-5" tells them nothing)."""

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PLACES = ["README.md", "docs", "teamenv", "strategy", "comms", "locomotion", "portable_math",
          "benchmarks", "examples", "scripts", "tests"]
SUFFIXES = {".md", ".py", ".json", ".sh", ".yml", ".toml"}
TRACKER = re.compile(r"\b[Ii]ssues? ?#?\d+")


def test_no_tracker_references():
    found = []
    for place in PLACES:
        base = ROOT / place
        paths = [base] if base.is_file() else sorted(base.rglob("*"))
        for path in paths:
            if path.suffix not in SUFFIXES or not path.is_file() or path == Path(__file__):
                continue
            for n, line in enumerate(path.read_text(errors="replace").splitlines(), 1):
                if TRACKER.search(line):
                    found.append(f"{path.relative_to(ROOT)}:{n}: {line.strip()[:100]}")
    assert not found, "\n".join(found)
