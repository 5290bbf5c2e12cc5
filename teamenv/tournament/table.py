"""League table (points, W/D/L, goals, goal difference), goal-difference matrix, CSV/JSON export."""

from __future__ import annotations

import csv
import json
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

POINTS_WIN = 3
POINTS_DRAW = 1

CSV_COLUMNS = ("rank", "team", "played", "won", "drawn", "lost", "goals_for", "goals_against",
               "goal_difference", "points", "forfeits", "elo", "elo_low", "elo_high", "bt",
               "bt_low", "bt_high")


@dataclass
class TableRow:
    """One team's line in the league table (goals by official score: forfeits count 0-3)."""

    team: str
    played: int = 0
    won: int = 0
    drawn: int = 0
    lost: int = 0
    goals_for: int = 0
    goals_against: int = 0
    forfeits: int = 0
    forfeit_reasons: dict[str, int] = field(default_factory=dict)
    rank: int = 0

    @property
    def goal_difference(self) -> int:
        return self.goals_for - self.goals_against

    @property
    def points(self) -> int:
        return POINTS_WIN * self.won + POINTS_DRAW * self.drawn


def league_table(records: Iterable, teams: Sequence[str] | None = None) -> list[TableRow]:
    """The table of stored matches, sorted by points, goal difference, goals for, name.

    ``teams`` lists every team (so a team with no match yet still has a row).
    """
    rows: dict[str, TableRow] = {t: TableRow(t) for t in teams or ()}
    for r in records:
        for me, gf, ga, side in ((r.left_team, r.left_official, r.right_official, "left"),
                                 (r.right_team, r.right_official, r.left_official, "right")):
            row = rows.setdefault(me, TableRow(me))
            row.played += 1
            row.goals_for += gf
            row.goals_against += ga
            if gf > ga:
                row.won += 1
            elif gf == ga:
                row.drawn += 1
            else:
                row.lost += 1
            if r.forfeit_side == side:
                row.forfeits += 1
                reason = r.forfeit_reason or "unknown"
                row.forfeit_reasons[reason] = row.forfeit_reasons.get(reason, 0) + 1
    ordered = sorted(rows.values(), key=lambda x: (-x.points, -x.goal_difference,
                                                   -x.goals_for, x.team))
    for k, row in enumerate(ordered):
        row.rank = k + 1
    return ordered


def goal_difference_matrix(records: Iterable, teams: Sequence[str]) -> np.ndarray:
    """Mean goal difference per match of row team against column team (NaN: never met)."""
    index = {t: i for i, t in enumerate(teams)}
    total = np.zeros((len(teams), len(teams)))
    count = np.zeros_like(total)
    for r in records:
        i, j = index[r.left_team], index[r.right_team]
        d = r.left_official - r.right_official
        total[i, j] += d
        total[j, i] -= d
        count[i, j] += 1
        count[j, i] += 1
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(count > 0, total / np.maximum(count, 1), np.nan)


def _row_dict(row: TableRow, ratings: Any | None) -> dict[str, Any]:
    out = {"rank": row.rank, "team": row.team, "played": row.played, "won": row.won,
           "drawn": row.drawn, "lost": row.lost, "goals_for": row.goals_for,
           "goals_against": row.goals_against, "goal_difference": row.goal_difference,
           "points": row.points, "forfeits": row.forfeits}
    if ratings is not None:
        for key, table in (("elo", ratings.elo), ("bt", ratings.bradley_terry)):
            r = table.get(row.team)
            out[key], out[f"{key}_low"], out[f"{key}_high"] = \
                (round(r.rating, 1), round(r.low, 1), round(r.high, 1)) if r else (None,) * 3
    return out


def write_csv(rows: Sequence[TableRow], path: str | Path, ratings: Any | None = None) -> Path:
    """Write the table (and ratings with intervals, when given) as CSV."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    columns = CSV_COLUMNS if ratings is not None else CSV_COLUMNS[:11]
    with open(path, "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=columns)
        writer.writeheader()
        for row in rows:
            writer.writerow(_row_dict(row, ratings))
    return path


def write_json(rows: Sequence[TableRow], path: str | Path, ratings: Any | None = None,
               extra: dict[str, Any] | None = None) -> Path:
    """Write the table, forfeit reasons, ratings and ``extra`` (e.g. the definition) as JSON."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    data = dict(extra or {})
    data["table"] = [dict(_row_dict(r, ratings), forfeit_reasons=r.forfeit_reasons) for r in rows]
    if ratings is not None:
        data["ratings"] = ratings.to_json()
    path.write_text(json.dumps(data, indent=2, sort_keys=False))
    return path


