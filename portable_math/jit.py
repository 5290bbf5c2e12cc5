"""numba, imported with Intel's SVML off: every compiled loop of the project imports it from here.

With Intel's short-vector math library installed (``icc_rt``, common in Intel and conda
distributions) numba tells LLVM to vectorize ``exp``, ``pow``, ``sin``... in loops with SVML's
kernels, which round differently from the C library's scalar functions, and differently per
CPU (AVX2, AVX-512). The project's loops are written to give the C library's bits
(``portable_math``), so SVML would make a seed play another match on another machine. numba
reads ``NUMBA_DISABLE_INTEL_SVML`` once, when it is first imported, so this module sets it
before importing numba. If numba was imported earlier (by the caller, or another library)
with SVML on, the setting can no longer be undone in this process: the import fails with an
error that says what to do, instead of results that differ between machines.
"""

from __future__ import annotations

import os
import sys

if "numba" not in sys.modules:
    # Not setdefault: a caller's "0" would buy speed with machine-dependent results.
    os.environ["NUMBA_DISABLE_INTEL_SVML"] = "1"

import numba  # noqa: E402

if numba.config.USING_SVML:
    raise ImportError(
        "numba was imported with Intel SVML enabled (numba.config.USING_SVML is True), "
        "which changes the bits of exp/pow/sin in compiled loops from machine to machine; "
        "teamenv's results would not be reproducible. Set NUMBA_DISABLE_INTEL_SVML=1 in the "
        "environment, or import teamenv (or portable_math.jit) before numba."
    )

__all__ = ["numba"]
