"""Role-assignment and vote plots draw one arrow per player and the vote matrix."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from strategy.positioning.roles import assign_roles, tally_votes  # noqa: E402
from strategy.positioning.roles.plot import plot_assignment, plot_votes  # noqa: E402


def test_plot_assignment_and_votes(tmp_path):
    rng = np.random.default_rng(0)
    players, positions = rng.uniform(-10, 10, (5, 2)), rng.uniform(-10, 10, (5, 2))
    a = assign_roles(players, positions)
    fig, (ax1, ax2) = plt.subplots(1, 2)
    plot_assignment(players, positions, a, ax=ax1, field_size=(30.0, 20.0))
    assert len(ax1.texts) >= 5  # arrows and numbers
    assert "longest walk" in ax1.get_title()
    vectors = [a.position_of, a.position_of, np.array([0, 2, 1, 3, 4])]
    plot_votes(vectors, tally_votes(vectors), ax=ax2)
    assert ax2.images
    fig.savefig(tmp_path / "roles.png")
    plt.close(fig)
