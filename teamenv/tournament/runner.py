"""run_tournament: validate, schedule, play what is missing, store each match as it ends."""

from __future__ import annotations

import tempfile
import time
from collections.abc import Iterator
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from teamenv.tournament.backends import Backend, make_backend
from teamenv.tournament.errors import StoreError, TournamentConfigError
from teamenv.tournament.schedule import MatchTask, Tournament
from teamenv.tournament.spec import validate_specs
from teamenv.tournament.store import ResultStore
from teamenv.tournament.table import league_table, rich_table

TABLE_REFRESH_S = 0.5  # the live league table is redrawn at most this often (seconds)


@dataclass(frozen=True)
class TournamentSummary:
    """What a call to run_tournament did (times in seconds)."""

    tournament: Tournament
    db_path: Path
    tournament_id: int
    scheduled: int          # matches in the schedule
    stored: int             # matches in the database after this call
    skipped: int            # already stored when this call started (resume)
    played: int             # matches played and stored by this call
    failures: tuple[tuple[int, str], ...] = ()  # (schedule index, error) still missing
    wall_s: float = 0.0     # wall time of the playing phase
    db_write_s: float = 0.0  # wall time spent writing matches to the database
    backend: str = "process"
    workers: int = 1
    forfeits: dict[str, int] = field(default_factory=dict)  # reason -> count (this call)
    separated: tuple[str, ...] = ()  # pairings left unfinished: already separated

    @property
    def complete(self) -> bool:
        return self.stored == self.scheduled

    @property
    def matches_per_minute(self) -> float:
        return 60.0 * self.played / self.wall_s if self.wall_s > 0 else 0.0

    def describe(self) -> str:
        missing = self.scheduled - self.stored
        if self.complete:
            state = "complete"
        elif self.separated and not self.failures:
            # only pairings that stopped early lack matches: the run did what it was asked
            state = (f"done ({missing} scheduled matches not needed: their pairings were "
                     "separated; --resume without --stop-when-separated plays them)")
        else:
            state = f"incomplete ({missing} missing; rerun with --resume)"
        text = (f"tournament {self.tournament.name!r}: {self.stored}/{self.scheduled} matches "
                f"stored, {state}; played {self.played} now ({self.skipped} were stored) in "
                f"{self.wall_s:.1f} s on {self.workers} {self.backend} worker(s), "
                f"{self.matches_per_minute:.1f} matches/min")
        for idx, err in self.failures:
            text += f"\n  match #{idx} could not be played: {err}"
        for pairing in self.separated:
            text += f"\n  {pairing}: stopped early, separated at 95 %"
        return text


@dataclass(frozen=True)
class _Row:
    left_team: str
    right_team: str
    left_official: int
    right_official: int
    forfeit_side: str | None
    forfeit_reason: str | None


def run_tournament(
    tournament: Tournament | None, db: str | Path, *, name: str | None = None,
    resume: bool = False, backend: str | Backend = "process", jobs: int | None = None,
    ray_address: str | None = None, replay_dir: str | Path | None = None,
    progress: bool = True, console: Any = None, synchronous: str = "FULL",
    stats: bool = True, stop_when_separated: str | None = None,
) -> TournamentSummary:
    """Play a tournament (or the missing part of one) and store every match in ``db``.

    ``tournament``: the definition; None with ``resume=True`` reloads it from ``db`` (by
    ``name``, or the only tournament there). Without ``resume`` the name must be new in ``db``.
    With ``resume`` a given definition must equal the stored one (or is started when it is not
    stored yet), and only matches not yet stored are played. Every team spec and the match options are checked (each team is built
    once) before anything runs. ``backend``: "process" (``jobs`` workers, default all cores),
    "ray" (``jobs`` local CPUs, or the cluster at ``ray_address``) or a Backend object.
    ``replay_dir``: record a replay (.npz) of every match there. ``progress``: show a rich
    progress bar and live league table on ``console`` (a rich Console; default stdout).
    Ctrl-C stops cleanly (matches already stored stay stored) and re-raises KeyboardInterrupt.
    ``stats``: store each match's per-team statistics (``teamenv.analytics``) in the
    ``team_stats`` table; matches are recorded to a temporary replay for it when there is no
    ``replay_dir`` (the replay is deleted once its statistics are stored).
    ``stop_when_separated``: a ranking metric (``teamenv.analytics.ranking.RANK_METRICS``);
    matches are then played round by round and a pairing whose stored matches already separate its teams at
    95 % (``teamenv.analytics.ranking.separated_pairings``) plays no further rounds.
    """
    if tournament is None and not resume:
        raise TournamentConfigError("run_tournament: give a tournament definition, or "
                                    "resume=True to continue one stored in the database")
    if tournament is not None and not isinstance(tournament, Tournament):
        raise TournamentConfigError(f"run_tournament: expected a Tournament, got {tournament!r}")
    store = ResultStore(db, synchronous=synchronous)
    try:
        with tempfile.TemporaryDirectory(prefix="teamenv-stats-") as scratch:
            return _run(store, tournament, name, resume, backend, jobs, ray_address, replay_dir,
                        progress, console, Path(scratch) if stats else None,
                        stop_when_separated)
    finally:
        store.close()


