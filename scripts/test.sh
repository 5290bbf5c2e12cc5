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
# The viewer's browser test drives Debian's chromium (Playwright's own download is unreachable).
if ! command -v chromium >/dev/null && command -v apt-get >/dev/null && [ "$(id -u)" = 0 ]; then
    export DEBIAN_FRONTEND=noninteractive
    { apt-get install -y -qq chromium || { apt-get update -qq && apt-get install -y -qq chromium; }; } \
        >/dev/null 2>&1 || echo "scripts/test.sh: could not install chromium" >&2
fi
exec "$VENV/bin/python" -m pytest "$@"
