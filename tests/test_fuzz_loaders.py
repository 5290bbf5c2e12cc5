"""The file loaders fed corrupted files (benchmarks/fuzz_loaders.py's seeded mutator, a few
hundred per kind): every load ends in the loader's own error naming the file, or loads; a
replay (checksummed) never loads other content. The 10^4-per-kind run is the benchmark's."""

from __future__ import annotations

import numpy as np
import pytest

from tests.benchmark_scripts import load_benchmark

fl = load_benchmark("fuzz_loaders")

FILES_PER_KIND = 300


def test_mutator_is_seeded_and_always_changes_the_data():
    data = bytes(range(256)) * 4
    first = [fl.mutate(data, np.random.default_rng(5)) for _ in range(3)]
    again = [fl.mutate(data, np.random.default_rng(5)) for _ in range(3)]
    assert first == again
    rng = np.random.default_rng(1)
    outs = [fl.mutate(data, rng) for _ in range(200)]
    assert all(out != data for out in outs)
    assert len({len(out) for out in outs}) > 10  # truncations, splices, deletions


@pytest.mark.parametrize("kind_name", sorted(fl.kinds()))
def test_corrupted_files_end_in_the_loaders_own_errors(tmp_path, kind_name):
    kind = fl.kinds()[kind_name]
    tally = fl.fuzz(kind, FILES_PER_KIND, seed=2024, directory=tmp_path, keep_examples=3)
    counts = tally.counts
    assert counts["foreign"] == 0, tally.examples["foreign"]
    assert counts["unnamed"] == 0, tally.examples["unnamed"]
    if kind.changed_fails:
        assert counts["changed"] == 0, tally.examples["changed"]
    assert counts["error"] > FILES_PER_KIND // 2
    assert sum(counts.values()) == FILES_PER_KIND


@pytest.mark.parametrize("kind_name", ["profile", "formation", "agent2d-json", "agent2d-csv",
                                       "agent2d-v3"])
def test_a_byte_that_is_not_utf8_names_file_and_line(tmp_path, kind_name):
    kind = fl.kinds()[kind_name]
    original = kind.make(tmp_path)
    lines = original.read_bytes().split(b"\n")
    lines[4] = lines[4] + b"\xe9"  # a Latin-1 e-acute on line 5
    bad = tmp_path / f"latin1{original.suffix}"
    bad.write_bytes(b"\n".join(lines))
    with pytest.raises(kind.errors, match=r"latin1.*not UTF-8 text: byte 0xe9 at line 5"):
        kind.load(bad)
