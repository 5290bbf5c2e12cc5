"""The CMA-ES loop (the ``cma`` package): ask, score, tell, checkpointing every generation.

The search runs in the unit cube of a ``SearchSpace`` (bounds [0, 1] through cma's
``BoundTransform``), starts at the config's defaults with step size ``sigma0`` (a fraction of
every parameter's range) and *maximizes* the evaluator's fitness. cma draws its samples from
our own seeded ``numpy.random.Generator`` (its ``randn`` option; ``seed=nan`` so cma never
seeds numpy's global state), and cma's integer handling is not used because it draws from the
global state: integers and choices are rounded when decoded. With the same seed and the same
fitness values, the search is the same, interrupted and resumed or not.

Resume: every generation's candidates are stored when they are asked, its scores when they
are known. A resumed run starts a fresh CMA-ES with the same seed and replays the stored
generations (ask, check the candidates are the stored ones, tell the stored scores), then
scores the generation that was running (an evaluator playing matches finds its stored ones),
so the continuation is the uninterrupted search bit for bit. (Replaying rather than pickling
cma's object: cma keys its solutions by Python's per-process salted hash, so a pickled state
does not resume identically in another process.)
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Protocol

import numpy as np

from paramkit.checks import check_fields, in_range, non_negative
from teamenv.errors import ConfigError
from teamenv.optimize.checkpoint import CheckpointStore, Generation, OptimizeError
from teamenv.search_space import SearchSpace

DEFINITION_FORMAT = 1


@dataclass(frozen=True)
class CandidateScore:
    """A candidate's fitness (higher is better) and what it is made of.

    ``goal_difference``: mean official goal difference per match (None for a synthetic
    fitness); ``fine``: the mean of the finer match metric (``territory`` or ``xg``, see
    ``teamenv.optimize.tournament_fitness``), None without one; ``matches``: matches it was
    scored on.
    """

    fitness: float
    goal_difference: float | None = None
    fine: float | None = None
    matches: int = 0

    def to_json(self) -> dict[str, Any]:
        return {"fitness": self.fitness, "goal_difference": self.goal_difference,
                "fine": self.fine, "matches": self.matches}


class Reporter(Protocol):
    """Progress of a run (a rich progress bar in the CLI; a no-op by default)."""

    def generation_started(self, generation: int, generations: int, matches: int,
                           done: int) -> None: ...

    def match_done(self, text: str) -> None: ...

    def generation_done(self, generation: int, scores: Sequence[CandidateScore]) -> None: ...


class QuietReporter:
    """Reports nothing."""

    def generation_started(self, generation: int, generations: int, matches: int,
                           done: int) -> None:
        pass

    def match_done(self, text: str) -> None:
        pass

    def generation_done(self, generation: int, scores: Sequence[CandidateScore]) -> None:
        pass


class Evaluator(Protocol):
    """Scores the candidates (config overrides) of a generation; must be deterministic given
    the generation and the configs (that is what makes resume exact)."""

    def definition(self) -> dict[str, Any]:
        """A JSON-able description of everything that changes a score (stored, compared on
        resume)."""

    def evaluate(self, generation: int, configs: list[dict[str, Any]],
                 reporter: Reporter) -> list[CandidateScore]: ...


class SearchSettingsError(OptimizeError, ConfigError):
    """A ``SearchSettings`` value is out of range or of the wrong type."""


@dataclass(frozen=True)
class SearchSettings:
    """CMA-ES settings: ``seed`` of its sampler, ``popsize`` (None: cma's default
    4 + 3 ln n), ``sigma0`` (initial step, a fraction of each parameter's range)."""

    seed: int = field(default=0, metadata=non_negative())
    popsize: int | None = field(default=None, metadata=in_range(2))
    sigma0: float = field(default=0.2, metadata=in_range(0.0, 1.0, low_open=True))

    def __post_init__(self) -> None:
        check_fields(self, SearchSettingsError)

    def to_json(self) -> dict[str, Any]:
        return {"seed": self.seed, "popsize": self.popsize, "sigma0": self.sigma0}


@dataclass(frozen=True)
class OptimizeResult:
    """What a run has done so far (all its generations, this call's and earlier ones)."""

    name: str
    space: SearchSpace
    definition: dict[str, Any]
    generations: list[Generation]
    recommended: dict[str, Any]   # the decoded distribution mean after the last tell
    wall_s: float                 # this call
    stop: dict[str, Any] = field(default_factory=dict)  # cma's termination reasons, if any

    @property
    def matches(self) -> int:
        return sum(s["matches"] for g in self.generations if g.scores for s in g.scores)

    def best_observed(self) -> tuple[int, dict[str, Any], dict[str, Any]] | None:
        """(generation, config, score) of the best scored candidate (noisy: a lucky draw)."""
        best = None
        for g in self.generations:
            for x, s in zip(g.candidates, g.scores or (), strict=False):
                if best is None or s["fitness"] > best[2]["fitness"]:
                    best = (g.generation, self.space.decode(x), s)
        return best


class _Normals:
    """cma's ``randn(lam, n)``, drawn from our own seeded generator."""

    def __init__(self, seed: int) -> None:
        self.rng = np.random.default_rng(seed)

    def __call__(self, *shape: int) -> np.ndarray:
        return self.rng.standard_normal(shape)


def new_strategy(space: SearchSpace, settings: SearchSettings) -> Any:
    """A fresh ``cma.CMAEvolutionStrategy`` over ``space``'s unit cube, started at the defaults."""
    import cma

    options: dict[str, Any] = {
        "randn": _Normals(settings.seed), "seed": math.nan, "bounds": [0.0, 1.0],
        "verbose": -9, "verb_log": 0, "verb_disp": 0, "verb_filenameprefix": "",
        # noisy, coarse fitness (goal differences): equal values for a few generations are
        # no reason to stop; the run's length is the caller's --generations
        "maxiter": math.inf, "tolfun": 0.0, "tolfunhist": 0.0, "tolflatfitness": 5,
    }
    if settings.popsize is not None:
        options["popsize"] = settings.popsize
    if space.dimension == 1:  # cma needs n >= 2: a second, ignored coordinate
        raise OptimizeError("search space: CMA-ES needs at least two parameters; add one "
                            "(--params) or give a wider search")
    return cma.CMAEvolutionStrategy(space.start().tolist(), settings.sigma0, options)


def optimize(name: str, db: str | Path, space: SearchSpace | None, evaluator: Evaluator,
             generations: int, settings: SearchSettings | None = None, *, resume: bool = False,
             reporter: Reporter | None = None,
             extra_definition: dict[str, Any] | None = None,
             after_generation: Callable[[OptimizeResult], None] | None = None
             ) -> OptimizeResult:
    """Run (or continue) the CMA-ES search ``name`` until ``generations`` are scored.

    ``space`` None with ``resume``: the stored one. A new ``name`` must not exist in ``db``
    unless ``resume``; a resumed run must have the same definition (space, settings,
    evaluator), and may be given more ``generations`` than it was started with. Stops early
    when cma's own termination criteria fire (e.g. the step size collapsed).
    ``after_generation``: called after each told generation (e.g. to redraw the plot).
    """
    if isinstance(generations, bool) or not isinstance(generations, int) or generations < 1:
        raise OptimizeError(f"generations: must be an int >= 1, got {generations!r}")
    reporter = reporter or QuietReporter()
    start = time.perf_counter()
    with CheckpointStore(db) as store:
        found = store.find_run(name)
        if found is not None and not resume:
            raise OptimizeError(f"database {str(db)!r}: optimization run {name!r} already "
                                "exists; continue it (--resume) or choose another name")
        if found is None and space is None:
            raise OptimizeError(f"database {str(db)!r}: no optimization run {name!r} to "
                                f"resume; it holds {store.run_names()}")
        if found is not None:
            stored_space = SearchSpace.from_json(found[1]["space"])
            space = stored_space if space is None else space
        assert space is not None
        settings = settings or (SearchSettings(**found[1]["settings"]) if found else
                                SearchSettings())
        definition = {"format": DEFINITION_FORMAT, "space": space.to_json(),
                      "settings": settings.to_json(), "evaluator": evaluator.definition(),
                      **(extra_definition or {})}
        definition = _json_round_trip(definition)
        if found is None:
            run_id = store.create_run(name, definition)
        else:
            run_id = found[0]
            if found[1] != definition:
                raise OptimizeError(_mismatch(name, found[1], definition))
        stop = _continue(store, run_id, name, space, settings, evaluator, generations,
                         reporter, definition, start, after_generation)
        return _result(store, run_id, name, space, definition, start, stop)


def _continue(store: CheckpointStore, run_id: int, name: str, space: SearchSpace,
              settings: SearchSettings, evaluator: Evaluator, generations: int,
              reporter: Reporter, definition: dict[str, Any], start: float,
              after_generation: Callable[[OptimizeResult], None] | None) -> dict[str, Any]:
    es = new_strategy(space, settings)
    g, candidates = 0, None
    for stored in store.generations(run_id):  # replay the stored search in this process
        g, candidates = stored.generation, [np.asarray(x, np.float64) for x in es.ask()]
        if [x.tolist() for x in candidates] != stored.candidates:
            raise OptimizeError(f"optimization run {name!r}: replaying its stored generations "
                                f"asks other candidates at generation {g} than it stored "
                                "(another cma version?); start a new run")
        if not stored.told:  # the generation that was running: score it now
            break
        es.tell(candidates, [-s["fitness"] for s in stored.scores])
        candidates = None
        g += 1
    if candidates is None:
        if g > 0 and (es.stop() or g >= generations):
            return dict(es.stop())
        candidates = _ask(store, run_id, g, es)
    while True:
        t0 = time.perf_counter()
        configs = [space.decode(x) for x in candidates]
        reporter.generation_started(g, generations, 0, 0)
        scores = evaluator.evaluate(g, configs, reporter)
        if len(scores) != len(configs) or not all(math.isfinite(s.fitness) for s in scores):
            raise OptimizeError(f"generation {g}: the evaluator returned {scores!r} for "
                                f"{len(configs)} candidates (one finite fitness each expected)")
        es.tell(candidates, [-s.fitness for s in scores])  # cma minimizes
        # the mean in the unit cube: cma's own ``es.mean`` lives in the unbounded space of its
        # BoundTransform; ``xfavorite`` is that mean mapped into the bounds
        store.save_told(run_id, g, [s.to_json() for s in scores],
                        list(map(float, es.result.xfavorite)), float(es.sigma),
                        time.perf_counter() - t0)
        reporter.generation_done(g, scores)
        if after_generation is not None:
            after_generation(_result(store, run_id, name, space, definition, start, {}))
        if es.stop() or g + 1 >= generations:
            return dict(es.stop())
        g, candidates = g + 1, _ask(store, run_id, g + 1, es)


def _ask(store: CheckpointStore, run_id: int, generation: int, es: Any) -> list[np.ndarray]:
    candidates = [np.asarray(x, dtype=np.float64) for x in es.ask()]
    store.save_asked(run_id, generation, [x.tolist() for x in candidates])
    return candidates


def _result(store: CheckpointStore, run_id: int, name: str, space: SearchSpace,
            definition: dict[str, Any], start: float, stop: dict[str, Any]) -> OptimizeResult:
    gens = store.generations(run_id)
    told = [g for g in gens if g.told]
    mean = told[-1].mean if told else space.start().tolist()
    return OptimizeResult(name, space, definition, gens, space.decode(mean),
                          time.perf_counter() - start, stop)


def load_result(db: str | Path, name: str) -> OptimizeResult:
    """The stored state of run ``name`` (no search is run)."""
    with CheckpointStore(db) as store:
        found = store.find_run(name)
        if found is None:
            raise OptimizeError(f"database {str(db)!r}: no optimization run {name!r}; it holds "
                                f"{store.run_names()}")
        space = SearchSpace.from_json(found[1]["space"])
        return _result(store, found[0], name, space, found[1], time.perf_counter(), {})


def _json_round_trip(data: dict[str, Any]) -> dict[str, Any]:
    import json

    return json.loads(json.dumps(data, sort_keys=True))


def _mismatch(name: str, stored: dict[str, Any], given: dict[str, Any]) -> str:
    diff = {k: (stored.get(k), given.get(k)) for k in sorted(set(stored) | set(given))
            if stored.get(k) != given.get(k)}
    return (f"optimization run {name!r}: the definition differs from the stored one "
            f"(field: (stored, given)) {diff}; resume without changing it, or use a new name")
