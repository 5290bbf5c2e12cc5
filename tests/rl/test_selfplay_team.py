"""The self-play league's committed 3 v 3 snapshot (examples/policies/selfplay_3v3.npz, numpy
only) replays its committed evaluation against chaser bit for bit on the first seeds, as the
report says it played them (benchmarks/results/selfplay_evaluation.json)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from teamenv.match import MatchOptions
from teamenv.selfplay.egocentric_team import TEAM_SPEC_NAME, egocentric_slots
from tests.benchmark_scripts import load_benchmark

selfplay_league = load_benchmark("selfplay_league")

ROOT = Path(__file__).resolve().parents[2]
POLICY = ROOT / "examples" / "policies" / "selfplay_3v3.npz"
REPORT = ROOT / "benchmarks" / "results" / "selfplay_evaluation.json"


@pytest.mark.parametrize("row", [0, 1])
def test_the_committed_snapshot_replays_its_evaluation(row):
    report = json.loads(REPORT.read_text())
    assert report["team_spec"] == TEAM_SPEC_NAME
    assert egocentric_slots(POLICY) == (2, 3)
    options = MatchOptions.from_dict(report["options"])
    game = report["opponents"]["chaser"]["per_seed"][row]
    # the evaluation's own match function; this report stored the score and side only
    replayed = selfplay_league.evaluation_match(
        (TEAM_SPEC_NAME, {"path": str(POLICY)}, "chaser", game["seed"], options))
    assert {key: replayed[key] for key in game} == game
    assert replayed["forfeit"] == ""
