"""The teamenv command under signals and pipes: SIGTERM stops a tournament as cleanly as
Ctrl-C (no worker, fork server or resource tracker left running, what is stored stays), and a
reader that goes away (`| head`) ends the listing quietly."""

from __future__ import annotations

import os
import signal
import sqlite3
import subprocess
import sys
import time
from pathlib import Path

import pytest

TEAMENV = str(Path(sys.executable).with_name("teamenv"))


def _session_members(sid: int) -> list[int]:
    """Live processes in session ``sid`` (the command was started as its leader)."""
    found = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            stat = (entry / "stat").read_text()
        except OSError:
            continue
        fields = stat[stat.rindex(")") + 2:].split()
        if fields[0] != "Z" and int(fields[3]) == sid:   # state, ppid, pgrp, session
            found.append(int(entry.name))
    return found


def _default_interrupt() -> None:
    """In the child before exec: Ctrl-C's default disposition. An ignored signal stays ignored
    across exec, and a pytest-xdist worker ignores SIGINT, so under ``-n 2`` the command would
    never see the interrupt and run to the end (CI saw it exit 0)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def _stored(db: Path) -> int:
    with sqlite3.connect(db) as con:
        return con.execute("SELECT COUNT(*) FROM matches").fetchone()[0]


@pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="reads /proc (Linux)")
@pytest.mark.parametrize("sig, status", [(signal.SIGTERM, 143), (signal.SIGINT, 130)])
def test_a_signal_stops_a_tournament_and_its_workers(tmp_path, sig, status):
    db = tmp_path / "t.sqlite"
    proc = subprocess.Popen(
        [TEAMENV, "tournament", "run", "chaser", "static", "--games", "6", "--team-size", "2",
         "--half-time", "4", "--halves", "1", "-j", "2", "--db", str(db), "--no-progress"],
        stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, start_new_session=True,
        preexec_fn=_default_interrupt)
    deadline = time.monotonic() + 240
    while time.monotonic() < deadline and proc.poll() is None:  # until the pool is up and a
        if db.exists() and len(_session_members(proc.pid)) >= 3:  # match or two are stored
            try:
                if _stored(db) >= 1:
                    break
            except sqlite3.Error:
                pass
        time.sleep(0.2)
    assert proc.poll() is None, "the tournament ended before the signal: make it longer"
    os.kill(proc.pid, sig)
    assert proc.wait(timeout=120) == status, proc.stderr.read().decode()[-2000:]
    deadline = time.monotonic() + 30
    while _session_members(proc.pid) and time.monotonic() < deadline:
        time.sleep(0.2)
    left = _session_members(proc.pid)
    for pid in left:                       # do not leave them to the next test
        os.kill(pid, signal.SIGKILL)
    assert not left, f"still running after the signal: {left}"
    stored = _stored(db)
    assert 1 <= stored < 12
    resumed = subprocess.run([TEAMENV, "tournament", "run", "--resume", "--db", str(db),
                              "--no-progress", "-j", "1"], capture_output=True, timeout=600)
    assert resumed.returncode == 0 and _stored(db) == 12


def test_matches_listing_has_a_header_and_survives_a_closed_pipe(tmp_path):
    db = tmp_path / "t.sqlite"
    subprocess.run([TEAMENV, "tournament", "run", "chaser", "static", "--games", "2",
                    "--team-size", "1", "--half-time", "1", "--halves", "1", "-j", "1",
                    "--db", str(db), "--no-progress"], check=True, capture_output=True,
                   timeout=300)
    listing = subprocess.run([TEAMENV, "tournament", "matches", "--db", str(db)],
                             capture_output=True, text=True, check=True, timeout=60).stdout
    header, *rows = listing.splitlines()
    assert header.split()[:2] == ["id", "#idx"] and len(rows) == 4
    # `| head`: the reader has gone away before the listing is written (a closed pipe), so
    # the first write fails with EPIPE; the command ends quietly with SIGPIPE's status
    read_end, write_end = os.pipe()
    os.close(read_end)
    try:
        done = subprocess.run([TEAMENV, "tournament", "matches", "--db", str(db)],
                              stdout=write_end, stderr=subprocess.PIPE, text=True, timeout=60)
    finally:
        os.close(write_end)
    assert "Traceback" not in done.stderr and "BrokenPipe" not in done.stderr, done.stderr
    assert done.returncode == 128 + signal.SIGPIPE
