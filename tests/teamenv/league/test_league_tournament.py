"""League round robin (``teamenv league-tournament``) without a server: the tournament
module's schedule, each match stored as it ends with its task's seed, resume plays only what
is missing, a definition mismatch or a missing tournament is an error, and the stored
tournament reads back like any other (table, the fidelity benchmark's points)."""

from __future__ import annotations

import pytest

from teamenv.cli import main
from teamenv.errors import TeamFault
from teamenv.league import tournament as lt
from teamenv.league.errors import LeagueError
from teamenv.league.match import LeagueMatchOptions
from teamenv.match import Goal, MatchResult
from teamenv.tournament import ResultStore, StoreError
from teamenv.tournament.table import league_table

TEAMS = ["chaser", "static", "full:communicate=false"]
OPTS = LeagueMatchOptions(team_size=2, game_s=3.0)


class FakePlay:
    """Stands in for play_league_match: the left team wins 1-0, unless it is static; stops
    (as a Ctrl-C would) after ``stop_after`` matches."""

    def __init__(self, stop_after=None):
        self.calls, self.stop_after = [], stop_after

    def __call__(self, left, right, options, seed, log_dir=None):
        if self.stop_after is not None and len(self.calls) == self.stop_after:
            raise KeyboardInterrupt
        self.calls.append((left, right, seed, options))
        score = (0, 0) if left == "static" else (1, 0)
        goals = (Goal(1.0, "left", None, None),) if score[0] else ()
        return MatchResult(seed=seed, left=left, right=right, score=score, goals=goals,
                           cycles=150, wall_s=1.0, options=options.match_options())


def test_round_robin_is_played_stored_and_resumed(tmp_path):
    db = tmp_path / "league.sqlite"
    first = FakePlay(stop_after=4)
    with pytest.raises(KeyboardInterrupt):
        lt.run_league_tournament("rr", db, TEAMS, OPTS, games=1, seed=5, play=first)
    again = FakePlay()
    summary = lt.run_league_tournament("rr", db, resume=True, play=again)
    assert (summary.scheduled, summary.played, summary.skipped) == (6, 2, 4)
    with ResultStore(db) as store:
        tid, tournament = store.get_tournament("rr")
        records = store.matches(tid)
    schedule = tournament.schedule()
    assert len(records) == 6 and {r.idx for r in records} == {t.index for t in schedule}
    assert {(r.left_team, r.right_team, r.seed) for r in records} == \
        {(t.left.label, t.right.label, t.seed) for t in schedule}
    played = first.calls + again.calls
    assert [(t.left.label, t.right.label, t.seed) for t in schedule] == \
        [(a, b, s) for a, b, s, _ in played]
    assert all(o == OPTS for *_, o in played)
    assert tournament.options.observation_mode == "vision" and tournament.options.vision == "mj"
    table = {row.team: row.points for row in league_table(records, TEAMS)}
    assert table == {"chaser": 7, "full:communicate=false": 7, "static": 2}  # 3 + 3 + 1 each
    assert lt.run_league_tournament("rr", db, resume=True, play=FakePlay()).played == 0


def test_errors_are_named(tmp_path):
    db = tmp_path / "league.sqlite"
    with pytest.raises(StoreError, match="no tournament 'rr' to resume"):
        lt.run_league_tournament("rr", db, resume=True, play=FakePlay())
    lt.run_league_tournament("rr", db, TEAMS[:2], OPTS, play=FakePlay())
    with pytest.raises(StoreError, match="tournament 'rr' already exists"):
        lt.run_league_tournament("rr", db, TEAMS[:2], OPTS, play=FakePlay())
    with pytest.raises(StoreError, match="definition"):
        lt.run_league_tournament("rr", db, TEAMS[:2], LeagueMatchOptions(team_size=3),
                                 resume=True, play=FakePlay())
    with pytest.raises(LeagueError, match="needs its teams and options"):
        lt.run_league_tournament("new", db, None, None, play=FakePlay())
    with pytest.raises(LeagueError, match="give both the teams and the options"):
        lt.run_league_tournament("new", db, TEAMS[:2], None, play=FakePlay())


