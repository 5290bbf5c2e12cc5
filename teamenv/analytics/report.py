"""The HTML page of a match replay (figures embedded as base64 PNGs, no external files or
scripts), and the page parts the tournament's page (``teamenv.tournament.report``) reuses."""

from __future__ import annotations

import base64
import html
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from teamenv.analytics.events import match_events
from teamenv.analytics.geometry import THIRDS
from teamenv.analytics.stats import MatchStats, match_stats
from teamenv.analytics.xg import XGModel
from teamenv.replay import load_replay

_STYLE = """body{font-family:system-ui,sans-serif;margin:2em;max-width:1200px;color:#222}
table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #ccc;padding:3px 8px;
text-align:right}th:first-child,td:first-child{text-align:left}img{max-width:100%}
h2{border-bottom:1px solid #ddd}.note{color:#666;font-size:90%}"""


def html_figure(title: str, png: bytes) -> str:
    """A heading and the PNG embedded as base64."""
    data = base64.b64encode(png).decode("ascii")
    return (f"<h2>{html.escape(title)}</h2>\n"
            f'<img alt="{html.escape(title)}" src="data:image/png;base64,{data}">')


def html_table(header: Sequence[str], rows: Sequence[Sequence[Any]]) -> str:
    """A table; floats with two decimals, None as "-"."""
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


def html_page(title: str, body: str) -> str:
    """A whole self-contained page around ``body``."""
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
    table = html_table(["", f"left: {stats.left.team}", f"right: {stats.right.team}"],
                       stats_rows(stats))
    figures = "\n".join(html_figure(t, png)
                        for t, png in match_figures(replay, events, stats).items())
    note = ("<p class=\"note\">Definitions: docs/analytics.md. xG model: "
            f"{html.escape(str(stats.xg_model.get('fitted', {}).get('data', 'see file')))}"
            "</p>")
    return html_page(title, facts + table + figures + note)
