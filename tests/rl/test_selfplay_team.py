"""The self-play league's committed 3 v 3 snapshot (examples/policies/selfplay_3v3.npz, numpy
only) replays its committed evaluation against chaser bit for bit on the first seeds, as the
report says it played them (benchmarks/results/selfplay_evaluation.json)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from teamenv.match import MatchOptions, play_match
from teamenv.selfplay.egocentric_team import TEAM_SPEC_NAME, egocentric_slots

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
    config = {"path": str(POLICY)}
    if game["snapshot_left"]:
        result = play_match(TEAM_SPEC_NAME, "chaser", game["seed"], options,
                            left_config=config)
        score = list(result.score)
    else:
        result = play_match("chaser", TEAM_SPEC_NAME, game["seed"], options,
                            right_config=config)
        score = [result.score[1], result.score[0]]
    assert score == game["goals"]
    assert result.forfeit is None
