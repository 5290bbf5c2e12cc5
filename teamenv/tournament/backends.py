"""Execution backends: play MatchTasks in a local process pool (default) or on a Ray cluster.

A backend only plays matches and yields outcomes as they finish; the caller (the runner, in the
parent process) writes them. Each match is independent and deterministic from its task, so
retrying a match, or playing it on another machine, gives the same result.
"""

from __future__ import annotations

import multiprocessing
import os
from collections import deque
from collections.abc import Iterator, Sequence
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass
from typing import Any, Protocol

from teamenv.errors import MissingExtraError
from teamenv.match import MatchResult, play_match
from teamenv.tournament.errors import TournamentConfigError
from teamenv.tournament.schedule import MatchTask

BACKENDS = ("process", "ray")


@dataclass(frozen=True)
class Outcome:
    """A task and either its result or why it could not be played (``error``)."""

    task: MatchTask
    result: MatchResult | None = None
    error: str | None = None


def execute_task(task: MatchTask) -> MatchResult:
    """Play one scheduled match (in whatever process runs it). Team faults become forfeits."""
    return play_match(task.left.name, task.right.name, task.seed, task.options,
                      left_config=task.left.config_dict, right_config=task.right.config_dict,
                      cycle_time_budget_s=task.cycle_time_budget_s,
                      stall_timeout_s=task.stall_timeout_s, replay_path=task.replay_path)


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


class ProcessPoolBackend:
    """A local pool of ``jobs`` worker processes (``spawn`` start method).

    A worker that dies (segfault, ``os._exit``, OOM kill) breaks a ProcessPoolExecutor; the
    pool is then rebuilt and the matches that were in flight are replayed one at a time, each
    in a fresh single-worker pool, so the match that kills its worker is identified and
    reported as an error outcome while the innocent ones are played normally. A stalled team
    is caught inside ``play_match`` by its stall watchdog.
    """

    name = "process"

    def __init__(self, jobs: int | None = None, start_method: str = "spawn") -> None:
        if jobs is not None and (isinstance(jobs, bool) or not isinstance(jobs, int) or jobs < 1):
            raise TournamentConfigError(f"jobs: must be an int >= 1, got {jobs!r}")
        self.workers = jobs or default_jobs()
        self.context = multiprocessing.get_context(start_method)

    def run(self, tasks: Sequence[MatchTask]) -> Iterator[Outcome]:
        pending: deque[MatchTask] = deque(tasks)
        suspects: deque[MatchTask] = deque()
        while pending or suspects:
            while suspects:
                yield self._run_isolated(suspects.popleft())
            if pending:
                yield from self._run_pool(pending, suspects)

    def _run_pool(self, pending: deque[MatchTask], suspects: deque[MatchTask]) -> Iterator[Outcome]:
        """Play from ``pending`` until it is empty or the pool breaks (in-flight -> suspects)."""
        pool = ProcessPoolExecutor(self.workers, mp_context=self.context)
        inflight: dict[Future, MatchTask] = {}
        try:
            while pending or inflight:
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
                _terminate_workers(pool)
            pool.shutdown(wait=not inflight, cancel_futures=True)

    def _run_isolated(self, task: MatchTask) -> Outcome:
        with ProcessPoolExecutor(1, mp_context=self.context) as pool:
            try:
                return Outcome(task, pool.submit(execute_task, task).result())
            except BrokenProcessPool as exc:
                return Outcome(task, error=f"worker process died while playing this match "
                                           f"({exc})")
            except Exception as exc:
                return Outcome(task, error=f"{type(exc).__name__}: {exc}")


def _terminate_workers(pool: ProcessPoolExecutor) -> None:
    """Kill a pool's worker processes (their matches are abandoned, not stored)."""
    for process in list((getattr(pool, "_processes", None) or {}).values()):
        try:
            process.terminate()
        except Exception:  # already gone
            pass


class RayBackend:
    """Play matches as Ray tasks (the ``ray`` extra), on a cluster or a local Ray instance.

    ``address``: a running cluster (``"auto"``, ``"ray://host:10001"``); None starts a local
    instance with ``num_cpus`` CPUs (or joins an already initialised one). Team code must be
    importable on every node. A task whose worker dies is retried ``max_retries`` times by Ray,
    then reported as an error outcome.
    """

    name = "ray"

    def __init__(self, address: str | None = None, num_cpus: int | None = None,
                 max_retries: int = 1) -> None:
        try:
            import ray  # noqa: F401  (the ray extra)
        except ImportError:
            raise MissingExtraError("ray", "ray", "the Ray backend") from None
        self.address = address
        self.num_cpus = num_cpus
        self.max_retries = max_retries
        self.workers = num_cpus or 0

    def run(self, tasks: Sequence[MatchTask]) -> Iterator[Outcome]:
        import ray

        owns = not ray.is_initialized()
        if owns:
            ray.init(address=self.address, num_cpus=self.num_cpus, include_dashboard=False,
                     log_to_driver=False, configure_logging=False)
        remote = ray.remote(num_cpus=1, max_retries=self.max_retries,
                            retry_exceptions=False)(execute_task)
        self.workers = max(1, int(ray.cluster_resources().get("CPU", 1)))
        pending = deque(tasks)
        inflight: dict[Any, MatchTask] = {}
        try:
            while pending or inflight:
                while pending and len(inflight) < 2 * self.workers:
                    task = pending.popleft()
                    inflight[remote.remote(task)] = task
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


def make_backend(backend: str | Backend = "process", jobs: int | None = None,
                 ray_address: str | None = None) -> Backend:
    """A backend by name ("process" or "ray"; ``jobs`` = worker processes / local Ray CPUs)."""
    if not isinstance(backend, str):
        return backend
    if backend == "process":
        return ProcessPoolBackend(jobs)
    if backend == "ray":
        return RayBackend(address=ray_address, num_cpus=jobs if ray_address is None else None)
    raise TournamentConfigError(f"backend: {backend!r}; choose one of {list(BACKENDS)}")
