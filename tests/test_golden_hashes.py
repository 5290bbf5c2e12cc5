"""Seeded matches and env runs give exactly the recorded results, whatever the CPU: a change
that makes the code faster must not change a match, and a match must not change with the
machine. The golden runs play once per NumPy/OpenBLAS setting, each in its own subprocess:

- ``native``: this CPU's own kernels (AVX-512 where it has it);
- ``avx2``: NumPy limited to AVX2 (``NPY_DISABLE_CPU_FEATURES``), OpenBLAS's own choice;
- ``pinned``: ``tests.golden.PINNED_ENV``, NumPy's SSE baseline and OpenBLAS's Haswell kernels.

On a CPU without any of the features the ``avx2`` setting turns off, that setting is the
native one (NumPy dispatches to the same kernels), so its hashes are the native run's rather
than a second identical run (``numpy``'s ``__cpu_features__`` says which features the CPU has).

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


def same_as_native(setting: dict[str, str]) -> bool:
    """True when ``setting`` changes nothing on this CPU: it only turns off NumPy CPU
    features (``NPY_DISABLE_CPU_FEATURES``) that this CPU does not have."""
    from numpy._core._multiarray_umath import __cpu_features__

    if set(setting) != {"NPY_DISABLE_CPU_FEATURES"}:
        return False
    return not any(__cpu_features__.get(name, False)
                   for name in setting["NPY_DISABLE_CPU_FEATURES"].split())


@pytest.fixture(scope="module")
def hashes_by_setting() -> dict[str, dict[str, str]]:
    # two at a time: the runs are single-threaded and CI has two cores
    out = {}
    names = [name for name in SETTINGS if name == "native" or not same_as_native(SETTINGS[name])]
    for batch in (names[:2], names[2:]):
        running = {name: start(SETTINGS[name]) for name in batch}
        for name, proc in running.items():
            stdout, stderr = proc.communicate(timeout=900)
            assert proc.returncode == 0, f"{name}: {stderr[-3000:]}"
            out[name] = json.loads(stdout)
    for name in SETTINGS:
        out.setdefault(name, out["native"])  # a setting that is the native one here
    return out


def test_a_setting_that_turns_off_a_feature_this_cpu_has_is_not_native():
    from numpy._core._multiarray_umath import __cpu_features__

    assert same_as_native({"NPY_DISABLE_CPU_FEATURES": "NO_SUCH_FEATURE"})
    assert not same_as_native(PINNED_ENV)  # it also pins OpenBLAS's kernels
    present = [name for name, has in __cpu_features__.items() if has]
    assert present  # every x86-64 CPU has SSE at least
    assert not same_as_native({"NPY_DISABLE_CPU_FEATURES": present[-1]})


@pytest.mark.slow
@pytest.mark.parametrize("setting", list(SETTINGS))
def test_seeded_matches_and_env_runs_hash_as_recorded(hashes_by_setting, setting):
    now = hashes_by_setting[setting]
    recorded = json.loads(HASH_FILE.read_text())
    assert set(now) == set(recorded), f"runs added or removed: {set(now) ^ set(recorded)}"
    changed = sorted(name for name in recorded if now[name] != recorded[name])
    assert not changed, f"under {setting}, these seeded runs no longer reproduce: {changed}"
