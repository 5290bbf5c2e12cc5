"""Execution backends: play MatchTasks in a local process pool (default), on a Ray cluster, or
in the calling process (serial).

A backend only plays matches and yields outcomes as they finish; the caller (the runner, in the
parent process) writes them. Each match is independent and deterministic from its task, so
retrying a match, or playing it on another machine, gives the same result.
"""

from __future__ import annotations

import json
import multiprocessing
import os
from collections import deque
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass
from typing import Any, Protocol

from teamenv.errors import MissingExtraError
from teamenv.match import MatchResult, play_match
from teamenv.match_envs import MatchEnvs
from teamenv.teams import resolve_team_class, team_version
from teamenv.tournament.errors import TournamentConfigError
from teamenv.tournament.ray_cluster import LOCAL, init_ray
from teamenv.tournament.schedule import MatchTask

BACKENDS = ("process", "ray", "serial")

# Per-process caches of a worker (a pool process, a Ray worker, or the caller for "serial"):
# filled by its first match with a team, reused by every later one, never shipped anywhere.
_TEAM_VERSIONS: dict[str, str] = {}
#: the envs of the matches this process played, kept for its next ones (``teamenv.match_envs``)
MATCH_ENVS = MatchEnvs()


@dataclass(frozen=True)
class Outcome:
    """A task and either its result or why it could not be played (``error``)."""

    task: MatchTask
    result: MatchResult | None = None
    error: str | None = None


def _team_version(name: str) -> str:
    """The version of team ``name``, looked up (entry points, module) once per process."""
    version = _TEAM_VERSIONS.get(name)
    if version is None:
        version = _TEAM_VERSIONS[name] = team_version(name)
    return version


def warm_up(names: Sequence[str] = ()) -> int:
    """Prepare this process to play matches: import teamenv's match code and each team in
    ``names`` once, and look up their versions; returns the process id. A team that fails to
    load is left for its match to report (it forfeits or fails there, as it would cold)."""
    for name in names:
        try:
            resolve_team_class(name)
            _team_version(name)
        except Exception:  # reported by the match that uses the team
            pass
    return os.getpid()


def execute_task(task: MatchTask) -> MatchResult:
    """Play one scheduled match (in whatever process runs it). Team faults become forfeits.

    The process keeps its envs between matches (``MATCH_ENVS``): a match on a kept env is the
    match on a fresh one, bit for bit (``reset`` restores everything a match depends on), so a
    match still depends on its task only, never on what its worker played before.
    """
    left, right = task.left.name, task.right.name
    return play_match(left, right, task.seed, task.options,
                      left_config=task.left.config_dict, right_config=task.right.config_dict,
                      cycle_time_budget_s=task.cycle_time_budget_s,
                      stall_timeout_s=task.stall_timeout_s, replay_path=task.replay_path,
                      team_versions=(_team_version(left), _team_version(right)),
                      envs=MATCH_ENVS)


def team_names(tasks: Sequence[MatchTask]) -> tuple[str, ...]:
    """The distinct team names (registered or ``module:Class``) that ``tasks`` play."""
    return tuple(sorted({spec.name for task in tasks for spec in (task.left, task.right)}))


class Backend(Protocol):
    """Plays tasks; yields one Outcome per task, in completion order."""

    name: str
    workers: int

    def run(self, tasks: Sequence[MatchTask]) -> Iterator[Outcome]:
        ...


