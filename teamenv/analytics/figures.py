"""Match figures (matplotlib, no display needed): heatmaps, pass networks, shot map, a
possession and role timeline, message use; each returned as PNG bytes."""

from __future__ import annotations

import io
from typing import Any

import numpy as np

from teamenv.analytics.events import PLAY_ON, MatchEvents
from teamenv.analytics.stats import SIDES, MatchStats, role_agreement
from teamenv.replay import Replay

COLOURS = ("#1f77b4", "#d62728")  # left, right
DPI = 80


def pyplot() -> Any:
    """matplotlib.pyplot on the Agg backend (no display needed)."""
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    return plt


def figure_png(fig: Any) -> bytes:
    """``fig`` as PNG bytes at ``DPI``; closes the figure."""
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=DPI, bbox_inches="tight")
    pyplot().close(fig)
    return buf.getvalue()


def _pitch(ax: Any, half_length: float, half_width: float, half_goal_width: float) -> None:
    ax.plot([-half_length, half_length, half_length, -half_length, -half_length],
            [-half_width, -half_width, half_width, half_width, -half_width], "k-", lw=1)
    ax.plot([0, 0], [-half_width, half_width], "k-", lw=0.8)
    for x in (-half_length, half_length):
        ax.plot([x, x], [-half_goal_width, half_goal_width], "k-", lw=4)
    ax.set_xlim(-half_length * 1.05, half_length * 1.05)
    ax.set_ylim(-half_width * 1.08, half_width * 1.08)
    ax.set_aspect("equal")
    ax.set_xticks([])
    ax.set_yticks([])


def _geometry(replay: Replay) -> tuple[float, float, float]:
    m = replay.metadata
    return float(m["half_length"]), float(m["half_width"]), float(m["half_goal_width"])


def heatmaps(replay: Replay, events: MatchEvents, stats: MatchStats) -> bytes:
    """Where each side's players and the ball were in play, in the side's attacking frame
    (attacking to the right)."""
    plt = pyplot()
    hl, hw, hg = _geometry(replay)
    n = replay.team_size
    play_on = replay.play_mode == PLAY_ON
    fig, axes = plt.subplots(1, 3, figsize=(15, 3.8))
    bins = (30, 20)
    extent = [[-hl, hl], [-hw, hw]]
    for side, ax in enumerate(axes[:2]):
        sign = events.team_sign[play_on, side][:, None]
        xy = replay.players[play_on, side * n:(side + 1) * n, :2].astype(float)
        x, y = (xy[..., 0] * sign).ravel(), (xy[..., 1] * sign).ravel()
        h, _, _ = np.histogram2d(x, y, bins=bins, range=extent)
        ax.imshow(h.T, origin="lower", extent=(-hl, hl, -hw, hw), cmap="Blues" if side == 0
                  else "Reds", aspect="equal")
        _pitch(ax, hl, hw, hg)
        ax.set_title(f"{SIDES[side]}: {stats.teams[side].team} (attacking →)")
    ball = replay.ball[play_on, :2].astype(float)
    h, _, _ = np.histogram2d(ball[:, 0], ball[:, 1], bins=bins, range=extent)
    axes[2].imshow(h.T, origin="lower", extent=(-hl, hl, -hw, hw), cmap="Greens",
                   aspect="equal")
    _pitch(axes[2], hl, hw, hg)
    axes[2].set_title("ball (world frame, left side's first-half view)")
    return figure_png(fig)


def pass_networks(replay: Replay, stats: MatchStats) -> bytes:
    """Completed passes between players (line width: count) at their mean positions in play,
    each side attacking to the right."""
    plt = pyplot()
    hl, hw, hg = _geometry(replay)
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.2))
    for side, ax in enumerate(axes):
        team = stats.teams[side]
        _pitch(ax, hl, hw, hg)
        pos = {p.unum: (p.mean_x, p.mean_y) for p in team.players}
        edges = stats.pass_network.get(SIDES[side], [])
        top = max((c for _, _, c in edges), default=1)
        for a, b, c in edges:
            (x0, y0), (x1, y1) = pos[a], pos[b]
            ax.annotate("", xy=(x1, y1), xytext=(x0, y0),
                        arrowprops={"arrowstyle": "->", "color": COLOURS[side],
                                    "lw": 0.8 + 4.0 * c / top, "alpha": 0.7})
        for p in team.players:
            ax.scatter([p.mean_x], [p.mean_y], s=60 + 12 * p.kicks, color=COLOURS[side],
                       edgecolor="k", zorder=3)
            ax.text(p.mean_x, p.mean_y, str(p.unum), ha="center", va="center", fontsize=7,
                    color="white", zorder=4)
        ax.set_title(f"{team.team}: {team.passes_completed}/{team.passes_attempted} "
                     "passes completed")
    return figure_png(fig)