def test_a_team_fault_stops_the_run_and_the_match_is_played_again_on_resume(tmp_path):
    db = tmp_path / "league.sqlite"

    class FaultOnSecond(FakePlay):
        def __call__(self, left, right, options, seed, log_dir=None):
            if len(self.calls) == 1:
                raise TeamFault("left", "raised", "team 'static' (agents left_1): act() raised")
            return super().__call__(left, right, options, seed, log_dir)

    with pytest.raises(TeamFault, match="act\\(\\) raised"):
        lt.run_league_tournament("rr", db, TEAMS[:2], OPTS, play=FaultOnSecond())
    with ResultStore(db) as store:
        tid, _ = store.get_tournament("rr")
        assert len(store.matches(tid)) == 1 and store.failures(tid) == []
    again = FakePlay()
    assert lt.run_league_tournament("rr", db, resume=True, play=again).played == 1
    assert len(again.calls) == 1


def test_cli(tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(lt, "play_league_match", FakePlay())
    db = str(tmp_path / "l.sqlite")
    assert main(["league-tournament", "chaser", "static", "--db", db, "--name", "rr",
                 "--team-size", "1", "--seconds", "2", "--games", "2"]) == 0
    out = capsys.readouterr().out
    assert "[4/4] " in out and "rr: 4 played, 0 already stored, 4 scheduled" in out
    assert main(["league-tournament", "--db", db, "--name", "rr", "--resume"]) == 0
    assert "rr: 0 played, 4 already stored" in capsys.readouterr().out
    assert main(["league-tournament", "--db", db, "--name", "other", "--resume"]) == 2
    assert "no tournament 'other' to resume" in capsys.readouterr().err


def test_league_round_robin_as_ray_tasks(tmp_path):
    """--ray-address local: the matches run as Ray tasks and are stored as usual."""
    pytest.importorskip("ray")
    import sys

    import ray.cloudpickle

    ray.cloudpickle.register_pickle_by_value(sys.modules[__name__])  # FakePlay, by value
    db = tmp_path / "rr.sqlite"
    summary = lt.run_league_tournament("rr", db, TEAMS[:2], OPTS, play=FakePlay(), workers=2,
                                       ray_address="local")
    assert summary.played == 2
    with ResultStore(db) as store:
        tid, _ = store.get_tournament("rr")
        rows = league_table(store.matches(tid), TEAMS[:2])
    assert {r.team: r.points for r in rows} == {"chaser": 4, "static": 1}  # a win, a draw


class SlowPlay:
    """A league match stand-in for worker processes: the first match (a marker file decides)
    ends at once, every other one marks that it started, sleeps ``sleep_s`` and marks that
    it finished."""

    def __init__(self, folder, sleep_s=60.0):
        self.folder, self.sleep_s = str(folder), sleep_s

    def __call__(self, left, right, options, seed, log_dir=None):
        import os
        import time
        from pathlib import Path

        folder = Path(self.folder)
        try:
            fd = os.open(folder / "first", os.O_CREAT | os.O_EXCL | os.O_WRONLY)
            os.close(fd)
        except FileExistsError:
            (folder / f"started-{seed}").touch()
            time.sleep(self.sleep_s)
            (folder / f"finished-{seed}").touch()
        return FakePlay()(left, right, options, seed)


def test_an_interrupt_stops_the_worker_processes(tmp_path):
    """Ctrl-C (or SIGTERM, the same in the study) after the first stored match: the matches in
    flight are stopped and the queued ones never start (a plain pool shutdown would play all
    of them to their end, unstored)."""
    markers = tmp_path / "markers"
    markers.mkdir()

    def interrupt(k, n, result):
        raise KeyboardInterrupt

    db = tmp_path / "rr.sqlite"
    with pytest.raises(KeyboardInterrupt):
        lt.run_league_tournament("rr", db, TEAMS, OPTS, play=SlowPlay(markers), workers=2,
                                 on_match=interrupt)
    started = sorted(p.name for p in markers.glob("started-*"))
    assert len(started) <= 2                       # at most one per worker; 6 matches queued
    assert not list(markers.glob("finished-*"))    # the sleeping matches were killed
    with ResultStore(db) as store:
        tid, _ = store.get_tournament("rr")
        assert len(store.matches(tid)) == 1        # the first match, stored before the stop