def default_jobs() -> int:
    """Worker processes to use by default: every core this process may run on."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # not Linux
        return max(1, os.cpu_count() or 1)


def default_start_method() -> str:
    """``forkserver`` where the platform has it (Linux, macOS), else ``spawn``."""
    return "forkserver" if "forkserver" in multiprocessing.get_all_start_methods() else "spawn"


# The fork server imports these once, before it forks any worker: the caller's main module
# (as spawn would, in every worker) and teamenv.tournament.preload, which imports the match
# code (numpy, scipy, pymunk, the env) and the teams listed in $TEAMENV_TOURNAMENT_TEAMS.
PRELOAD_ENV = "TEAMENV_TOURNAMENT_TEAMS"
_FORKSERVER_PRELOAD = ["__main__", "teamenv.tournament.preload"]


def start_forkserver(names: Sequence[str] = ()) -> None:
    """Start this process's fork server unless it runs already, preloading the match code and
    the teams ``names`` (in the background: a fork request waits for it). Later tournaments in
    the same process reuse the server; their other teams are imported by each worker."""
    from multiprocessing import forkserver

    forkserver.set_forkserver_preload(_FORKSERVER_PRELOAD)
    old = os.environ.get(PRELOAD_ENV)
    os.environ[PRELOAD_ENV] = json.dumps(sorted(names))  # read by the server only
    try:
        forkserver.ensure_running()
    finally:
        if old is None:
            os.environ.pop(PRELOAD_ENV, None)
        else:
            os.environ[PRELOAD_ENV] = old


class ProcessPoolBackend:
    """A local pool of ``jobs`` worker processes, started once per run and reused for every
    match.

    Workers come from a fork server (``forkserver`` start method where available, else
    ``spawn``) that has imported teamenv's match code and the tournament's teams once (see
    ``start_forkserver``), so a worker starts in milliseconds instead of importing numpy,
    scipy, pymunk and the teams again; each worker looks its teams up once (``warm_up``,
    which imports any team the server did not) before its first match. The fork server lives
    as long as the calling process, like the modules that process imported: team code edited
    on disk after a process's first tournament is seen by a new process (the CLI), not by later
    tournaments of the same one (the parent has the old code too; versions stay consistent).

    A worker that dies (segfault, ``os._exit``, OOM kill) breaks a ProcessPoolExecutor; the
    pool is then rebuilt and the matches that were in flight are replayed one at a time, each
    in a fresh single-worker pool, so the match that kills its worker is identified and
    reported as an error outcome while the innocent ones are played normally. A stalled team
    is caught inside ``play_match`` by its stall watchdog.
    """

    name = "process"

    def __init__(self, jobs: int | None = None, start_method: str | None = None) -> None:
        if jobs is not None and (isinstance(jobs, bool) or not isinstance(jobs, int) or jobs < 1):
            raise TournamentConfigError(f"jobs: must be an int >= 1, got {jobs!r}")
        self.workers = jobs or default_jobs()
        self.start_method = start_method or default_start_method()
        self.context = multiprocessing.get_context(self.start_method)

    def prepare(self, names: Sequence[str] = ()) -> None:
        """Get ready to start workers (the runner calls it before it validates the teams, so
        the two overlap): start the fork server, which imports the match code and ``names``."""
        if self.start_method == "forkserver":
            start_forkserver(names)

    def start_pool(self, names: Sequence[str] = (), workers: int | None = None
                   ) -> ProcessPoolExecutor:
        """A pool of ``workers`` (default: ``self.workers``) processes that import the teams
        ``names`` once each, when they start."""
        self.prepare(names)
        return ProcessPoolExecutor(workers or self.workers, mp_context=self.context,
                                   initializer=warm_up, initargs=(tuple(names),))

    def run(self, tasks: Sequence[MatchTask]) -> Iterator[Outcome]:
        pending: deque[MatchTask] = deque(tasks)
        suspects: deque[MatchTask] = deque()
        names = team_names(tasks)
        while pending or suspects:
            while suspects:
                yield self._run_isolated(suspects.popleft())
            if pending:
                yield from self._run_pool(pending, suspects, names)

    def _run_pool(self, pending: deque[MatchTask], suspects: deque[MatchTask],
                  names: tuple[str, ...]) -> Iterator[Outcome]:
        """Play from ``pending`` until it is empty or the pool breaks (in-flight -> suspects)."""
        pool = self.start_pool(names, min(self.workers, len(pending)))
        inflight: dict[Future, MatchTask] = {}
        try:
            while pending or inflight:
                # Two per worker in flight: a worker finds its next match queued when it ends one.
                while pending and len(inflight) < 2 * self.workers:
                    task = pending.popleft()
                    inflight[pool.submit(execute_task, task)] = task
                done, _ = wait(inflight, return_when=FIRST_COMPLETED)
                broken = False
                for fut in sorted(done, key=lambda f: inflight[f].index):
                    task = inflight.pop(fut)
                    try:
                        outcome = Outcome(task, fut.result())
                    except BrokenProcessPool:
                        broken = True
                        suspects.append(task)
                        continue
                    except Exception as exc:  # play_match itself failed: not a team fault
                        outcome = Outcome(task, error=f"{type(exc).__name__}: {exc}")
                    yield outcome
                if broken:
                    for fut, task in sorted(inflight.items(), key=lambda kv: kv[1].index):
                        fut.cancel()
                        suspects.append(task)
                    inflight.clear()
                    return
        finally:
            if inflight:  # interrupted (Ctrl-C, generator closed) or broken: stop workers now
                terminate_workers(pool)
            pool.shutdown(wait=not inflight, cancel_futures=True)

    def _run_isolated(self, task: MatchTask) -> Outcome:
        with self.start_pool((task.left.name, task.right.name), 1) as pool:
            try:
                return Outcome(task, pool.submit(execute_task, task).result())
            except BrokenProcessPool as exc:
                return Outcome(task, error=f"worker process died while playing this match "
                                           f"({exc})")
            except Exception as exc:
                return Outcome(task, error=f"{type(exc).__name__}: {exc}")


def terminate_workers(pool: ProcessPoolExecutor) -> None:
    """Kill a pool's worker processes (their matches are abandoned, not stored)."""
    for process in list((getattr(pool, "_processes", None) or {}).values()):
        try:
            process.terminate()
        except Exception:  # already gone
            pass