def _run(store: ResultStore, tournament: Tournament | None, name: str | None, resume: bool,
         backend: str | Backend, jobs: int | None, ray_address: str | None,
         replay_dir: str | Path | None, progress: bool, console: Any,
         stats_dir: Path | None = None, stop_when_separated: str | None = None
         ) -> TournamentSummary:
    lookup = tournament.name if tournament is not None else name
    found = store.find_tournament(lookup) if (resume or lookup is not None) else None
    if found is not None and not resume:
        raise StoreError(f"database {str(store.path)!r}: tournament {lookup!r} already exists; "
                         "resume it (--resume) or choose another name")
    if found is None and tournament is None:
        what = f"tournament {lookup!r}" if lookup else "tournament"
        raise StoreError(f"database {str(store.path)!r}: no {what} to resume; it holds "
                         f"{store.tournament_names()} (give the teams to start one)")
    if found is not None and tournament is not None and \
            found[1].definition_hash() != tournament.definition_hash():
        raise StoreError(_definition_mismatch(found[1], tournament))
    if found is not None:
        tournament = found[1]
    assert tournament is not None
    runner = make_backend(backend, jobs, ray_address)  # a bad backend fails before anything
    prepare = getattr(runner, "prepare", None)
    if prepare is not None:  # e.g. the pool's fork server imports the teams meanwhile
        prepare(sorted({spec.name for spec in tournament.all_teams}))
    versions = validate_specs(tournament.all_teams, tournament.options)
    if found is None:
        tid = store.create_tournament(tournament, versions)
    else:
        tid = found[0]
        stored_versions = store.team_versions(tid)
        changed = {t: (stored_versions.get(t), v) for t, v in versions.items()
                   if stored_versions.get(t) != v}
        if changed:
            raise StoreError(f"tournament {tournament.name!r}: team versions changed since it "
                             f"started {changed} (stored, now); results would mix versions — "
                             "start a new tournament")
    schedule = tournament.schedule()
    done = store.completed_indices(tid)
    todo = [t for t in schedule if t.index not in done]
    if replay_dir is not None:
        todo = [_with_replay(t, Path(replay_dir), tournament.name) for t in todo]
    elif stats_dir is not None:  # a scratch replay per match, only for its statistics
        todo = [_with_replay(t, stats_dir, tournament.name) for t in todo]
    rows = [_Row(r.left_team, r.right_team, r.left_official, r.right_official, r.forfeit_side,
                 r.forfeit_reason) for r in store.matches(tid)]
    teams = [t.label for t in tournament.all_teams]
    played = 0
    db_write_s = 0.0
    forfeits: dict[str, int] = {}
    display = _Display(tournament, len(schedule), len(done), progress, console, teams, rows)
    start = time.perf_counter()
    if stop_when_separated is not None:
        from teamenv.analytics.ranking import check_metric

        outcomes = _by_round(runner, todo, store, tid, check_metric(stop_when_separated))
    else:
        outcomes = runner.run(todo)
    try:
        with display:
            for outcome in outcomes:
                t0 = time.perf_counter()
                if outcome.result is None:
                    store.record_failure(tid, outcome.task, outcome.error or "unknown error")
                    display.note(f"match #{outcome.task.index} failed: {outcome.error}")
                    continue
                res = outcome.result
                scratch = replay_dir is None and outcome.task.replay_path is not None
                task = replace(outcome.task, replay_path=None) if scratch else outcome.task
                stored = store.record_match(tid, task, res)
                if stored and stats_dir is not None:
                    _store_stats(store, tid, outcome.task, display)
                if scratch:
                    Path(outcome.task.replay_path).unlink(missing_ok=True)
                db_write_s += time.perf_counter() - t0
                if stored:
                    played += 1
                    official = res.official_score
                    rows.append(_Row(outcome.task.left.label, outcome.task.right.label,
                                     official[0], official[1],
                                     res.forfeit.side if res.forfeit else None,
                                     res.forfeit.reason if res.forfeit else None))
                    if res.forfeit:
                        forfeits[res.forfeit.reason] = forfeits.get(res.forfeit.reason, 0) + 1
                display.advance(outcome.task, res)
    except KeyboardInterrupt:
        display.console_print(f"interrupted: {store.count_matches(tid)}/{len(schedule)} matches "
                              f"stored in {str(store.path)!r}; continue with --resume")
        raise
    finally:
        outcomes.close()
    wall = time.perf_counter() - start
    separated: tuple[str, ...] = ()
    if stop_when_separated is not None:
        from teamenv.analytics.ranking import separated_pairings

        stored_now = store.completed_indices(tid)
        unfinished = {t.pairing for t in schedule if t.index not in stored_now}
        separated = tuple(sorted(unfinished & separated_pairings(
            store.matches(tid), store.team_stats(tid), stop_when_separated)))
    return TournamentSummary(
        tournament=tournament, db_path=store.path, tournament_id=tid, scheduled=len(schedule),
        stored=store.count_matches(tid), skipped=len(done), played=played,
        failures=tuple(store.failures(tid)), wall_s=wall, db_write_s=db_write_s,
        backend=getattr(runner, "name", type(runner).__name__),
        workers=getattr(runner, "workers", 1), forfeits=forfeits, separated=separated)


