"""``teamenv optimize`` end to end on real (tiny) matches: common seeds within a generation,
fitness from the stored matches, resume plays only what is missing, the exported override is
usable by name in tournaments, and bad input gives clear errors."""

from __future__ import annotations

import json

import numpy as np
import pytest

from teamenv.cli import main
from teamenv.match import MatchOptions
from teamenv.optimize.checkpoint import CheckpointStore
from teamenv.optimize.cmaes_loop import QuietReporter, load_result
from teamenv.optimize.heldout import bootstrap, held_out
from teamenv.optimize.tournament_fitness import TournamentFitness
from teamenv.tournament import ResultStore, TeamSpecError, parse_team_spec
from teamenv.tournament.overrides import write_team_override

TINY = ["--team-size", "3", "--half-time", "5", "--halves", "1", "--backend", "serial",
        "--no-progress"]


def _run(tmp_path, *extra: str) -> int:
    return main(["optimize", "full", "--against", "chaser", "--db", str(tmp_path / "o.sqlite"),
                 "--name", "tiny", "--params", "pressure_m,kick_goal_weight", "--popsize", "2",
                 "--export", str(tmp_path / "overrides" / "tiny.json"),
                 "--plot", str(tmp_path / "tiny.png"), *TINY, *extra])


def test_optimize_full_against_chaser_then_resume_and_use_the_override(tmp_path, monkeypatch,
                                                                        capsys):
    db = tmp_path / "o.sqlite"
    assert _run(tmp_path, "--generations", "1") == 0
    with ResultStore(db) as store:
        first_ids = {m.id for name in store.tournament_names()
                     for m in store.matches(store.get_tournament(name)[0])}
    assert len(first_ids) == 2 * 2  # 2 candidates x 1 opponent x 1 seed x both sides
    assert main(["optimize", "--resume", "--db", str(db), "--name", "tiny",
                 "--generations", "2", "--backend", "serial", "--no-progress",
                 "--export", str(tmp_path / "overrides" / "tiny.json"),
                 "--plot", str(tmp_path / "tiny.png")]) == 0
    result = load_result(db, "tiny")
    assert [g.generation for g in result.generations if g.told] == [0, 1]
    with ResultStore(db) as store, CheckpointStore(db) as checkpoints:
        names = sorted(store.tournament_names())
        assert names == [f"tiny/g{g:03d}/c{c:02d}" for g in (0, 1) for c in range(2)]
        all_ids = set()
        for g in (0, 1):
            seeds = []
            for c in range(2):
                tid, t = store.get_tournament(f"tiny/g{g:03d}/c{c:02d}")
                records = store.matches(tid)
                all_ids |= {m.id for m in records}
                seeds.append(sorted((m.seed, m.swapped) for m in records))
                # the stored fitness is what these matches say, from the candidate's side
                me = t.challenger.label
                gd = np.mean([(m.left_official - m.right_official) * (1 if m.left_team == me
                                                                      else -1)
                              for m in records])
                metric = checkpoints.match_metrics("territory", [m.id for m in records])
                terr = np.mean([metric[m.id] * (1 if m.left_team == me else -1)
                                for m in records])
                score = result.generations[g].scores[c]
                assert score["goal_difference"] == pytest.approx(gd)
                assert score["fitness"] == pytest.approx(gd + terr)
                assert -1 <= score["fine"] <= 1 and score["matches"] == 2
                assert t.seed == 7000 + g
            assert seeds[0] == seeds[1]  # common random numbers
    assert first_ids <= all_ids and len(all_ids) == 8  # resume kept generation 0's matches
    assert not list((tmp_path / "o.sqlite.replays").rglob("*.npz"))  # metrics kept, files gone
    assert (tmp_path / "tiny.png").stat().st_size > 0
    exported = json.loads((tmp_path / "overrides" / "tiny.json").read_text())
    assert exported["team"] == "full" and exported["config"] == result.recommended
    out = capsys.readouterr().out
    assert "2 generations, 8 matches" in out

    monkeypatch.chdir(tmp_path)  # full@tiny finds overrides/tiny.json
    spec = parse_team_spec("full@tiny")
    assert spec.name == "full" and spec.config_dict == result.recommended
    spec = parse_team_spec("full@tiny:pressure_m=3.5")
    assert spec.config_dict["pressure_m"] == 3.5
    assert main(["tournament", "run", "full@tiny", "chaser", "--db", "t.sqlite", "--games", "1",
                 "--team-size", "3", "--half-time", "2", "--halves", "1", "--backend",
                 "serial", "--no-progress"]) == 0
    with ResultStore(tmp_path / "t.sqlite") as store:
        records = store.matches(store.get_tournament(None)[0])
    report = held_out(records, parse_team_spec("full@tiny").label)
    gd = [(r.left_official - r.right_official) * (1 if r.left_team.startswith("full") else -1)
          for r in records]
    assert report.matches == 2 and report.seeds == 1 and report.territory is None
    assert report.goal_difference.mean == pytest.approx(np.mean(gd))


