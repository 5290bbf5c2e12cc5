"""Running tournaments: schedule, storage, resume idempotence, forfeits, crashed workers,
gauntlet, exports, replays."""

from __future__ import annotations

import json
import sqlite3

import pytest

from teamenv.match import MatchOptions
from teamenv.tournament import (
    ResultStore,
    StoreError,
    Tournament,
    gauntlet,
    round_robin,
    run_tournament,
)

FAULTY = "tests.teamenv.tournament_faulty_teams"
SHORT = MatchOptions(team_size=2, half_time_s=3.0, halves=1)


def test_schedule_round_robin_and_gauntlet():
    t = round_robin("t", ["a:x=1", "b", "c"], games_per_pairing=2, seed=5)
    tasks = t.schedule()
    assert len(tasks) == 3 * 2 * 2
    assert [x.index for x in tasks] == list(range(12))
    seeds = t.round_seeds()
    assert len(set(seeds)) == 2 and all(0 <= s < 2 ** 31 for s in seeds)
    assert {x.seed for x in tasks if x.round == 1} == {seeds[1]}
    first = [x for x in tasks if x.pairing == "a:x=1 vs b"]
    assert [(x.left.label, x.right.label, x.swapped) for x in first[:2]] == \
        [("a:x=1", "b", False), ("b", "a:x=1", True)]
    assert len({x.key for x in tasks}) == 12
    assert round_robin("t", ["a", "b"], seed=6).round_seeds() != \
        round_robin("t", ["a", "b"], seed=5).round_seeds()
    g = gauntlet("g", "a", ["b", "c", "d"], games_per_pairing=1, swap_sides=False)
    assert [(x.left.label, x.right.label) for x in g.schedule()] == [("a", "b"), ("a", "c"),
                                                                      ("a", "d")]
    assert Tournament.from_json(t.to_json()) == t


def test_run_store_and_resume_is_idempotent(tmp_path):
    db = tmp_path / "t.sqlite"
    t = round_robin("rr", ["chaser", "static"], games_per_pairing=2, options=SHORT, seed=1)
    s = run_tournament(t, db, jobs=2, progress=False)
    assert s.complete and s.played == 4 and s.scheduled == 4 and s.failures == ()
    with ResultStore(db) as store:
        tid, stored = store.get_tournament("rr")
        assert stored == t
        records = store.matches(tid)
        assert [r.idx for r in records] == [0, 1, 2, 3]
        assert all(r.left_version == r.right_version == "teamenv 0.1.0" for r in records)
        assert all(r.cycles >= 150 and r.wall_s > 0 for r in records)
        assert store.team_versions(tid) == {"chaser": "teamenv 0.1.0", "static": "teamenv 0.1.0"}
    # resume of a complete tournament plays nothing; the definition can come from the db
    again = run_tournament(None, db, resume=True, jobs=1, progress=False)
    assert again.played == 0 and again.skipped == 4 and again.stored == 4
    with pytest.raises(StoreError, match="already exists"):
        run_tournament(t, db, jobs=1, progress=False)
    changed = round_robin("rr", ["chaser", "static"], games_per_pairing=3, options=SHORT)
    with pytest.raises(StoreError, match="games_per_pairing"):
        run_tournament(changed, db, resume=True, jobs=1, progress=False)
    # the unique constraint refuses a second copy of a match
    with ResultStore(db) as store:
        tid, _ = store.get_tournament("rr")
        from teamenv.tournament.backends import execute_task
        task = t.schedule()[0]
        assert store.record_match(tid, task, execute_task(task)) is False
        assert store.count_matches(tid) == 4
    with sqlite3.connect(db) as conn:
        assert conn.execute("PRAGMA journal_mode").fetchone()[0] == "wal"


