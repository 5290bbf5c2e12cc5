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
# Test files run in parallel, one worker per core up to 4 (pytest-xdist; TEAMENV_TEST_WORKERS=0
# runs in this process). Whole files go to one worker (--dist loadfile), so a module's expensive
# fixture is built once.
CORES="$(nproc 2>/dev/null || echo 2)"
WORKERS="${TEAMENV_TEST_WORKERS:-$(( CORES < 4 ? CORES : 4 ))}"
PARALLEL=(-n "$WORKERS" --dist loadfile)
[ "$WORKERS" = 0 ] && PARALLEL=()
# Two steps. First every test but the slow ones, each under pytest's per-test timeout
# (pyproject: 600 s, a guard against hangs). Then the tests marked slow (long but valuable:
# e.g. full-length strength matches), with no per-test timeout, so a loaded machine makes them
# late, not red; the step as a whole has its own budget (TEAMENV_SLOW_BUDGET_S, default 3600 s).
# Pytest's exit code 5 (nothing selected, e.g. a path without slow tests) is not a failure.
step() {
    local rc=0
    "$@" || rc=$?
    [ "$rc" = 5 ] && rc=0
    return "$rc"
}
status=0
# --durations: the slowest tests are listed at the end (where CI time goes).
step "$VENV/bin/python" -m pytest -m "not slow" "${PARALLEL[@]}" --durations=15 "$@" || status=$?
echo "== slow tests (no per-test timeout; budget ${TEAMENV_SLOW_BUDGET_S:-3600} s) =="
step timeout "${TEAMENV_SLOW_BUDGET_S:-3600}" "$VENV/bin/python" -m pytest -m slow \
    --timeout=0 "${PARALLEL[@]}" --durations=15 "$@" || status=$?
exit "$status"