def test_bootstrap_resamples_whole_seeds():
    same = bootstrap([[1.0, -1.0], [1.0, -1.0]])
    assert (same.mean, same.low, same.high) == (0.0, 0.0, 0.0)
    spread = bootstrap([[2.0, 2.0], [0.0, 0.0], [1.0, 1.0]], resamples=500, seed=3)
    assert spread.mean == 1.0 and 0.0 <= spread.low < 1.0 < spread.high <= 2.0
    assert spread == bootstrap([[2.0, 2.0], [0.0, 0.0], [1.0, 1.0]], resamples=500, seed=3)


def test_override_files_bad_input(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(TeamSpecError, match="team override 'nothere': no such file"):
        parse_team_spec("full@nothere")
    write_team_override(tmp_path / "overrides" / "c.json", "chaser", {"all_chase": True})
    with pytest.raises(TeamSpecError, match="is for team 'chaser', not 'full'"):
        parse_team_spec("full@c")
    (tmp_path / "junk.json").write_text('{"config": {}}')
    with pytest.raises(TeamSpecError, match="not a team override file"):
        parse_team_spec("full@junk")
    assert parse_team_spec("chaser@c").config_dict == {"all_chase": True}


@pytest.mark.parametrize("args, message", [
    (["full", "--against", "chaser", "--params", "pressure"], "unknown field 'pressure'"),
    (["full", "--against", "chaser", "--params", "vote"], "'vote' declares no search range"),
    (["full", "--against", "chaser", "--bounds", "pressure_m=5:1"], "low must be < high"),
    (["full", "--against", "chaser", "--bounds", "kick_goal_weight=0:9:log"],
     "low must be > 0 on a log scale"),
    (["full", "--params", "pressure_m,ball_pull"], "--against"),
    (["full:pressure_m=2", "--against", "chaser", "--params", "pressure_m,ball_pull"],
     "fixed by the team spec and searched"),
    (["full", "--against", "nosuchteam", "--params", "pressure_m,ball_pull"], "nosuchteam"),
    (["--resume", "--name", "missing"], "no optimization run 'missing'"),
])
def test_bad_optimize_arguments_are_clear_errors(tmp_path, capsys, args, message):
    code = main(["optimize", *args, "--db", str(tmp_path / "e.sqlite"), *TINY])
    assert code == 2
    assert message in capsys.readouterr().err


def test_identical_candidates_play_once_and_goal_difference_alone_needs_no_replays(tmp_path):
    fitness = TournamentFitness(tmp_path / "d.sqlite", "dup", "full", ["chaser"],
                                options=MatchOptions(team_size=3, half_time_s=3.0, halves=1),
                                backend="serial", metric_weight=0.0)
    scores = fitness.evaluate(0, [{"pressure_m": 2.5}, {"pressure_m": 2.5}], QuietReporter())
    assert scores[0] == scores[1] and scores[0].fine is None and scores[0].matches == 2
    assert scores[0].fitness == scores[0].goal_difference
    with ResultStore(tmp_path / "d.sqlite") as store:
        assert store.tournament_names() == ["dup/g000/c00"]
        assert all(m.replay_path is None for m in store.matches(store.get_tournament(None)[0]))
