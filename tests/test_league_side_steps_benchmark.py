"""benchmarks/league_side_steps.py: paired rows per seed, paired intervals."""

import json
import math

from tests.benchmark_scripts import load_benchmark

side_steps = load_benchmark("league_side_steps")


def test_a_short_teamenv_run_writes_paired_rows(tmp_path):
    out = tmp_path / "rows.json"
    side_steps.main(["--world", "teamenv", "--seeds", "5:7", "--seconds", "4",
                     "--team-size", "3", "--json", str(out)])
    rows = json.loads(out.read_text())["rows"]
    assert [(r["seed"], r["one_sided"]) for r in rows] == [
        (5, False), (5, True), (6, False), (6, True)]
    assert all(r["kicks"] >= 0 and r["falls"] >= 0 and len(r["score"]) == 2 for r in rows)


def test_paired_differences_and_their_interval():
    rows = [{"seed": s, "one_sided": o, "kicks": k, "falls": 0, "score": [g, 0]}
            for s, o, k, g in [(1, False, 2, 0), (1, True, 4, 1), (2, False, 1, 0),
                               (2, True, 2, 0), (3, False, 0, 0), (3, True, 3, 1)]]
    mean, low, high = side_steps.paired(rows, "kicks")
    assert mean == 2.0 and low < 2.0 < high
    assert side_steps.paired(rows, "goals")[0] == 2 / 3
    assert math.isnan(side_steps.paired(rows[:2], "falls")[1])  # one pair: no interval
