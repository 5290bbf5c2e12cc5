"""Seed 002's grid world: cell codes, one 32-bit integer per field part and code, lossy sharing."""

import math
from dataclasses import dataclass, field
from enum import IntEnum

import numpy as np

from comms.errors import DecodeError, EncodeError, SchemaError
from comms.profiles import ChannelProfile
from comms.schema import Int, Schema
from paramkit.checks import check_fields, in_range, positive

PART_BITS = 32  # MiteCom sends 32-bit integers: one bit per cell


class Cell(IntEnum):
    """Cell codes of seed 002 (0 nothing ... 7 ball)."""

    NOTHING = 0
    OWN_GOAL = 1
    ENEMY_GOAL = 2
    OWN_POSITION = 3
    TEAMMATE = 4
    OPPONENT = 5
    OBSTACLE = 6
    BALL = 7


CODES: tuple[int, ...] = tuple(int(c) for c in Cell if c != Cell.NOTHING)  # 1..7


@dataclass(frozen=True)
class GridSpec:
    """The grid over a `length` x `width` field (metres), `nx` x `ny` cells, origin cell at the
    centre spot (seed 002 uses odd counts so a cell sits on the centre spot and each goal).

    Cells are numbered row-major from the corner (-x, -y): index = iy * nx + ix; part p holds
    cells 32 p .. 32 p + 31. Default 17 x 15 = 255 cells in 8 parts, the seed's 8 integers
    per information type.
    """

    length: float = field(default=30.0, metadata=positive())
    width: float = field(default=20.0, metadata=positive())
    nx: int = field(default=17, metadata=in_range(1))
    ny: int = field(default=15, metadata=in_range(1))
    n_cells: int = field(init=False)
    n_parts: int = field(init=False)

    def __post_init__(self) -> None:
        check_fields(self, SchemaError)
        object.__setattr__(self, "n_cells", self.nx * self.ny)
        object.__setattr__(self, "n_parts", math.ceil(self.nx * self.ny / PART_BITS))

    def cell_of(self, x: float, y: float) -> tuple[int, int]:
        """(ix, iy) of the cell holding field point (x, y) m (seed eqs. 15-16, clipped)."""
        cx = round(x / self.length * self.nx) + self.nx // 2
        cy = round(y / self.width * self.ny) + self.ny // 2
        return min(max(cx, 0), self.nx - 1), min(max(cy, 0), self.ny - 1)

    def centre_of(self, ix: int, iy: int) -> tuple[float, float]:
        """Field coordinates (m) of the centre of cell (ix, iy)."""
        return (
            (ix - self.nx // 2) * self.length / self.nx,
            (iy - self.ny // 2) * self.width / self.ny,
        )

    def empty(self) -> np.ndarray:
        """An all-NOTHING grid, uint8 (ny, nx)."""
        return np.zeros((self.ny, self.nx), dtype=np.uint8)


#: The seed's grid on the SimSpark field: 17 x 15 cells, 8 parts of 32.
DEFAULT_GRID = GridSpec()


def grid_to_ints(grid: np.ndarray, spec: GridSpec) -> np.ndarray:
    """Pack a (ny, nx) grid of cell codes into uint32 words, shape (n_parts, 7).

    word[p, c - 1] has bit j set when cell 32 p + j holds code c.
    """
    g = np.asarray(grid)
    if g.shape != (spec.ny, spec.nx):
        raise EncodeError(f"grid shape {g.shape} does not match spec ({spec.ny}, {spec.nx})")
    if g.size and (g.min() < 0 or g.max() > 7):
        raise EncodeError(f"grid holds codes outside 0..7: {np.unique(g).tolist()}")
    flat = np.zeros(spec.n_parts * PART_BITS, dtype=np.int64)
    flat[: spec.n_cells] = g.reshape(-1)
    cells = flat.reshape(spec.n_parts, PART_BITS)
    weights = np.left_shift(np.uint64(1), np.arange(PART_BITS, dtype=np.uint64))
    out = np.empty((spec.n_parts, len(CODES)), dtype=np.uint32)
    for k, code in enumerate(CODES):
        out[:, k] = ((cells == code).astype(np.uint64) * weights).sum(axis=1)
    return out


def ints_to_grid(words: np.ndarray, spec: GridSpec) -> np.ndarray:
    """Inverse of `grid_to_ints` (a cell claimed by several codes keeps the highest)."""
    w = np.asarray(words, dtype=np.uint64)
    if w.shape != (spec.n_parts, len(CODES)):
        raise DecodeError(f"words shape {w.shape}, expected ({spec.n_parts}, {len(CODES)})")
    bits = (w[:, :, None] >> np.arange(PART_BITS, dtype=np.uint64)) & np.uint64(1)  # (P, 7, 32)
    flat = np.zeros((spec.n_parts, PART_BITS), dtype=np.uint8)
    for k, code in enumerate(CODES):
        flat[bits[:, k, :] == 1] = code
    return flat.reshape(-1)[: spec.n_cells].reshape(spec.ny, spec.nx)


def grid_part_schema(
    spec: GridSpec = DEFAULT_GRID, channel: "str | ChannelProfile" = "simspark", check_bits: int = 6
) -> Schema:
    """One grid-world word per message: part (0..n_parts-1), code (1..7), the 32-bit word.

    Default spec: 3 + 3 + 32 + 6 check = 44 bits: base64 8 chars on `simspark`, fits `mj`.
    """
    return Schema(
        "grid_part",
        [
            Int("part", 0, spec.n_parts - 1),
            Int("code", 1, len(CODES)),
            Int("word", 0, (1 << PART_BITS) - 1),
        ],
        channel=channel,
        check_bits=check_bits,
    )


class GridWorld:
    """A grid-world model shared word by word over a lossy channel.

    `messages()` gives one text per (part, code) word (optionally only non-zero words);
    `apply(text)` merges one received word: in that part, cells marked with that code become
    that code, and cells that held it but are unmarked become NOTHING. A lost message leaves
    only its part and code stale.
    """

    def __init__(
        self, spec: GridSpec = DEFAULT_GRID, channel: "str | ChannelProfile" = "simspark"
    ) -> None:
        self.spec = spec
        self.schema = grid_part_schema(spec, channel)
        self.grid = spec.empty()

    def messages(self, nonzero_only: bool = False) -> list[str]:
        """Texts for every word (n_parts * 7), or only the words with a bit set."""
        words = grid_to_ints(self.grid, self.spec)
        enc = self.schema.encode
        return [
            enc({"part": p, "code": code, "word": int(words[p, k])})
            for p in range(self.spec.n_parts)
            for k, code in enumerate(CODES)
            if not nonzero_only or words[p, k]
        ]

    def apply(self, text: str) -> None:
        """Merge one received word into `grid` (raises DecodeError on a corrupt text)."""
        rec = self.schema.decode(text)
        flat = np.zeros(self.spec.n_parts * PART_BITS, dtype=np.uint8)
        flat[: self.spec.n_cells] = self.grid.reshape(-1)
        part = flat[rec.part * PART_BITS : (rec.part + 1) * PART_BITS]
        marked = ((rec.word >> np.arange(PART_BITS)) & 1).astype(bool)
        part[(part == rec.code) & ~marked] = Cell.NOTHING
        part[marked] = rec.code
        self.grid = flat[: self.spec.n_cells].reshape(self.spec.ny, self.spec.nx)


def grid_cost(spec: GridSpec = DEFAULT_GRID, channel: str = "simspark") -> dict:
    """Bits and messages the grid world spends for a full picture, for the README comparison."""
    schema = grid_part_schema(spec, channel)
    words = spec.n_parts * len(CODES)
    return {
        "cells": spec.n_cells,
        "parts": spec.n_parts,
        "words": words,
        "payload_bits": words * PART_BITS,
        "message_bits": schema.bits,
        "messages_full": words,
        "bits_full": words * schema.bits,
    }