def shot_map(replay: Replay, stats: MatchStats) -> bytes:
    """Every kick on frame from where it was taken (world frame), size by its xG; filled when
    it scored."""
    plt = pyplot()
    hl, hw, hg = _geometry(replay)
    fig, ax = plt.subplots(figsize=(8, 4.6))
    _pitch(ax, hl, hw, hg)
    for shot in stats.shots:
        side = SIDES.index(shot["side"])
        goal = shot["outcome"] == "goal"
        ax.scatter([shot["x"]], [shot["y"]], s=30 + 600 * (shot["xg"] or 0.0),
                   facecolor=COLOURS[side] if goal else "none", edgecolor=COLOURS[side],
                   lw=1.5, alpha=0.8)
    ax.set_title(f"kicks on frame (size: xG; filled: goal) — xG {stats.left.xg:.2f} : "
                 f"{stats.right.xg:.2f}")
    return figure_png(fig)


def timeline(replay: Replay, events: MatchEvents, stats: MatchStats) -> bytes:
    """Possession over time (which side made the last contact), play mode in play, and with
    extras the role agreement of each side and each agent's own role."""
    plt = pyplot()
    t = replay.time_s
    agree = role_agreement(replay)
    rows = 2 + (0 if agree is None else 2)
    fig, axes = plt.subplots(rows, 1, figsize=(12, 1.3 * rows + 0.6), sharex=True,
                             squeeze=False)
    axes = axes[:, 0]
    poss = events.possession.astype(float)
    poss[poss < 0] = np.nan
    axes[0].imshow(poss[None, :], aspect="auto", cmap="coolwarm", vmin=0, vmax=1,
                   extent=(t[0], t[-1], 0, 1), interpolation="nearest")
    axes[0].set_yticks([])
    axes[0].set_ylabel("possession", rotation=0, ha="right")
    axes[1].fill_between(t, 0, (replay.play_mode == PLAY_ON).astype(float), step="post",
                         color="0.6")
    axes[1].set_yticks([])
    axes[1].set_ylabel("in play", rotation=0, ha="right")
    if agree is not None:
        n = replay.team_size
        for side in (0, 1):
            ax = axes[2 + side]
            roles = replay.role[:, side * n:(side + 1) * n].astype(float)
            roles[roles < 0] = np.nan
            ax.imshow(roles.T, aspect="auto", cmap="tab20", extent=(t[0], t[-1], n + 0.5, 0.5),
                      interpolation="nearest")
            bad = agree[:, side] == 0
            ax.fill_between(t, n + 0.5, n + 0.5 - 0.4 * bad, step="post", color="k")
            ax.set_ylabel(f"{SIDES[side]} roles\n(black: disagree)", rotation=0, ha="right")
    axes[-1].set_xlabel("game time (s)")
    fig.suptitle("blue: left has the ball, red: right")
    return figure_png(fig)


def message_use(replay: Replay, stats: MatchStats) -> bytes:
    """Per player: messages sent, drops of its messages and what it heard; per side: bytes
    said per 10 s of game time."""
    plt = pyplot()
    n = replay.team_size
    fig, (ax0, ax1) = plt.subplots(1, 2, figsize=(13, 3.8))
    x = np.arange(2 * n)
    sent = [p.messages_sent for t in stats.teams for p in t.players]
    ax0.bar(x - 0.2, sent, width=0.4, color=[COLOURS[i // n] for i in x], label="sent")
    drops = replay.say_drops.astype(np.int64).sum(axis=0)
    ax0.bar(x + 0.2, drops, width=0.4, color="0.6", label="drop records")
    ax0.set_xticks(x, [f"{'L' if i < n else 'R'}{i % n + 1}" for i in x], fontsize=7)
    ax0.set_yscale("symlog")
    ax0.legend(fontsize=8)
    ax0.set_title("messages per player")
    t = replay.time_s
    width = 10.0
    edges = np.arange(0.0, max(float(t[-1]), width) + width, width)
    for side in (0, 1):
        b = replay.say_bytes[:, side * n:(side + 1) * n].astype(np.int64).sum(axis=1)
        per, _ = np.histogram(t, bins=edges, weights=b)
        ax1.step(edges[:-1], per, where="post", color=COLOURS[side],
                 label=f"{stats.teams[side].team} ({stats.teams[side].message_bytes} bytes)")
    ax1.set_xlabel("game time (s)")
    ax1.set_ylabel(f"bytes said per {width:g} s")
    ax1.legend(fontsize=8)
    ax1.set_title("message bytes over time")
    return figure_png(fig)


def match_figures(replay: Replay, events: MatchEvents, stats: MatchStats
                  ) -> dict[str, bytes]:
    """Every figure of a match page, by title."""
    return {"Heatmaps": heatmaps(replay, events, stats),
            "Pass networks": pass_networks(replay, stats),
            "Shots and expected goals": shot_map(replay, stats),
            "Possession and roles over time": timeline(replay, events, stats),
            "Messages": message_use(replay, stats)}