class SerialBackend:
    """Play every match in the calling process, one after another (no worker, no pool).

    For debugging (a debugger or profiler sees the match) and as a baseline; it has no fault
    isolation: a team that kills its process (segfault, ``os._exit``) ends the run (matches
    stored so far stay stored; ``--resume`` continues).
    """

    name = "serial"
    workers = 1

    def run(self, tasks: Sequence[MatchTask]) -> Iterator[Outcome]:
        warm_up(team_names(tasks))
        for task in tasks:
            try:
                result = execute_task(task)
            except Exception as exc:  # play_match itself failed: not a team fault
                yield Outcome(task, error=f"{type(exc).__name__}: {exc}")
                continue
            yield Outcome(task, result)


class RayBackend:
    """Play matches as Ray tasks (the ``ray`` extra), on a cluster or a local Ray instance.

    ``address``: a running cluster to join (``"auto"``, ``"HOST:PORT"``,
    ``"ray://host:10001"``); None (or ``"local"``) starts a private local instance with
    ``num_cpus`` CPUs, whatever other Ray cluster runs on the machine (see
    ``teamenv.ray_cluster``). If this process already initialised Ray, that instance is used. Team code must be
    importable on every node. A task whose worker dies is retried ``max_retries`` times by Ray,
    then reported as an error outcome. Ray reuses its worker processes, so each imports the
    teams and looks up their versions once.

    ``worker_niceness``: the nice value of the workers of a local instance this backend starts
    (Ray's default is 15, which lets any other process on the machine starve the matches:
    they ran several times slower than in a plain process on a busy machine); None keeps
    Ray's default. Not applied to a cluster or to an instance that is already running.
    """

    name = "ray"

    def __init__(self, address: str | None = None, num_cpus: int | None = None,
                 max_retries: int = 1, worker_niceness: int | None = 0,
                 runner: Callable[[MatchTask], MatchResult] | None = None) -> None:
        try:
            import ray  # noqa: F401  (the ray extra)
        except ImportError:
            raise MissingExtraError("ray", "ray", "the Ray backend") from None
        #: what a Ray task runs for one task (default: the env's ``execute_task``; the league
        #: backend passes its match function)
        self.runner = runner or execute_task
        self.address = address
        self.num_cpus = num_cpus
        self.max_retries = max_retries
        self.worker_niceness = worker_niceness
        self.workers = num_cpus or 0

    def run(self, tasks: Sequence[MatchTask]) -> Iterator[Outcome]:
        import ray

        owns = not ray.is_initialized()
        if owns:
            niceness = None if self.worker_niceness is None else \
                {"worker_niceness": int(self.worker_niceness)}
            init_ray(self.address, self.num_cpus, local_system_config=niceness,
                     include_dashboard=False, log_to_driver=False, configure_logging=False)
        remote = ray.remote(num_cpus=1, max_retries=self.max_retries,
                            retry_exceptions=False)(_run_task)
        self.workers = max(1, int(ray.cluster_resources().get("CPU", 1)))
        pending = deque(tasks)
        inflight: dict[Any, MatchTask] = {}
        try:
            while pending or inflight:
                while pending and len(inflight) < 2 * self.workers:
                    task = pending.popleft()
                    inflight[remote.remote(self.runner, task)] = task
                ready, _ = ray.wait(list(inflight), num_returns=1)
                for ref in ready:
                    task = inflight.pop(ref)
                    try:
                        outcome = Outcome(task, ray.get(ref))
                    except ray.exceptions.RayError as exc:
                        outcome = Outcome(task, error=f"{type(exc).__name__}: {exc}")
                    yield outcome
        finally:
            for ref in inflight:
                ray.cancel(ref, force=True)
            if owns:
                ray.shutdown()


def _run_task(runner: Callable[[MatchTask], MatchResult], task: MatchTask) -> MatchResult:
    """A Ray task: ``runner(task)`` (``ray.remote`` takes functions, not partials)."""
    return runner(task)


def make_backend(backend: str | Backend = "process", jobs: int | None = None,
                 ray_address: str | None = None) -> Backend:
    """A backend by name ("process", "ray" or "serial"; ``jobs`` = worker processes / local
    Ray CPUs; "serial" plays in this process and ignores ``jobs``)."""
    if not isinstance(backend, str):
        return backend
    if backend == "process":
        return ProcessPoolBackend(jobs)
    if backend == "ray":
        local = ray_address in (None, LOCAL)
        return RayBackend(address=None if local else ray_address,
                          num_cpus=jobs if local else None)
    if backend == "serial":
        return SerialBackend()
    raise TournamentConfigError(f"backend: {backend!r}; choose one of {list(BACKENDS)}")
