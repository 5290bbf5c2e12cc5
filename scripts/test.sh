#!/usr/bin/env bash
# Set up a fresh virtual environment with every extra and run the whole test suite.
set -euo pipefail
cd "$(dirname "$0")/.."
VENV="${TEAMENV_VENV:-.venv}"
[ -x "$VENV/bin/python" ] || python3 -m venv "$VENV"
"$VENV/bin/python" -m pip install -q --upgrade pip
"$VENV/bin/python" -m pip install -q -e '.[dev,render,ray,humanoid,rl]'
# Small LAPACK calls (SciPy Delaunay) stall on a multi-threaded BLAS pool on 2 shared cores.
export SDL_VIDEODRIVER=dummy MPLBACKEND=Agg OPENBLAS_NUM_THREADS=1
exec "$VENV/bin/python" -m pytest "$@"
