"""Shared builders for the strategy tests: small formations and hypothesis strategies."""

from __future__ import annotations

import numpy as np
from hypothesis import strategies as st

from strategy.positioning.formation import Formation, FormationError, Role


def roles(n: int) -> list[Role]:
    """A goalie and n - 1 midfielders."""
    return [Role("Goalie", "G")] + [Role(f"P{i + 1}", "MF") for i in range(1, n)]


def grid_formation(n: int = 4, field: str = "simspark", seed: int = 0,
                   outside: str = "nearest") -> Formation:
    """A formation on a 3 x 3 grid of ball samples (simspark-sized) with random positions."""
    rng = np.random.default_rng(seed)
    ball = np.array([[x, y] for x in (-12.0, 0.0, 12.0) for y in (-8.0, 0.0, 8.0)])
    # jitter so the Delaunay triangulation is unique (no four co-circular samples)
    ball += rng.uniform(-1.0, 1.0, ball.shape)
    pos = rng.uniform([-14, -9], [14, 9], (len(ball), n, 2))
    return Formation(roles(n), ball, pos, field=field, name="grid", outside=outside)


@st.composite
def formations(draw, max_samples: int = 12, max_players: int = 5) -> Formation:
    """Random valid formations on the simspark pitch (hypothesis)."""
    s = draw(st.integers(3, max_samples))
    n = draw(st.integers(1, max_players))
    seed = draw(st.integers(0, 2**32 - 1))
    rng = np.random.default_rng(seed)
    ball = rng.uniform([-15, -10], [15, 10], (s, 2))
    pos = rng.uniform([-15, -10], [15, 10], (s, n, 2))
    try:
        return Formation(roles(n), ball, pos, field="simspark", name="random")
    except FormationError:
        from hypothesis import assume

        assume(False)
        raise  # pragma: no cover
