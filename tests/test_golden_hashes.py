"""Seeded matches and env runs give exactly the results recorded before the speed work
(issue 16): a change that makes the code faster must not change a match. Re-record with
``env $(python -c 'from tests.golden import PINNED_ENV as e; print(*(f"{k}={v}" for k, v in
e.items()))') python -m tests.golden --write`` only when a rule changes, and say so."""

import json
import os
import subprocess
import sys
from pathlib import Path

from tests.golden import HASH_FILE, PINNED_ENV

ROOT = Path(__file__).resolve().parents[1]


def test_seeded_matches_and_env_runs_hash_as_recorded():
    env = {**os.environ, **PINNED_ENV, "PYTHONHASHSEED": "0"}
    out = subprocess.run([sys.executable, "-m", "tests.golden"], cwd=ROOT, env=env,
                         capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr[-3000:]
    now = json.loads(out.stdout)
    recorded = json.loads(HASH_FILE.read_text())
    changed = sorted(name for name in recorded if now.get(name) != recorded[name])
    assert set(now) == set(recorded), f"runs added or removed: {set(now) ^ set(recorded)}"
    assert not changed, f"these seeded runs no longer reproduce bit for bit: {changed}"