def _by_round(runner: Backend, todo: list[MatchTask], store: ResultStore, tid: int,
              metric: str) -> Iterator[Any]:
    """Outcomes of ``todo`` round by round, leaving out the pairings whose stored matches
    already separate their teams on ``metric`` (checked before each round)."""
    from teamenv.analytics.ranking import separated_pairings

    for number in sorted({t.round for t in todo}):
        done = separated_pairings(store.matches(tid), store.team_stats(tid), metric)
        batch = [t for t in todo if t.round == number and t.pairing not in done]
        if not batch:
            continue
        outcomes = runner.run(batch)
        try:
            yield from outcomes
        finally:
            outcomes.close()


def _store_stats(store: ResultStore, tid: int, task: MatchTask, display: _Display) -> None:
    """Per-team statistics of a stored match from its replay (a match without a readable
    replay, e.g. played on another machine of a cluster, simply has none)."""
    from teamenv.analytics.stats import replay_stats

    if task.replay_path is None or not Path(task.replay_path).exists():
        return
    try:
        stats = replay_stats(task.replay_path)
    except Exception as exc:  # statistics are extra: a failure must not stop the tournament
        display.note(f"match #{task.index}: no statistics: {type(exc).__name__}: {exc}")
        return
    store.record_team_stats(tid, task.index, stats)


def _with_replay(task: MatchTask, replay_dir: Path, name: str) -> MatchTask:
    safe = "".join(c if c.isalnum() or c in "-_" else "_" for c in name)
    path = replay_dir / f"{safe}-{task.index:05d}-{task.key[:10]}.npz"
    return replace(task, replay_path=str(path))


def _definition_mismatch(stored: Tournament, given: Tournament) -> str:
    a, b = stored.to_json(), given.to_json()
    diff = {k: (a.get(k), b.get(k)) for k in sorted(set(a) | set(b)) if a.get(k) != b.get(k)}
    return (f"tournament {given.name!r}: the definition differs from the stored one "
            f"(field: (stored, given)) {diff}; resume without changing it, or use a new name")


class _Display:
    """rich progress bar + live league table (a no-op when ``enabled`` is False)."""

    def __init__(self, tournament: Tournament, total: int, done: int, enabled: bool,
                 console: Any, teams: list[str], rows: list[_Row]) -> None:
        self.enabled = enabled
        self.teams = teams
        self.rows = rows
        self.title = f"{tournament.name} ({tournament.format.replace('_', ' ')})"
        self._last = 0.0
        from rich.console import Console, Group

        self.console = console or Console(stderr=not enabled)
        if not enabled:
            return
        from rich.live import Live
        from rich.progress import (
            BarColumn,
            MofNCompleteColumn,
            Progress,
            TextColumn,
            TimeElapsedColumn,
            TimeRemainingColumn,
        )

        self.progress = Progress(TextColumn("[bold]{task.description}"), BarColumn(),
                                 MofNCompleteColumn(), TimeElapsedColumn(), TimeRemainingColumn(),
                                 TextColumn("{task.fields[last]}"), console=self.console)
        self.task_id = self.progress.add_task("matches", total=total, completed=done, last="")
        self._group = Group
        self.live = Live(self._renderable(), console=self.console, refresh_per_second=4,
                         transient=False)

    def _renderable(self) -> Any:
        table = rich_table(league_table(self.rows, self.teams), title=self.title)
        return self._group(table, self.progress)

    def __enter__(self) -> _Display:
        if self.enabled:
            self.live.__enter__()
        return self

    def __exit__(self, *exc: Any) -> None:
        if self.enabled:
            self.live.update(self._renderable())
            self.live.__exit__(*exc)
            if not self.console.is_terminal:
                self.console.print()

    def advance(self, task: MatchTask, result: Any) -> None:
        if not self.enabled:
            return
        last = f"{task.left.label} {result.score[0]}-{result.score[1]} {task.right.label}"
        if result.forfeit:
            last += f" (forfeit {result.forfeit.side}: {result.forfeit.reason})"
        self.progress.update(self.task_id, advance=1, last=last)
        now = time.monotonic()
        if now - self._last >= TABLE_REFRESH_S:
            self._last = now
            self.live.update(self._renderable())

    def note(self, text: str) -> None:
        if self.enabled:
            self.console.print(text)

    def console_print(self, text: str) -> None:
        self.console.print(text)
