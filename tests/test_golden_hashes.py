"""Seeded matches and env runs give exactly the recorded results, whatever the CPU: a change
that makes the code faster must not change a match, and a match must not change with the
machine. The golden runs play once per NumPy/OpenBLAS setting, each in its own subprocess:

- ``native``: this CPU's own kernels (AVX-512 where it has it);
- ``avx2``: NumPy limited to AVX2 (``NPY_DISABLE_CPU_FEATURES``), OpenBLAS's own choice;
- ``pinned``: ``tests.golden.PINNED_ENV``, NumPy's SSE baseline and OpenBLAS's Haswell kernels.

Re-record with ``python -m tests.golden --write`` only when a rule changes, and say so."""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from tests.golden import HASH_FILE, PINNED_ENV

ROOT = Path(__file__).resolve().parents[1]
SETTINGS = {
    "native": {},
    "avx2": {"NPY_DISABLE_CPU_FEATURES": "X86_V4 AVX512_ICL AVX512_SPR"},
    "pinned": PINNED_ENV,
}


def start(setting: dict[str, str]) -> subprocess.Popen:
    env = {k: v for k, v in os.environ.items()
           if k not in ("NPY_DISABLE_CPU_FEATURES", "NPY_ENABLE_CPU_FEATURES",
                        "OPENBLAS_CORETYPE")}
    env.update({"OPENBLAS_NUM_THREADS": "1", "PYTHONHASHSEED": "0", **setting})
    return subprocess.Popen([sys.executable, "-m", "tests.golden"], cwd=ROOT, env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


@pytest.fixture(scope="module")
def hashes_by_setting() -> dict[str, dict[str, str]]:
    # two at a time: the runs are single-threaded and CI has two cores
    out = {}
    names = list(SETTINGS)
    for batch in (names[:2], names[2:]):
        running = {name: start(SETTINGS[name]) for name in batch}
        for name, proc in running.items():
            stdout, stderr = proc.communicate(timeout=900)
            assert proc.returncode == 0, f"{name}: {stderr[-3000:]}"
            out[name] = json.loads(stdout)
    return out


@pytest.mark.slow
@pytest.mark.parametrize("setting", list(SETTINGS))
def test_seeded_matches_and_env_runs_hash_as_recorded(hashes_by_setting, setting):
    now = hashes_by_setting[setting]
    recorded = json.loads(HASH_FILE.read_text())
    assert set(now) == set(recorded), f"runs added or removed: {set(now) ^ set(recorded)}"
    changed = sorted(name for name in recorded if now[name] != recorded[name])
    assert not changed, f"under {setting}, these seeded runs no longer reproduce: {changed}"
