"""The committed 5 v 5 learned team of the options league run (examples/policies/
selfplay_5v5_options.npz: a network that chooses full_options' open-play options, numpy
only) replays its committed evaluation against chaser bit for bit on an evaluation seed
where it won (the first; one full-length match keeps CI's time): the same score, goal times and sides, and cycles as the per-seed report
(benchmarks/results/selfplay_options_evaluation.json). Full-length matches (2 x 300 s):
slow."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from teamenv.match import MatchOptions
from teamenv.policy_team.mlp_file import option_team
from teamenv.selfplay.egocentric_team import egocentric_slots
from teamenv.selfplay.option_policy_team import OPTION_POLICY_SPEC_NAME
from tests.benchmark_scripts import load_benchmark

selfplay_league = load_benchmark("selfplay_league")

ROOT = Path(__file__).resolve().parents[3]
POLICY = ROOT / "examples" / "policies" / "selfplay_5v5_options.npz"
REPORT = ROOT / "benchmarks" / "results" / "selfplay_options_evaluation.json"
#: How many of the evaluation's won matches against chaser the test replays.
REPLAYED_WINS = 1


def _report() -> dict:
    return json.loads(REPORT.read_text())


def test_the_report_describes_the_committed_file():
    report = _report()
    assert report["team_spec"] == OPTION_POLICY_SPEC_NAME
    assert Path(report["policy_file"]).name == POLICY.name
    assert option_team(POLICY) == ("full_options", 3)
    assert egocentric_slots(POLICY) == (4, 5)
    chaser = report["opponents"]["chaser"]
    assert chaser["matches"] == len(chaser["per_seed"]) >= 40
    assert all(100_000 <= row["seed"] < 200_000 for row in chaser["per_seed"])  # evaluation
    options = MatchOptions.from_dict(report["options"])
    assert (options.field, options.team_size, options.half_time_s) == ("mj7v7", 5, 300.0)


def _won(report: dict) -> list[dict]:
    rows = report["opponents"]["chaser"]["per_seed"]
    return [row for row in rows if row["goals"][0] > row["goals"][1]][:REPLAYED_WINS]


@pytest.mark.slow
@pytest.mark.parametrize("k", range(REPLAYED_WINS))
def test_the_committed_team_replays_a_won_evaluation_match_against_chaser(k):
    report = _report()
    game = _won(report)[k]
    replayed = selfplay_league.evaluation_match(
        (OPTION_POLICY_SPEC_NAME, {"path": str(POLICY)}, "chaser", game["seed"],
         MatchOptions.from_dict(report["options"])))
    assert replayed["forfeit"] == "" and game["forfeit"] == ""
    assert replayed == game
    assert replayed["goals"][0] > replayed["goals"][1]
