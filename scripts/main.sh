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
echo "== a small tournament: round robin of full, chaser and static, 7 v 7 on mj7v7, two 60 s halves, =="
echo "== seeded rounds x both sides per pairing until each pairing is separated on territory (at most 4) =="
echo "== (silent, the full team without talk, plays the same state-mode match as full; vision mode: docs/team_strength.md) =="
rm -f out/tournament.sqlite
"$VENV/bin/teamenv" tournament run full chaser static --games 4 --stop-when-separated \
    --field mj7v7 --team-size 7 --half-time 60 --db out/tournament.sqlite -j 2 \
    --rank-by territory --csv out/table.csv --json out/table.json --plots out/plots
