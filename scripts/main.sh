#!/usr/bin/env bash
# Set up a fresh virtual environment and run the main job: one match and a small tournament
# between the built-in teams, on the embedded defaults (local processes, SQLite in ./out).
set -euo pipefail
cd "$(dirname "$0")/.."
VENV="${TEAMENV_VENV:-.venv}"
[ -x "$VENV/bin/python" ] || python3 -m venv "$VENV"
"$VENV/bin/python" -m pip install -q --upgrade pip
"$VENV/bin/python" -m pip install -q -e '.[render]'
export SDL_VIDEODRIVER=dummy MPLBACKEND=Agg
mkdir -p out
echo "== one match: full vs chaser, simspark 11 v 11, two 60 s halves =="
"$VENV/bin/teamenv" match full chaser --seed 1 --half-time 60 --replay out/match.npz --gif out/match.gif
echo
echo "== a small tournament: round robin of the built-in teams, 2 seeds x both sides per pairing =="
rm -f out/tournament.sqlite
"$VENV/bin/teamenv" tournament run full silent chaser static --games 2 \
    --half-time 30 --team-size 5 --db out/tournament.sqlite -j 2 \
    --csv out/table.csv --json out/table.json --plots out/plots
