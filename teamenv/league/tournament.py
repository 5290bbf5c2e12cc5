"""A round robin on the league server, stored as one tournament (``teamenv league-tournament``).

The schedule is the tournament module's own (``teamenv.tournament.round_robin``: every pair,
``games`` seeded rounds, each once with either team on the left), and the run is the tournament
module's too (``teamenv.tournament.run_tournament``: create or resume, the definition and team
versions checked, each match stored as it ends), with ``LeagueBackend`` playing each task on a
fresh server (``play_league_match``), one after another. So the stored tournament reads like
any other (``teamenv tournament table``, ``benchmarks/fidelity_ranking.py``). A team that
raises stops the run with its ``TeamFault`` (the match is not stored; a resume plays it again).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from teamenv.match import MatchResult

from .errors import LeagueError
from .match import LeagueMatchOptions, play_league_match

if TYPE_CHECKING:  # the tournament module is imported when a tournament runs
    from teamenv.tournament.backends import Outcome
    from teamenv.tournament.schedule import MatchTask


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


def play_league_task(task: MatchTask, play: Callable[..., MatchResult], server: str,
                     log_dir: str | Path | None) -> MatchResult:
    """One tournament task as a league match (module level: a Ray task pickles it)."""
    options = LeagueMatchOptions(team_size=task.options.team_size,
                                 game_s=task.options.half_time_s, server=server)
    kwargs: dict = {"seed": task.seed, "log_dir": log_dir}
    if task.replay_path is not None:
        kwargs["replay_path"] = task.replay_path
    return play(task.left.label, task.right.label, options, **kwargs)


class LeagueBackend:
    """A tournament backend (``teamenv.tournament.run_tournament(backend=...)``) that plays each
    task on the league server: ``play(left, right, options, seed, log_dir, replay_path)``
    (default ``play_league_match``) with the task's team labels, seed and replay path and
    league options made from the task's (team size, the half's length as the game).
    ``workers`` > 1 plays that many matches at once in worker processes (``spawn``; each match
    on its own server), else one after another in this process; ``ray_address`` plays them as
    Ray tasks instead (``"local"``: a local Ray instance with ``workers`` CPUs; ``"auto"`` or
    ``"ray://host:10001"``: a cluster whose nodes have the humanoid extra), a task that fails
    there is recorded as a failure and played again on resume. ``on_match(k, n, result)``
    after the k-th of the n matches of this run is stored."""

    name = "league"

    def __init__(self, play: Callable[..., MatchResult] | None = None,
                 log_dir: str | Path | None = None,
                 on_match: Callable[[int, int, MatchResult], None] | None = None,
                 server: str = "real", workers: int = 1,
                 ray_address: str | None = None) -> None:
        if workers < 1:
            raise LeagueError(f"league backend: workers must be >= 1, not {workers}")
        self.ray_address = ray_address
        self.play = play or play_league_match
        self.log_dir = log_dir
        self.on_match = on_match
        self.server = server
        self.workers = workers

    def run(self, tasks: Sequence[MatchTask]) -> Iterator[Outcome]:
        for k, outcome in enumerate(self._outcomes(tasks), 1):
            yield outcome
            # resumed after the tournament runner stored the match
            if self.on_match is not None and outcome.result is not None:
                self.on_match(k, len(tasks), outcome.result)

    def _outcomes(self, tasks: Sequence[MatchTask]) -> Iterator[Outcome]:
        """Each task's outcome as its match ends: as Ray tasks, in worker processes, or one
        after another in this process."""
        from teamenv.tournament.backends import Outcome

        settings = {"play": self.play, "server": self.server, "log_dir": self.log_dir}
        if self.ray_address is not None:
            from functools import partial

            from teamenv.tournament.backends import RayBackend

            local = self.ray_address == "local"
            yield from RayBackend(address=None if local else self.ray_address,
                                  num_cpus=self.workers if local else None,
                                  runner=partial(play_league_task, **settings)).run(tasks)
        elif self.workers == 1:
            for task in tasks:
                yield Outcome(task, play_league_task(task, **settings))
        else:
            import multiprocessing
            from concurrent.futures import ProcessPoolExecutor, as_completed

            from teamenv.tournament.backends import terminate_workers

            pool = ProcessPoolExecutor(self.workers,
                                       mp_context=multiprocessing.get_context("spawn"))
            futures = {pool.submit(play_league_task, task, **settings): task for task in tasks}
            finished = False
            try:
                for future in as_completed(futures):
                    # a TeamFault stops the run, as in one process
                    yield Outcome(futures[future], future.result())
                finished = True
            finally:
                if not finished:
                    # interrupted (Ctrl-C, SIGTERM, a fault, the generator closed): stop the
                    # matches in flight and drop the queued ones; a plain shutdown would
                    # play every queued match to its end, unstored
                    terminate_workers(pool)
                pool.shutdown(wait=finished, cancel_futures=True)


def run_league_tournament(
    name: str, db: str | Path, teams: Sequence[str] | None = None,
    options: LeagueMatchOptions | None = None, games: int = 1, seed: int = 0,
    resume: bool = False, log_dir: str | Path | None = None,
    on_match: Callable[[int, int, MatchResult], None] | None = None,
    play: Callable[..., MatchResult] | None = None, progress: bool = False,
    server: str = "real", workers: int = 1, replay_dir: str | Path | None = None,
    ray_address: str | None = None,
) -> LeagueTournamentSummary:
    """Play (or, with ``resume``, finish) league round robin ``name`` in ``db``.

    A new run needs ``teams`` and ``options``; a resume reads the stored definition (teams,
    options, games and seed given with it must match it). ``on_match(k, n, result)`` after the
    k-th stored match of the n this run plays; ``play`` is the match function (default
    ``play_league_match``; tests pass a stand-in); ``progress``: the tournament runner's live
    table; ``server``: "real" or "local" (``LeagueMatchOptions.server``; not part of the
    stored definition, so a run may be resumed on either); ``workers``: matches at once;
    ``replay_dir``: record every match there (``server="local"`` only) and store its
    statistics (``teamenv.analytics.stats``, as the env's tournaments do); ``ray_address``:
    play the matches as Ray tasks (``LeagueBackend``). The database errors (a name that exists, nothing to resume, a definition that
    differs) are the tournament module's ``StoreError``."""
    from teamenv.tournament import run_tournament

    if (teams is None) != (options is None):
        raise LeagueError("give both the teams and the options (or neither, to resume)")
    if teams is None and not resume:
        raise LeagueError("a new league tournament needs its teams and options")
    if replay_dir is not None and server != "local":
        raise LeagueError("league replays need server='local' (the recorder reads the "
                          "simulation)")
    tournament = None if teams is None else league_round_robin(name, teams, options, games,
                                                                seed)
    summary = run_tournament(tournament, db, name=name, resume=resume,
                             backend=LeagueBackend(play, log_dir, on_match, server, workers,
                                                   ray_address),
                             progress=progress, stats=replay_dir is not None,
                             replay_dir=replay_dir)
    return LeagueTournamentSummary(summary.scheduled, summary.played, summary.skipped,
                                   summary.wall_s)
