"""Plots of role assignment (who walks where) and of a vote tally (matplotlib)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from strategy.positioning.roles.assignment import Assignment
from strategy.positioning.roles.voting import vote_matrix

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes


def plot_assignment(
    players: ArrayLike,
    positions: ArrayLike,
    assignment: Assignment,
    *,
    ax: Axes | None = None,
    field_size: tuple[float, float] | None = None,
    colour: str = "#1f5fbf",
    label: str = "assignment",
    title: str | None = None,
) -> Axes:
    """Draw players (dots, numbered), positions (crosses) and an arrow per player to its position.

    Args:
        players: (N, 2) player positions, metres; positions: (N, 2) formation positions.
        assignment: from ``assign_roles``; its longest walk is drawn thicker.
        ax: axes to draw on (default: a new figure).
        field_size: (length, width) in metres to draw the pitch outline (optional).
        colour, label: arrow colour and legend label (draw two assignments on one axes to
            compare them, e.g. MMD+MSD² and greedy).
        title: axes title (default: the longest walk and the sum of squares).
    """
    import matplotlib.pyplot as plt
    from matplotlib.patches import Rectangle

    p = np.asarray(players, dtype=np.float64)
    q = np.asarray(positions, dtype=np.float64)
    if ax is None:
        _, ax = plt.subplots(figsize=(7, 5))
    if field_size is not None:
        length, width = field_size
        ax.add_patch(Rectangle((-length / 2, -width / 2), length, width, facecolor="#e8f3e8",
                               edgecolor="#4a7a4a", zorder=0))
    walks = np.hypot(*(q[assignment.position_of] - p).T)
    longest = int(np.argmax(walks))
    for i, (a, k) in enumerate(zip(p, assignment.position_of, strict=True)):
        b = q[k]
        ax.annotate("", xy=b, xytext=a, zorder=3,
                    arrowprops={"arrowstyle": "->", "color": colour,
                                "lw": 2.6 if i == longest else 1.2})
    ax.plot([], [], color=colour, label=f"{label}: longest {assignment.max_distance:.1f} m")
    ax.scatter(p[:, 0], p[:, 1], s=50, color="#333333", zorder=4)
    ax.scatter(q[:, 0], q[:, 1], s=60, marker="x", color="#c8323c", zorder=4)
    for i, (x, y) in enumerate(p):
        ax.annotate(str(i + 1), (x, y), textcoords="offset points", xytext=(-10, 4), fontsize=8)
    ax.set_aspect("equal")
    ax.legend(loc="lower left", fontsize=8)
    ax.set_title(title if title is not None else
                 f"longest walk {assignment.max_distance:.2f} m, "
                 f"sum of squares {assignment.sum_squared:.1f} m²")
    return ax


def plot_votes(vectors: ArrayLike, result: ArrayLike, *, ax: Axes | None = None,
               title: str | None = None) -> Axes:
    """Heat map of ``votes[player, position]`` from K role vectors, the adopted one circled."""
    import matplotlib.pyplot as plt

    v = np.asarray(vectors)
    n = v.shape[1]
    votes = vote_matrix(v, n)
    if ax is None:
        _, ax = plt.subplots(figsize=(5, 5))
    ax.imshow(votes, cmap="Blues", vmin=0, vmax=len(v))
    for i in range(n):
        for k in range(n):
            if votes[i, k]:
                ax.text(k, i, str(votes[i, k]), ha="center", va="center", fontsize=8)
    r = np.asarray(result)
    ax.scatter(r, np.arange(n), s=260, facecolors="none", edgecolors="#c8323c", linewidths=1.6)
    ax.set_xticks(range(n), [str(k + 1) for k in range(n)])
    ax.set_yticks(range(n), [str(i + 1) for i in range(n)])
    ax.set_xlabel("formation position")
    ax.set_ylabel("player (uniform number)")
    ax.set_title(title if title is not None else f"votes of {len(v)} agents; circled: adopted")
    return ax
