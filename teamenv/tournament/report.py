"""``teamenv report``: one self-contained HTML page (figures embedded as base64 PNGs, no
external files or scripts) for a match replay or a tournament database.

Here, above the analytics, because it reads a tournament database (``ResultStore``); a replay's
page is the analytics' own (``teamenv.analytics.report.match_page``).
"""

from __future__ import annotations

import html
import sqlite3
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from teamenv.analytics.figures import figure_png, pyplot
from teamenv.analytics.ranking import RANK_METRICS, has_numbers, match_margins, rank_teams
from teamenv.analytics.report import html_figure, html_page, html_table, match_page
from teamenv.analytics.xg import XGModel
from teamenv.errors import ConfigError
from teamenv.tournament.store import ResultStore
from teamenv.tournament.table import league_table


def write_report(source: str | Path, out: str | Path, *, name: str | None = None,
                 model: XGModel | None = None) -> Path:
    """Write the page for ``source``: a replay (.npz) or a tournament database (SQLite);
    ``name`` picks the tournament in a database holding several."""
    source, out = Path(source), Path(out)
    if not source.exists():
        raise ConfigError(f"report: {str(source)!r} does not exist")
    page = tournament_page(source, name) if _is_sqlite(source) else \
        match_page(source, model)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(page, encoding="utf-8")
    return out


def _is_sqlite(path: Path) -> bool:
    with open(path, "rb") as fh:
        return fh.read(16) == b"SQLite format 3\x00"


def tournament_page(db: str | Path, name: str | None = None) -> str:
    """The HTML page of a stored tournament: league table, rankings on every metric of
    ``teamenv.analytics.ranking`` with intervals, per-team mean statistics and figures."""
    try:
        with ResultStore(db) as store:
            tid, tournament = store.get_tournament(name)
            records = store.matches(tid)
            team_stats = store.team_stats(tid)
    except sqlite3.DatabaseError as exc:
        raise ConfigError(f"report: database {str(db)!r}: {exc}") from exc
    teams = [t.label for t in tournament.all_teams]
    rows = league_table(records, teams)
    body = [f"<p>{len(records)}/{len(tournament.schedule())} matches stored; "
            f"{len(team_stats)} with statistics. Database: {html.escape(str(db))}.</p>",
            html_table(["#", "team", "P", "W", "D", "L", "GF", "GA", "GD", "Pts"],
                       [[r.rank, r.team, r.played, r.won, r.drawn, r.lost, r.goals_for,
                         r.goals_against, r.goal_difference, r.points] for r in rows])]
    margins = match_margins(records, team_stats)
    ranks = {}
    for metric in RANK_METRICS:
        usable = [m for m in margins if has_numbers(m, metric)]
        if not usable:
            continue
        ranks[metric] = rank_teams(usable, metric, teams)
        body.append(f"<h2>Ranked by {metric} (mean margin per match, 95 % bootstrap "
                    "interval)</h2>")
        body.append(html_table(["#", "team", "margin", "low", "high", "matches"],
                               [[r.rank, r.team, r.mean, r.low, r.high, r.matches]
                                for r in ranks[metric]]))
    means = _team_means(records, team_stats)
    if means:
        keys = ["goals", "xg", "shots", "possession_pct", "passes_completed",
                "ball_progress_m", "distance_walked_m", "falls", "messages_sent"]
        body.append("<h2>Mean statistics per match</h2>")
        body.append(html_table(["team", *keys], [[team, *[means[team].get(k) for k in keys]]
                                                 for team in sorted(means)]))
        body.append(html_figure("Expected goals and goals per match", _tournament_figure(means)))
    if ranks:
        body.append(html_figure("Rankings with intervals", _ranks_figure(ranks)))
    return html_page(f"Tournament {tournament.name}", "\n".join(body))


def _team_means(records: Sequence[Any], team_stats: dict[int, dict[str, dict]]
                ) -> dict[str, dict[str, float]]:
    sums: dict[str, dict[str, float]] = {}
    counts: dict[str, int] = {}
    for r in records:
        for side, team in (("left", r.left_team), ("right", r.right_team)):
            s = team_stats.get(r.id, {}).get(side)
            if s is None:
                continue
            counts[team] = counts.get(team, 0) + 1
            acc = sums.setdefault(team, {})
            other = team_stats[r.id].get("right" if side == "left" else "left", {})
            acc["xg_against"] = acc.get("xg_against", 0.0) + float(other.get("xg", 0.0))
            acc["goals_against"] = acc.get("goals_against", 0.0) + float(other.get("goals", 0))
            for k, v in s.items():
                if isinstance(v, (int, float)) and not isinstance(v, bool):
                    acc[k] = acc.get(k, 0.0) + float(v)
    return {t: {k: v / counts[t] for k, v in acc.items()} for t, acc in sums.items()}


def _tournament_figure(means: dict[str, dict[str, float]]) -> bytes:
    plt = pyplot()
    teams = sorted(means)
    x = np.arange(len(teams))
    fig, ax = plt.subplots(figsize=(max(6, 1.4 * len(teams)), 3.6))
    for k, (key, label) in enumerate((("goals", "goals for"), ("xg", "xG for"),
                                      ("goals_against", "goals against"),
                                      ("xg_against", "xG against"))):
        ax.bar(x + (k - 1.5) * 0.2, [means[t].get(key, 0.0) for t in teams], width=0.2,
               label=label)
    ax.set_xticks(x, teams, fontsize=8)
    ax.set_ylabel("per match")
    ax.legend(fontsize=8)
    return figure_png(fig)


def _ranks_figure(ranks: dict[str, list[Any]]) -> bytes:
    plt = pyplot()
    fig, axes = plt.subplots(1, len(ranks), figsize=(4.5 * len(ranks), 3.2), squeeze=False)
    for ax, (metric, rows) in zip(axes[0], ranks.items(), strict=True):
        for k, r in enumerate(rows):
            ax.errorbar([r.mean], [k], xerr=[[r.mean - r.low], [r.high - r.mean]], fmt="o",
                        capsize=3)
        ax.axvline(0.0, color="0.6", lw=0.8)
        ax.set_yticks(range(len(rows)), [r.team for r in rows], fontsize=8)
        ax.invert_yaxis()
        ax.set_title(f"margin per match: {metric}")
    return figure_png(fig)
