"""The self-play league's learners and demo script at their --smoke settings: the CleanRL
example plugs into the league as a learner, and the demo run writes its curve, record and
evaluation report."""

from __future__ import annotations

import json

import pytest

from tests.benchmark_scripts import load_benchmark
from tests.examples.test_examples import run_example

pytestmark = pytest.mark.rl


def test_the_cleanrl_example_is_a_league_learner(tmp_path):
    pytest.importorskip("torch", reason="needs the rl extra: pip install -e '.[rl]'")
    stdout = run_example("selfplay_cleanrl.py", "--out", str(tmp_path))
    assert "3 generation(s) rated" in stdout
    assert sorted(p.name for p in (tmp_path / "snapshots").iterdir()) == [
        "gen-0000.npz", "gen-0001.npz", "gen-0002.npz"]
    assert (tmp_path / "learner" / "gen-0002" / "cleanrl.pt").is_file()


def test_the_demo_run_writes_its_curve_record_and_evaluation(tmp_path):
    pytest.importorskip("stable_baselines3", reason="needs the rl extra: pip install -e '.[rl]'")
    demo = load_benchmark("selfplay_league")
    demo.main(["--smoke", "--run-dir", str(tmp_path), "--evaluate", "2",
               "--eval-half-time", "5"])
    assert (tmp_path / "curve.png").stat().st_size > 10_000
    record = json.loads((tmp_path / "league.json").read_text())
    assert record["generations_rated"] == 2
    assert [g["snapshot"] for g in record["generations"]] == ["gen-0000", "gen-0001",
                                                               "gen-0002"]
    assert record["rating_tournament_seeds_in_evaluation_range"] == []
    report = json.loads((tmp_path / "evaluation.json").read_text())
    for result in (report["opponents"]["chaser"], report["opponents"]["full"],
                   report["untrained"]["chaser"]):
        assert result["matches"] == 2 and len(result["per_seed"]) == 2
        assert [row["seed"] for row in result["per_seed"]] == [100_000, 100_001]
        low, high = result["goal_difference_per_match"]["ci95"]
        assert low <= result["goal_difference_per_match"]["mean"] <= high
    assert (tmp_path / "best.npz").is_file()


def test_the_options_demo_clones_full_and_its_snapshots_play_full_options(tmp_path):
    pytest.importorskip("stable_baselines3", reason="needs the rl extra: pip install -e '.[rl]'")
    demo = load_benchmark("selfplay_league")
    demo.main(["--smoke", "--learner", "options", "--run-dir", str(tmp_path), "--evaluate",
               "1", "--eval-half-time", "3"])
    record = json.loads((tmp_path / "league.json").read_text())
    assert record["generations_rated"] == 2
    assert record["config"]["training"]["option_team"] == "full_options"
    clone = json.loads((tmp_path / "learner" / "gen-0001" / "imitation.json").read_text())
    assert [r["played_by"] for r in clone["clone_log"]] == ["teacher", "network"]
    assert 0.0 <= clone["clone_log"][1]["option_disagreement_when_played"] <= 1.0
    report = json.loads((tmp_path / "evaluation.json").read_text())
    assert report["team_spec"] == "teamenv.selfplay.option_policy_team:OptionPolicyTeam"
    assert report["teacher"]["chaser"]["snapshot"] == "full_options"
