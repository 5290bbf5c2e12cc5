"""Plots of tournament results (matplotlib, Agg, no pyplot state): ratings with intervals and
the goal-difference matrix."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np


def _figure(width_in: float, height_in: float) -> Any:
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width_in, height_in), layout="constrained")
    FigureCanvasAgg(fig)
    return fig


def plot_ratings(ratings: Any, path: str | Path) -> Path:
    """Horizontal error bars of Elo and Bradley–Terry ratings (points) with their intervals."""
    teams = list(ratings.bradley_terry)[::-1]
    y = np.arange(len(teams))
    fig = _figure(8.0, 1.2 + 0.45 * len(teams))
    ax = fig.add_subplot()
    for offset, table, label in ((0.15, ratings.bradley_terry, "Bradley–Terry"),
                                 (-0.15, ratings.elo, "Elo")):
        mid = np.array([table[t].rating for t in teams])
        low = np.array([table[t].low for t in teams])
        high = np.array([table[t].high for t in teams])
        err = np.vstack([np.maximum(mid - low, 0), np.maximum(high - mid, 0)])
        ax.errorbar(mid, y + offset, xerr=err, fmt="o", capsize=3, label=label)
    ax.set_yticks(y, teams)
    ax.set_xlabel(f"rating (Elo points; {ratings.confidence:.0%} bootstrap interval, "
                  f"{ratings.n_bootstrap} resamples of {ratings.n_games} matches)")
    ax.axvline(1500.0, color="grey", lw=0.5)
    ax.legend(loc="best")
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=120)
    return path


def plot_goal_difference(teams: Sequence[str], matrix: np.ndarray, path: str | Path) -> Path:
    """Heat map of the mean goal difference per match, row team against column team."""
    n = len(teams)
    fig = _figure(2.0 + 0.8 * n, 1.5 + 0.7 * n)
    ax = fig.add_subplot()
    finite = np.abs(matrix[np.isfinite(matrix)])
    vmax = max(1.0, float(finite.max())) if finite.size else 1.0
    image = ax.imshow(np.ma.masked_invalid(matrix), cmap="RdBu", vmin=-vmax, vmax=vmax)
    for i in range(n):
        for j in range(n):
            if np.isfinite(matrix[i, j]):
                ax.text(j, i, f"{matrix[i, j]:+.1f}", ha="center", va="center", fontsize=8)
    ax.set_xticks(range(n), teams, rotation=45, ha="right")
    ax.set_yticks(range(n), teams)
    ax.set_xlabel("opponent")
    ax.set_title("mean goal difference per match (row vs column)")
    fig.colorbar(image, ax=ax, label="goals")
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=120)
    return path
