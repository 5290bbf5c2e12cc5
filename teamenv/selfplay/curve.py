"""The rating curve of a league run (PNG): every snapshot's Bradley–Terry rating with its
bootstrap interval against its generation, the built-in teams as bands, and what each
generation trained against (the PFSP probabilities)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from teamenv.errors import ConfigError
from teamenv.selfplay.league_store import LeagueStore
from teamenv.selfplay.snapshots import snapshot_name

_BUILTIN_COLORS = ("tab:red", "tab:purple", "tab:brown", "tab:gray", "tab:olive", "tab:cyan")


def plot_rating_curve(store: LeagueStore, path: str | Path, title: str | None = None) -> Path:
    """Write the run's rating curve to ``path``; returns the path."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    last = store.last_rated()
    if last < 0:
        raise ConfigError("selfplay curve: no generation rated yet")
    final = store.ratings(last)
    records = store.generations()[:last + 1]
    gens = list(range(last + 1))
    names = [snapshot_name(g) for g in gens]
    bt = final.bradley_terry
    rating = np.array([bt[n].rating for n in names])
    low = np.array([bt[n].low for n in names])
    high = np.array([bt[n].high for n in names])
    at_the_time = np.array([store.ratings(g).bradley_terry[snapshot_name(g)].rating
                            for g in gens])

    fig, (ax, ax_mix) = plt.subplots(2, 1, figsize=(8, 7), height_ratios=(3, 2), sharex=True)
    builtins = [t for t in bt if not t.startswith("gen-")]
    for k, team in enumerate(builtins):
        color = _BUILTIN_COLORS[k % len(_BUILTIN_COLORS)]
        r = bt[team]
        ax.axhspan(r.low, r.high, color=color, alpha=0.12)
        ax.axhline(r.rating, color=color, ls="--", lw=1,
                   label=f"{team} {r.rating:.0f} [{r.low:.0f}, {r.high:.0f}]")
    ax.errorbar(gens, rating, yerr=[rating - low, high - rating], color="tab:green", marker="o",
                capsize=3, label=f"snapshot, after generation {last} (95 % bootstrap)")
    ax.plot(gens, at_the_time, color="tab:green", ls=":", marker=".",
            label="snapshot, when it was rated")
    ax.set(ylabel="Bradley-Terry rating (Elo scale)",
           title=title or f"self-play league: {final.n_games} rating matches")
    ax.legend(fontsize=7, loc="best")

    opponents = sorted({o["team"] for r in records for o in r.opponents},
                       key=lambda t: (t.startswith("gen-"), t))
    shares = np.zeros((len(opponents), len(gens)))
    for record in records:
        for o in record.opponents:
            shares[opponents.index(o["team"]), record.generation] = o["probability"]
    builtin_rows = [k for k, t in enumerate(opponents) if not t.startswith("gen-")]
    snapshot_rows = [k for k, t in enumerate(opponents) if t.startswith("gen-")]
    bottom = np.zeros(len(gens))
    for k in builtin_rows:
        color = _BUILTIN_COLORS[builtins.index(opponents[k]) % len(_BUILTIN_COLORS)] \
            if opponents[k] in builtins else None
        ax_mix.bar(gens, shares[k], bottom=bottom, color=color, label=opponents[k])
        bottom += shares[k]
    if snapshot_rows:
        ax_mix.bar(gens, shares[snapshot_rows].sum(axis=0), bottom=bottom, color="tab:green",
                   alpha=0.5, label="earlier snapshots")
    ax_mix.set(xlabel="generation (0 = untrained)", ylabel="PFSP share of training episodes",
               ylim=(0, 1))
    ax_mix.legend(fontsize=7, loc="upper right")
    fig.tight_layout()
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return path
