"""A tournament killed with SIGKILL mid-run and resumed ends with the same results as an
uninterrupted run: nothing lost, nothing counted twice."""

from __future__ import annotations

import os
import signal
import sqlite3
import subprocess
import sys
import time
from pathlib import Path

from teamenv.match import MatchOptions
from teamenv.tournament import ResultStore, round_robin, run_tournament

ROOT = Path(__file__).resolve().parents[3]
TEAMS = ["chaser", "static", "chaser:all_chase=true"]
OPTIONS = MatchOptions(team_size=2, half_time_s=25.0, halves=1)
ARGS = ["--team-size", "2", "--half-time", "25", "--halves", "1", "--games", "2", "--seed", "3",
        "--name", "kill"]


def _count(db: Path) -> int:
    try:
        with sqlite3.connect(db, timeout=5) as conn:
            return int(conn.execute("SELECT COUNT(*) FROM matches").fetchone()[0])
    except sqlite3.OperationalError:  # not created yet
        return 0


def _cli(db: Path, *extra: str) -> subprocess.Popen:
    env = dict(os.environ, PYTHONPATH=f"{ROOT}{os.pathsep}{os.environ.get('PYTHONPATH', '')}")
    # SIGINT may be ignored by whatever started pytest; the CLI must see Ctrl-C as a user would
    return subprocess.Popen([sys.executable, "-m", "teamenv.tournament", "run", *extra,
                             "--db", str(db), "-j", "2", "--no-progress", "--bootstrap", "0"],
                            cwd=ROOT, env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, start_new_session=True,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))


def test_resume_after_sigkill_matches_uninterrupted_run(tmp_path):
    db = tmp_path / "killed.sqlite"
    proc = _cli(db, *TEAMS, *ARGS)
    deadline = time.monotonic() + 120
    try:
        while _count(db) < 3:
            assert proc.poll() is None, proc.stdout.read().decode()
            assert time.monotonic() < deadline, "no match stored in time"
            time.sleep(0.05)
    finally:
        os.killpg(proc.pid, signal.SIGKILL)  # the CLI and its workers, mid-match
        proc.wait()
    killed_at = _count(db)
    assert 3 <= killed_at < 12
    with sqlite3.connect(db) as conn:
        assert conn.execute("PRAGMA integrity_check").fetchone()[0] == "ok"

    resumed = _cli(db, "--resume")  # the definition comes from the database
    out, _ = resumed.communicate(timeout=240)
    assert resumed.returncode == 0, out.decode()
    assert f"played {12 - killed_at} now ({killed_at} were stored)" in out.decode()

    reference = tmp_path / "reference.sqlite"
    t = round_robin("kill", TEAMS, games_per_pairing=2, seed=3, options=OPTIONS)
    assert run_tournament(t, reference, jobs=2, progress=False).complete

    with ResultStore(db) as a, ResultStore(reference) as b:
        assert a.get_tournament("kill")[1] == t
        got = [r.comparable() for r in a.matches(a.get_tournament("kill")[0])]
        want = [r.comparable() for r in b.matches(b.get_tournament("kill")[0])]
        goals = a.conn.execute("SELECT COUNT(*) FROM goals").fetchone()[0]
        assert goals == b.conn.execute("SELECT COUNT(*) FROM goals").fetchone()[0]
        assert goals >= 1  # seed 3 has a goal in round 0: goal events are compared too
    assert len(got) == 12
    assert got == want


def test_ctrl_c_stops_cleanly_and_resume_completes(tmp_path):
    db = tmp_path / "int.sqlite"
    proc = _cli(db, "chaser", "static", "--team-size", "2", "--half-time", "3", "--halves",
                "1", "--games", "6", "--name", "int")
    deadline = time.monotonic() + 120
    while _count(db) < 2 and proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.05)
    os.killpg(proc.pid, signal.SIGINT)  # Ctrl-C reaches the CLI and its workers
    out, _ = proc.communicate(timeout=60)
    stored = _count(db)
    if proc.returncode == 0:  # finished before the signal landed: nothing to resume
        assert stored == 12
        return
    assert proc.returncode == 130, out.decode()
    assert "continue with --resume" in out.decode()
    resumed = _cli(db, "--resume", "--name", "int")
    out, _ = resumed.communicate(timeout=120)
    assert resumed.returncode == 0, out.decode()
    assert f"played {12 - stored} now ({stored} were stored)" in out.decode()
    assert _count(db) == 12
