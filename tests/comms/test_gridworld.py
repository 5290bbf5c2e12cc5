"""Tests of seed 002's grid world: cell codes, 32-bit words, lossy sharing, cost comparison."""

import numpy as np
import pytest

from comms import DecodeError, EncodeError
from comms.gridworld import (
    CODES,
    Cell,
    GridSpec,
    GridWorld,
    grid_cost,
    grid_part_schema,
    grid_to_ints,
    ints_to_grid,
)
from comms.messages import TEAM_STATE
from comms.testing import check_roundtrip


def test_codes():
    assert [int(c) for c in Cell] == list(range(8))
    assert Cell.BALL == 7 and Cell.NOTHING == 0 and CODES == tuple(range(1, 8))


def test_spec_and_cells():
    s = GridSpec()
    assert (s.nx, s.ny, s.n_cells, s.n_parts) == (17, 15, 255, 8)
    assert s.cell_of(0.0, 0.0) == (8, 7)  # origin cell on the centre spot
    assert s.cell_of(-15.0, 0.0) == (0, 7) and s.cell_of(15.0, 10.0) == (16, 14)
    assert s.cell_of(99.0, -99.0) == (16, 0)
    assert s.centre_of(8, 7) == (0.0, 0.0)


@pytest.mark.parametrize("seed", range(5))
def test_words_roundtrip(seed):
    spec = GridSpec()
    g = np.random.default_rng(seed).integers(0, 8, size=(spec.ny, spec.nx)).astype(np.uint8)
    w = grid_to_ints(g, spec)
    assert w.shape == (8, 7) and w.dtype == np.uint32
    assert (ints_to_grid(w, spec) == g).all()


def test_single_cell_bit():
    spec = GridSpec()
    g = spec.empty()
    g[0, 1] = Cell.BALL  # cell index 1 -> part 0, bit 1
    g[14, 16] = Cell.OPPONENT  # cell 254 -> part 7, bit 30
    w = grid_to_ints(g, spec)
    assert w[0, Cell.BALL - 1] == 2 and w[7, Cell.OPPONENT - 1] == 1 << 30
    assert w.sum() == 2 + (1 << 30)
    with pytest.raises(EncodeError):
        grid_to_ints(np.full((spec.ny, spec.nx), 8), spec)
    with pytest.raises(DecodeError):
        ints_to_grid(np.zeros((3, 7)), spec)


def test_lossy_sharing():
    rng = np.random.default_rng(0)
    a, b = GridWorld(), GridWorld()
    a.grid = rng.integers(0, 8, size=a.grid.shape).astype(np.uint8)
    msgs = a.messages()
    assert len(msgs) == 56
    lost = set(rng.choice(len(msgs), size=10, replace=False).tolist())
    for k, t in enumerate(msgs):
        if k not in lost:
            b.apply(t)
    # only the lost (part, code) words differ
    spec = a.spec
    flat_a = np.zeros(spec.n_parts * 32, np.uint8)
    flat_b = np.zeros(spec.n_parts * 32, np.uint8)
    flat_a[: spec.n_cells] = a.grid.reshape(-1)
    flat_b[: spec.n_cells] = b.grid.reshape(-1)
    lost_pc = {(k // 7, CODES[k % 7]) for k in lost}
    for i in np.nonzero(flat_a != flat_b)[0]:
        assert (i // 32, int(flat_a[i])) in lost_pc
    for t in msgs:
        b.apply(t)
    assert (b.grid == a.grid).all()
    with pytest.raises(DecodeError):
        b.apply("~~~~~~~~")


def test_part_schema_fits_both_channels():
    s = grid_part_schema()
    assert s.bits == 44 and s.chars == 8
    check_roundtrip(s, n=50)
    check_roundtrip(grid_part_schema(channel="mj"), n=50)


def test_cost_comparison():
    c = grid_cost()
    assert c["words"] == 56 and c["payload_bits"] == 56 * 32
    assert c["bits_full"] > 20 * TEAM_STATE.bits
