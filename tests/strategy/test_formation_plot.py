"""Formation plots: triangulation, samples and home positions are drawn; a PNG can be saved."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402

from strategy.positioning.formation import builtin_formation, plot_formation  # noqa: E402


def test_plot_draws_triangulation_samples_and_home_positions(tmp_path):
    f = builtin_formation("11v11-defend")
    ax = plot_formation(f, (5.0, 3.0))
    assert "11v11-defend" in ax.get_title()
    # triangulation lines, the sample scatter, the home positions, the ball
    assert max(len(line.get_xdata()) for line in ax.lines) >= len(f.simplices)  # triplot
    offsets = [c.get_offsets() for c in ax.collections]
    assert any(len(o) == f.n_samples for o in offsets)
    assert any(len(o) == f.n_players for o in offsets)
    out = tmp_path / "f.png"
    ax.figure.savefig(out)
    assert out.stat().st_size > 1000
    plt.close(ax.figure)


def test_plot_static_formation_on_given_axes():
    fig, ax = plt.subplots()
    f = builtin_formation("7v7-kickoff-ours")
    assert plot_formation(f, ax=ax, show_samples=False, title="kick-off") is ax
    assert ax.get_title() == "kick-off"
    plt.close(fig)
