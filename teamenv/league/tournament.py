"""A round robin on the league server, stored as one tournament (``teamenv league-tournament``).

The schedule is the tournament module's own (``teamenv.tournament.round_robin``: every pair,
``games`` seeded rounds, each once with either team on the left), so the stored tournament
reads like any other (``teamenv tournament table``, ``benchmarks/fidelity_ranking.py``).
Matches are played one after another, each on a fresh server (``play_league_match``), and
stored as each ends; ``resume`` plays only what is missing. A team that raises stops the run
with its ``TeamFault`` (the match is not stored; a resume plays it again)."""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

from teamenv.match import MatchResult

from .errors import LeagueError
from .match import LeagueMatchOptions, play_league_match


@dataclass(frozen=True)
class LeagueTournamentSummary:
    scheduled: int
    played: int
    skipped: int
    wall_s: float


def league_round_robin(name: str, teams: Sequence[str], options: LeagueMatchOptions,
                       games: int = 1, seed: int = 0):
    """The tournament definition of a league round robin (options: ``mj7v7``, vision, ``mj``)."""
    from teamenv.tournament import round_robin

    return round_robin(name, list(teams), games_per_pairing=games, swap_sides=True, seed=seed,
                       options=options.match_options())


def run_league_tournament(
    name: str, db: str | Path, teams: Sequence[str] | None = None,
    options: LeagueMatchOptions | None = None, games: int = 1, seed: int = 0,
    resume: bool = False, log_dir: str | Path | None = None,
    on_match: Callable[[int, int, MatchResult], None] | None = None,
    play: Callable[..., MatchResult] | None = None,
) -> LeagueTournamentSummary:
    """Play (or, with ``resume``, finish) league round robin ``name`` in ``db``.

    A new run needs ``teams`` and ``options``; a resume reads the stored definition (teams,
    options, games and seed given with it must match it). ``on_match(done, total, result)``
    after each stored match; ``play`` is the match function (default ``play_league_match``;
    tests pass a stand-in)."""
    from teamenv.tournament import ResultStore

    play = play or play_league_match
    start = time.monotonic()
    with ResultStore(db) as store:
        found = store.find_tournament(name)
        if resume:
            if found is None:
                raise LeagueError(f"database {str(db)!r}: no tournament {name!r} to resume")
            tid, tournament = found
            if teams is not None and options is not None:
                want = league_round_robin(name, teams, options, games, seed)
                if want.definition_hash() != tournament.definition_hash():
                    raise LeagueError(f"tournament {name!r}: the stored definition differs from "
                                      "the one given; resume with the same teams and options")
        else:
            if found is not None:
                raise LeagueError(f"database {str(db)!r}: tournament {name!r} already exists; "
                                  "resume it (--resume) or choose another name")
            if teams is None or options is None:
                raise LeagueError("a new league tournament needs its teams and options")
            tournament = league_round_robin(name, teams, options, games, seed)
            from teamenv.teams import team_version

            tid = store.create_tournament(tournament, {t.label: team_version(t.name)
                                                       for t in tournament.all_teams})
        done = store.completed_indices(tid)
    mo = tournament.options
    match_options = LeagueMatchOptions(team_size=mo.team_size, game_s=mo.half_time_s)
    schedule = tournament.schedule()
    todo = [task for task in schedule if task.index not in done]
    played = 0
    for task in todo:
        result = play(task.left.label, task.right.label, match_options, seed=task.seed,
                      log_dir=log_dir)
        with ResultStore(db) as store:
            store.record_match(tid, task, result)
        played += 1
        if on_match is not None:
            on_match(len(done) + played, len(schedule), result)
    return LeagueTournamentSummary(len(schedule), played, len(schedule) - len(todo),
                                   time.monotonic() - start)