def rich_table(rows: Sequence[TableRow], title: str | None = None) -> Any:
    """A rich Table of the league: rank, W/D/L, goals, goal difference, points, forfeits."""
    from rich.table import Table

    table = Table(title=title, title_justify="left")
    for col in ("#", "team", "P", "W", "D", "L", "GF", "GA", "GD", "Pts", "forfeits"):
        if col == "team":
            table.add_column(col, overflow="fold", ratio=1, min_width=12)
        else:
            table.add_column(col, justify="right", no_wrap=col != "forfeits")
    for r in rows:
        table.add_row(str(r.rank), r.team, str(r.played), str(r.won), str(r.drawn), str(r.lost),
                      str(r.goals_for), str(r.goals_against), f"{r.goal_difference:+d}",
                      str(r.points), _forfeits(r))
    return table


def rich_ratings(ratings: Any, title: str | None = None) -> Any:
    """A rich Table of Elo and Bradley–Terry ratings (points) with their intervals."""
    from rich.table import Table

    pct = int(round(ratings.confidence * 100))
    table = Table(title=title, title_justify="left",
                  caption=f"{pct}% bootstrap intervals, {ratings.n_bootstrap} resamples of "
                          f"{ratings.n_games} matches", caption_justify="left")
    table.add_column("team", overflow="fold", ratio=1, min_width=12)
    for name in ("BT", "BT interval", "Elo", "Elo interval"):
        table.add_column(name, justify="right", no_wrap=True)
    for team, bt in ratings.bradley_terry.items():
        el = ratings.elo[team]
        table.add_row(team, f"{bt.rating:.0f}", f"[{bt.low:.0f}, {bt.high:.0f}]",
                      f"{el.rating:.0f}", f"[{el.low:.0f}, {el.high:.0f}]")
    return table


def rich_rank(ranks: Sequence[Any], title: str | None = None, confidence: float = 0.95,
              used: int | None = None, total: int | None = None) -> Any:
    """A rich Table of ``teamenv.analytics.ranking.rank_teams``: mean margin per match on the
    ranking metric and its bootstrap interval."""
    from rich.table import Table

    caption = (f"{int(round(confidence * 100))}% bootstrap intervals over each team's matches, "
               "resampled within each opponent")
    if used is not None and total is not None and used != total:
        caption += f"; {used} of {total} matches have the numbers"
    table = Table(title=title, title_justify="left", caption=caption, caption_justify="left")
    table.add_column("#", justify="right")
    table.add_column("team", overflow="fold", ratio=1, min_width=12)
    for name in ("margin/match", "interval", "matches"):
        table.add_column(name, justify="right", no_wrap=True)
    for r in ranks:
        table.add_row(str(r.rank), r.team, f"{r.mean:+.2f}", f"[{r.low:+.2f}, {r.high:+.2f}]",
                      str(r.matches))
    return table


def rich_head_to_head(pairings: Sequence[Any], title: str | None = None,
                      confidence: float = 0.95) -> Any:
    """A rich Table of ``teamenv.analytics.ranking.head_to_head``: each pairing's mean margin,
    its t interval and which team is ahead once the interval excludes zero."""
    from rich.table import Table

    caption = (f"{int(round(confidence * 100))}% t intervals of the mean margin per match; "
               "ahead: the interval excludes 0")
    table = Table(title=title, title_justify="left", caption=caption, caption_justify="left")
    table.add_column("pairing", overflow="fold", ratio=1, min_width=12)
    for name in ("margin/match", "interval", "matches", "ahead"):
        table.add_column(name, justify="right", no_wrap=True)
    for p in pairings:
        table.add_row(f"{p.a} vs {p.b}", f"{p.mean:+.2f}", f"[{p.low:+.2f}, {p.high:+.2f}]",
                      str(p.matches), p.leader() or "not separated")
    return table


def _forfeits(row: TableRow) -> str:
    if not row.forfeits:
        return "0"
    return f"{row.forfeits} (" + ", ".join(f"{k} {v}" for k, v in
                                           sorted(row.forfeit_reasons.items())) + ")"


__all__ = ["TableRow", "goal_difference_matrix", "league_table", "rich_head_to_head",
           "rich_rank", "rich_ratings", "rich_table", "write_csv", "write_json"]
