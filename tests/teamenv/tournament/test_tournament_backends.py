"""Backends: one tournament gives the same stored results whichever backend and how many
workers played it (serial vs process pool here; Ray vs process pool and serial in
test_tournament_ray.py), and the process pool starts its workers once and reuses them."""

from __future__ import annotations

import pytest

from teamenv.match import MatchOptions
from teamenv.tournament import ResultStore, round_robin, run_tournament
from teamenv.tournament.backends import (
    ProcessPoolBackend,
    SerialBackend,
    make_backend,
    team_names,
    warm_up,
)

OPTIONS = MatchOptions(team_size=2, half_time_s=25.0, halves=1)
TEAMS = ["chaser", "static", "chaser:all_chase=true"]


def _rows(db, summary):
    with ResultStore(db) as store:
        return [r.comparable() for r in store.matches(summary.tournament_id)]


def _tournament():
    return round_robin("same", TEAMS, games_per_pairing=1, seed=3, options=OPTIONS)


@pytest.fixture(scope="module")
def serial_rows(tmp_path_factory):
    db = tmp_path_factory.mktemp("serial") / "serial.sqlite"
    s = run_tournament(_tournament(), db, backend="serial", progress=False)
    assert s.complete and s.backend == "serial" and s.workers == 1
    rows = _rows(db, s)
    assert len(rows) == 6 and sum(len(r["goals"]) for r in rows) >= 1  # goals compared too
    return rows


@pytest.mark.parametrize("jobs", [1, 2])
def test_process_pool_equals_serial(tmp_path, serial_rows, jobs):
    s = run_tournament(_tournament(), tmp_path / "p.sqlite", jobs=jobs, progress=False)
    assert s.complete and s.backend == "process" and s.workers == jobs
    assert _rows(tmp_path / "p.sqlite", s) == serial_rows


def test_pool_workers_start_once_and_are_reused():
    backend = ProcessPoolBackend(2)
    assert backend.start_method in ("forkserver", "spawn")
    pool = backend.start_pool(("chaser", "static"))
    try:
        pids = {f.result() for f in [pool.submit(warm_up, ()) for _ in range(20)]}
    finally:
        pool.shutdown()
    assert 1 <= len(pids) <= 2


def test_team_names_and_serial_backend_by_name():
    assert team_names(_tournament().schedule()) == ("chaser", "static")
    assert isinstance(make_backend("serial", jobs=4), SerialBackend)