def test_faulty_teams_forfeit_and_the_tournament_goes_on(tmp_path):
    db = tmp_path / "f.sqlite"
    t = gauntlet("faults", "static", [f"{FAULTY}:RaisingTeam", f"{FAULTY}:InvalidTeam",
                                      f"{FAULTY}:SlowTeam", f"{FAULTY}:StallingTeam"],
                 games_per_pairing=1, swap_sides=False, options=SHORT,
                 cycle_time_budget_s=0.1, stall_timeout_s=1.0)
    s = run_tournament(t, db, jobs=2, progress=False)
    assert s.complete and s.played == 4
    with ResultStore(db) as store:
        records = {r.right_team.split(":")[-1]: r for r in store.matches(s.tournament_id)}
    expected = {"RaisingTeam": "raised", "InvalidTeam": "invalid_action",
                "SlowTeam": "too_slow", "StallingTeam": "stalled"}
    for team, reason in expected.items():
        r = records[team]
        assert (r.forfeit_side, r.forfeit_reason) == ("right", reason), r
        assert r.forfeit_detail
        assert (r.left_official, r.right_official) == (3, 0)
    assert s.forfeits == {"raised": 1, "invalid_action": 1, "too_slow": 1, "stalled": 1}


def test_crashed_worker_is_isolated_and_recorded(tmp_path):
    db = tmp_path / "c.sqlite"
    crash = f"{FAULTY}:CrashingTeam"
    t = round_robin("crash", ["chaser", "static", crash], games_per_pairing=1,
                    swap_sides=False, options=SHORT)
    s = run_tournament(t, db, jobs=2, progress=False)
    # the two matches of the crashing team kill their worker: recorded as failures, the
    # others are played; nothing is counted for the failed ones
    assert s.stored == 1 and s.scheduled == 3 and not s.complete
    assert len(s.failures) == 2 and all("worker process died" in e for _, e in s.failures)
    with ResultStore(db) as store:
        assert [(r.left_team, r.right_team) for r in store.matches(s.tournament_id)] == \
            [("chaser", "static")]


def test_cli_table_exports_and_replay(tmp_path, capsys):
    from teamenv.cli import main
    from teamenv.tournament.replays import match_replay

    db = tmp_path / "cli.sqlite"
    code = main(["tournament", "run", "chaser", "static", "--db", str(db), "--name", "c",
                 "--team-size", "2", "--half-time", "3", "--halves", "1", "--games", "1",
                 "-j", "1", "--no-progress", "--bootstrap", "20",
                 "--replay-dir", str(tmp_path / "replays")])
    assert code == 0
    out = capsys.readouterr().out
    assert "2/2 matches stored, complete" in out and "chaser" in out
    assert main(["tournament", "table", "--db", str(db), "--csv", str(tmp_path / "t.csv"),
                 "--json", str(tmp_path / "t.json"), "--plots", str(tmp_path / "plots"),
                 "--bootstrap", "20"]) == 0
    data = json.loads((tmp_path / "t.json").read_text())
    assert {row["team"] for row in data["table"]} == {"chaser", "static"}
    assert data["tournament"]["name"] == "c" and "bradley_terry" in data["ratings"]
    assert (tmp_path / "plots" / "ratings.png").stat().st_size > 1000
    assert (tmp_path / "plots" / "goal_difference.png").stat().st_size > 1000
    assert main(["tournament", "matches", "--db", str(db)]) == 0
    assert main(["tournament", "list", "--db", str(db)]) == 0
    assert "c: round_robin, 2 teams, 2/2 matches" in capsys.readouterr().out
    with ResultStore(db) as store:
        first = store.matches(1)[0]
    assert first.replay_path and match_replay(db, first.id) == __import__("pathlib").Path(
        first.replay_path)
    # no stored replay: the match is played again from its seed and checked
    again = match_replay(db, first.id, replay_out=tmp_path / "again.npz")
    from teamenv.replay import load_replay
    assert load_replay(again).metadata["seed"] == first.seed
    pytest.importorskip("pygame")
    pytest.importorskip("imageio")
    gif = tmp_path / "m.gif"
    assert main(["tournament", "replay", str(first.id), "--db", str(db), "--out", str(gif),
                 "--every", "25"]) == 0
    assert gif.stat().st_size > 0
