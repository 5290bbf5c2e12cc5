"""Plot a formation with matplotlib: pitch, triangulation, sample balls, home positions for a ball."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from strategy.positioning.formation.model import Formation

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes

_TYPE_COLOURS = {"G": "#e6a700", "DF": "#1f5fbf", "MF": "#2e9e44", "FW": "#c8323c"}


def plot_formation(
    formation: Formation,
    ball: ArrayLike | None = None,
    *,
    ax: Axes | None = None,
    show_triangulation: bool = True,
    show_samples: bool = True,
    show_labels: bool = True,
    title: str | None = None,
) -> Axes:
    """Draw ``formation`` on a pitch of its size and return the matplotlib ``Axes``.

    Args:
        formation: what to draw.
        ball: a ball position (x, y) in metres; its home positions are drawn, coloured by role
            type and labelled with the uniform number. Default: the first sample's ball.
        ax: axes to draw on (default: a new figure, 9 inches wide).
        show_triangulation: draw the Delaunay triangles of the sample ball positions.
        show_samples: draw the sample ball positions.
        show_labels: write uniform numbers next to the home positions.
        title: the axes title (default: the formation's name and the ball position).
    """
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D
    from matplotlib.patches import Circle, Rectangle

    length, width = formation.field_size
    if ax is None:
        _, ax = plt.subplots(figsize=(9, 9 * (width + 4) / (length + 4)))
    hl, hw = length / 2.0, width / 2.0
    ax.add_patch(Rectangle((-hl, -hw), length, width, facecolor="#e8f3e8", edgecolor="#4a7a4a",
                           linewidth=1.5, zorder=0))
    ax.plot([0, 0], [-hw, hw], color="#4a7a4a", linewidth=1.0, zorder=0)
    ax.add_patch(Circle((0, 0), 0.09 * width, fill=False, edgecolor="#4a7a4a", linewidth=1.0,
                        zorder=0))
    goal = 0.07 * width
    for sx in (-1, 1):
        ax.plot([sx * hl, sx * (hl + 0.02 * length)], [goal, goal], color="k", linewidth=1.0)
        ax.plot([sx * hl, sx * (hl + 0.02 * length)], [-goal, -goal], color="k", linewidth=1.0)
    samples = formation.ball_samples
    if show_triangulation and not formation.is_static:
        ax.triplot(samples[:, 0], samples[:, 1], formation.simplices, color="#8c8c8c",
                   linewidth=0.6, zorder=1)
    if show_samples:
        ax.scatter(samples[:, 0], samples[:, 1], s=10, color="#555555", zorder=2,
                   label="sample ball positions")
    b = np.asarray(samples[0] if ball is None else ball, dtype=np.float64)
    home = formation.home_positions(b)
    colours = [_TYPE_COLOURS.get(r.type, "k") for r in formation.roles]
    ax.scatter(home[:, 0], home[:, 1], s=90, c=colours, edgecolors="k", linewidths=0.8,
               zorder=4)
    if show_labels:
        for i, (x, y) in enumerate(home):
            ax.annotate(str(i + 1), (x, y), textcoords="offset points", xytext=(6, 5),
                        fontsize=8, zorder=5)
    ax.scatter([b[0]], [b[1]], s=60, color="white", edgecolors="k", marker="o", zorder=6)
    handles: list[Any] = [
        Line2D([], [], marker="o", linestyle="", markerfacecolor=c, markeredgecolor="k",
               label=t) for t, c in _TYPE_COLOURS.items()
        if any(r.type == t for r in formation.roles)
    ]
    handles.append(Line2D([], [], marker="o", linestyle="", markerfacecolor="white",
                          markeredgecolor="k", label="ball"))
    if show_samples:
        handles.append(Line2D([], [], marker="o", linestyle="", markersize=4,
                              markerfacecolor="#555555", markeredgecolor="#555555",
                              label="samples"))
    ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize=8,
              frameon=False)
    ax.set_xlim(-hl - 0.05 * length, hl + 0.05 * length)
    ax.set_ylim(-hw - 0.05 * length, hw + 0.05 * length)
    ax.set_aspect("equal")
    ax.set_xlabel("x (m), we attack +x")
    ax.set_ylabel("y (m)")
    ax.set_title(title if title is not None else
                 f"{formation.name}: ball at ({b[0]:.1f}, {b[1]:.1f}) m")
    return ax
