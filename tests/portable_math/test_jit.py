"""numba is imported with Intel's SVML off, or not at all (``portable_math.jit``)."""

import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def run(code: str, **env: str) -> subprocess.CompletedProcess:
    environ = {k: v for k, v in os.environ.items() if k != "NUMBA_DISABLE_INTEL_SVML"}
    environ.update(env, PYTHONPATH=str(ROOT))
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          env=environ, cwd=ROOT, timeout=300)


def test_svml_is_switched_off_before_numba_reads_its_config():
    # even when the caller asked for it: SVML would trade the same bits everywhere for speed
    for asked in ({}, {"NUMBA_DISABLE_INTEL_SVML": "0"}):
        done = run("from portable_math.jit import numba\n"
                   "import portable_math.c_library_loops\n"
                   "print(numba.config.DISABLE_INTEL_SVML, numba.config.USING_SVML)", **asked)
        assert done.returncode == 0, done.stderr
        assert done.stdout.split() == ["1", "False"]


def test_numba_imported_earlier_with_svml_on_is_a_clear_error():
    # SVML is only on where Intel's library is installed; the flag numba sets is what counts
    done = run("import numba\n"
               "numba.config.USING_SVML = True\n"
               "from strategy.behaviours import walk_kernel\n")
    assert done.returncode != 0
    assert "ImportError" in done.stderr and "NUMBA_DISABLE_INTEL_SVML=1" in done.stderr


def test_numba_imported_earlier_without_svml_is_fine():
    done = run("import numba\n"
               "from portable_math.jit import numba as ours\n"
               "print(ours is numba, numba.config.USING_SVML)")
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == ["True", "False"]
