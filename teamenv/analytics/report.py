"""``teamenv report``: one self-contained HTML page (figures embedded as base64 PNGs, no
external files or scripts) for a match replay or a tournament database."""

from __future__ import annotations

import base64
import html
import sqlite3
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from teamenv.analytics.events import match_events
from teamenv.analytics.geometry import THIRDS
from teamenv.analytics.stats import MatchStats, match_stats
from teamenv.analytics.xg import XGModel
from teamenv.errors import ConfigError
from teamenv.replay import load_replay

_STYLE = """body{font-family:system-ui,sans-serif;margin:2em;max-width:1200px;color:#222}
table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #ccc;padding:3px 8px;
text-align:right}th:first-child,td:first-child{text-align:left}img{max-width:100%}
h2{border-bottom:1px solid #ddd}.note{color:#666;font-size:90%}"""


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


def _img(title: str, png: bytes) -> str:
    data = base64.b64encode(png).decode("ascii")
    return (f"<h2>{html.escape(title)}</h2>\n"
            f'<img alt="{html.escape(title)}" src="data:image/png;base64,{data}">')


def _table(header: Sequence[str], rows: Sequence[Sequence[Any]]) -> str:
    head = "".join(f"<th>{html.escape(str(h))}</th>" for h in header)
    body = "\n".join("<tr>" + "".join(f"<td>{html.escape(_cell(c))}</td>" for c in row)
                     + "</tr>" for row in rows)
    return f"<table>\n<tr>{head}</tr>\n{body}\n</table>"


def _cell(value: Any) -> str:
    if value is None:
        return "-"
    if isinstance(value, float):
        return f"{value:.2f}"
    return str(value)


def _page(title: str, body: str) -> str:
    return ("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
            f"<title>{html.escape(title)}</title>\n<style>{_STYLE}</style>\n</head>\n<body>\n"
            f"<h1>{html.escape(title)}</h1>\n{body}\n</body>\n</html>\n")


def stats_rows(stats: MatchStats) -> list[list[Any]]:
    """The match table's rows: (label, left, right)."""
    left, right = stats.teams
    rows: list[list[Any]] = []

    def add(label: str, fn: Any) -> None:
        rows.append([label, fn(left), fn(right)])

    add("goals", lambda t: t.goals)
    add("expected goals (xG)", lambda t: t.xg)
    add("shots in reach / kicks on frame", lambda t: f"{t.shots} / {t.attempts_on_frame}")
    add("possession %", lambda t: t.possession_pct)
    add("possession lost (at restarts)", lambda t: f"{t.possession_lost} ({t.lost_at_restart})")
    add("kicks", lambda t: t.kicks)
    add("passes completed / attempted", lambda t: f"{t.passes_completed} / "
        f"{t.passes_attempted}")
    add("pass completion %", lambda t: t.pass_completion_pct)
    add("ball progress (m)", lambda t: t.ball_progress_m)
    for third in THIRDS:
        add(f"ball in {third} third, % of play", lambda t, k=third: t.third_pct[k])
    add("distance walked (m)", lambda t: t.distance_walked_m)
    add("falls", lambda t: t.falls)
    add("messages sent (bytes)", lambda t: f"{t.messages_sent} ({t.message_bytes})")
    add("message drop records", lambda t: t.messages_dropped)
    add("messages heard from teammates / opponents",
        lambda t: f"{t.messages_heard_team} / {t.messages_heard_opponents}")
    add("role agreement, % of play", lambda t: t.role_agreement_pct)
    for kind in ("KickOff", "KickIn", "CornerKick", "GoalKick"):
        add(f"{kind}: awarded / taken / goal / shot / kept / lost",
            lambda t, k=kind: " / ".join(str(t.set_plays[k][x]) for x in
                                         ("awarded", "taken", "goal", "shot", "kept", "lost")))
    return rows


def match_page(path: str | Path, model: XGModel | None = None) -> str:
    """The HTML page of one replay: facts, the statistics table and every figure."""
    from teamenv.analytics.figures import match_figures

    replay = load_replay(path)
    events = match_events(replay)
    stats = match_stats(replay, model, events)
    title = (f"{stats.left.team} {stats.score[0]} - {stats.score[1]} {stats.right.team} "
             f"(seed {stats.seed})")
    facts = (f"<p>{html.escape(stats.field)} {stats.team_size} v {stats.team_size}, "
             f"{stats.cycles} cycles ({stats.duration_s:.0f} s game time, in play "
             f"{stats.play_on_s:.0f} s), {stats.possession_changes} possession changes. "
             f"Replay: {html.escape(str(path))}."
             + ("" if stats.has_extras else " Recorded without agent beliefs and roles "
                "(role agreement unknown).") + "</p>")
    table = _table(["", f"left: {stats.left.team}", f"right: {stats.right.team}"],
                   stats_rows(stats))
    figures = "\n".join(_img(t, png) for t, png in match_figures(replay, events, stats).items())
    note = ("<p class=\"note\">Definitions: docs/analytics.md. xG model: "
            f"{html.escape(str(stats.xg_model.get('fitted', {}).get('data', 'see file')))}"
            "</p>")
    return _page(title, facts + table + figures + note)


def tournament_page(db: str | Path, name: str | None = None) -> str:
    """The HTML page of a stored tournament: league table, rankings on every metric of
    ``teamenv.analytics.ranking`` with intervals, per-team mean statistics and figures."""
    from teamenv.analytics.ranking import RANK_METRICS, has_numbers, match_margins, rank_teams
    from teamenv.tournament.store import ResultStore
    from teamenv.tournament.table import league_table

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
            _table(["#", "team", "P", "W", "D", "L", "GF", "GA", "GD", "Pts"],
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
        body.append(_table(["#", "team", "margin", "low", "high", "matches"],
                           [[r.rank, r.team, r.mean, r.low, r.high, r.matches]
                            for r in ranks[metric]]))
    means = _team_means(records, team_stats)
    if means:
        keys = ["goals", "xg", "shots", "possession_pct", "passes_completed",
                "ball_progress_m", "distance_walked_m", "falls", "messages_sent"]
        body.append("<h2>Mean statistics per match</h2>")
        body.append(_table(["team", *keys], [[team, *[means[team].get(k) for k in keys]]
                                             for team in sorted(means)]))
        body.append(_img("Expected goals and goals per match", _tournament_figure(means)))
    if ranks:
        body.append(_img("Rankings with intervals", _ranks_figure(ranks)))
    return _page(f"Tournament {tournament.name}", "\n".join(body))


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
    import numpy as np

    from teamenv.analytics.figures import _png, _pyplot

    plt = _pyplot()
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
    return _png(fig)


def _ranks_figure(ranks: dict[str, list[Any]]) -> bytes:
    from teamenv.analytics.figures import _png, _pyplot

    plt = _pyplot()
    fig, axes = plt.subplots(1, len(ranks), figsize=(4.5 * len(ranks), 3.2), squeeze=False)
    for ax, (metric, rows) in zip(axes[0], ranks.items(), strict=True):
        for k, r in enumerate(rows):
            ax.errorbar([r.mean], [k], xerr=[[r.mean - r.low], [r.high - r.mean]], fmt="o",
                        capsize=3)
        ax.axvline(0.0, color="0.6", lw=0.8)
        ax.set_yticks(range(len(rows)), [r.team for r in rows], fontsize=8)
        ax.invert_yaxis()
        ax.set_title(f"margin per match: {metric}")
    return _png(fig)
