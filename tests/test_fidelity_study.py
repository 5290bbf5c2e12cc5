"""benchmarks/fidelity_study.py's analysis on a tiny stored run (three strategies, 2 v 2, 6 s):
results JSON, ranks, the agreement table, the figure and the docs page."""

from __future__ import annotations

import json
import math
import shutil
from pathlib import Path

import pytest

from tests.benchmark_scripts import load_benchmark

ROOT = Path(__file__).resolve().parents[1]
study = load_benchmark("fidelity_study")
STORED = ROOT / "tests" / "data" / "fidelity_study_tiny"


@pytest.fixture
def run(tmp_path):
    out = tmp_path / "run"
    shutil.copytree(STORED, out)
    return out


def test_analysis_of_a_stored_run(run, tmp_path):
    figure, page = tmp_path / "fig.png", tmp_path / "page.md"
    results = study.analyse(run, bootstrap=100, seed=0, figure=figure, page=page)
    assert results["league_matches"] == 6
    on_disk = json.loads((run / "results.json").read_text())
    assert on_disk["ranks"] == results["ranks"]
    for world in ("league", "teamenv", "teamenv calibrated"):
        for metric, table in results["ranking"][world].items():
            r = results["ranks"][world][metric]
            assert set(r) == {"full", "chaser", "static"}
            best = max(table, key=table.get)
            assert r[best] == min(r.values())          # rank 1 goes to the best score
            assert sum(r.values()) == pytest.approx(6)  # ties share their mean rank
    # every league match of the tiny run was 0-0: the points table is a tie, so the
    # headline ranking falls back to a finer one that separates the teams
    assert len(set(results["ranking"]["league"]["points"].values())) == 1
    assert study.headline_metric(results) != "points"
    assert math.isnan(results["agreement"]["teamenv vs league, points"]["rho"])
    assert figure.stat().st_size > 5000
    text = page.read_text()
    assert "Spearman rho" in text and "`full`" in text and "fig.png" in text
    assert text.count("\n| teamenv") >= 4


def test_stat_ratios_flag_the_25_percent_band():
    ratios = study.stat_ratios({"league": {"goals": 1.0, "kicks": 4.0, "falls": 0.0},
                                "teamenv": {"goals": 1.2, "kicks": 6.0, "falls": 0.0}})
    assert ratios["teamenv"]["goals"]["within_25pct"]
    assert not ratios["teamenv"]["kicks"]["within_25pct"]
    assert ratios["teamenv"]["falls"]["within_25pct"]        # 0 against 0
    assert "ball_progress_m" not in ratios["teamenv"]


def test_study_refuses_a_seed_outside_the_evaluation_range(tmp_path):
    with pytest.raises(SystemExit):
        study.main(["--out", str(tmp_path), "--seed", "5", "--analyse-only"])


def test_a_run_under_way_is_compared_on_the_pairings_every_world_has_played(run, tmp_path):
    """Only the league's first four matches (full's) are stored: with ``common_pairings`` the
    calibrated world is compared on the same four pairings, and the world not asked for is
    left out."""
    import sqlite3

    with sqlite3.connect(run / "league.sqlite") as db:
        db.execute("DELETE FROM matches WHERE left_team != 'full' AND right_team != 'full'")
    results = study.analyse(run, bootstrap=50, seed=0, figure=None, page=None,
                            worlds=("teamenv_calibrated", "league"), common_pairings=True)
    assert results["league_matches"] == 4
    assert set(results["stats"]) == {"teamenv calibrated", "league"}
    assert results["stats"]["teamenv calibrated"]["matches"] == 4
    assert not any(key.startswith("teamenv vs") for key in results["agreement"])
    everything = study.analyse(run, bootstrap=50, seed=0, figure=None, page=None)
    assert everything["stats"]["teamenv calibrated"]["matches"] == 6


def test_a_world_is_not_resumed_under_another_profile(tmp_path):
    """The profile each teamenv world plays with is recorded; a resume under a changed
    profile file (e.g. a recalibrated t1_league) or an unrecorded database stops, named."""
    out = tmp_path / "run"
    out.mkdir()
    study.check_profile(out, "teamenv_calibrated", "t1_league")
    recorded = json.loads((out / "profiles.json").read_text())
    assert recorded["teamenv_calibrated"] == {"profile": "t1_league",
                                              "sha256": study.profile_digest("t1_league")}
    (out / "teamenv_calibrated.sqlite").write_bytes(b"")
    study.check_profile(out, "teamenv_calibrated", "t1_league")      # the same: resumes
    with pytest.raises(SystemExit, match="played with profile t1_league .* t1_mj"):
        study.check_profile(out, "teamenv_calibrated", "t1_mj")
    recorded["teamenv_calibrated"]["sha256"] = "0" * 64              # the file changed since
    (out / "profiles.json").write_text(json.dumps(recorded))
    with pytest.raises(SystemExit, match="move that database away"):
        study.check_profile(out, "teamenv_calibrated", "t1_league")
    (out / "teamenv.sqlite").write_bytes(b"")
    with pytest.raises(SystemExit, match="has no profile record"):
        study.check_profile(out, "teamenv", "t1_mj")
