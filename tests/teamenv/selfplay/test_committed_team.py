"""The committed 3 v 3 team of the imitation league run (examples/policies/
selfplay_3v3_imitation.npz, numpy only, no torch needed) replays its committed evaluation
against chaser bit for bit on a few evaluation seeds: the same score and the same match
statistics (the goals' times and sides, the cycles played) as the per-seed report (benchmarks/results/
selfplay_imitation_evaluation.json) stored."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from teamenv.match import MatchOptions
from teamenv.selfplay.egocentric_team import TEAM_SPEC_NAME, egocentric_slots
from tests.benchmark_scripts import load_benchmark

selfplay_league = load_benchmark("selfplay_league")

ROOT = Path(__file__).resolve().parents[3]
POLICY = ROOT / "examples" / "policies" / "selfplay_3v3_imitation.npz"
REPORT = ROOT / "benchmarks" / "results" / "selfplay_imitation_evaluation.json"
#: Rows of the report's per-seed list against chaser that the test replays.
ROWS = (0, 1)


def _report() -> dict:
    return json.loads(REPORT.read_text())


def test_the_report_describes_the_committed_file():
    report = _report()
    assert report["team_spec"] == TEAM_SPEC_NAME
    assert Path(report["policy_file"]).name == POLICY.name
    assert egocentric_slots(POLICY) == (2, 3)
    chaser = report["opponents"]["chaser"]
    assert chaser["matches"] == len(chaser["per_seed"]) >= 40
    assert all(100_000 <= row["seed"] < 200_000 for row in chaser["per_seed"])  # evaluation


@pytest.mark.parametrize("row", ROWS)
def test_the_committed_team_replays_its_evaluation_against_chaser(row):
    report = _report()
    options = MatchOptions.from_dict(report["options"])
    game = report["opponents"]["chaser"]["per_seed"][row]
    # the evaluation's own match function: score, goal times and sides, cycles, forfeit
    replayed = selfplay_league.evaluation_match(
        (TEAM_SPEC_NAME, {"path": str(POLICY)}, "chaser", game["seed"], options))
    assert replayed["forfeit"] == "" and game["forfeit"] == ""
    assert replayed == game
