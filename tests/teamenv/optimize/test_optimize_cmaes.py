"""The CMA-ES loop on a synthetic fitness (no matches): it converges, it is seeded, it leaves
numpy's global random state alone, and a run killed with SIGKILL mid-generation and resumed
makes exactly the search an uninterrupted run makes."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from teamenv.optimize.checkpoint import CheckpointStore, OptimizeError
from teamenv.optimize.cmaes_loop import (
    CandidateScore,
    SearchSettings,
    load_result,
    optimize,
)
from teamenv.search_space import Choice, Range, SearchSpace, build_search_space, search

ROOT = Path(__file__).resolve().parents[3]
TARGET = {"speed": 1.6, "weight": 30.0, "count": 4, "shape": "deep"}


@dataclass(frozen=True)
class ToyConfig:
    speed: float = field(default=1.0, metadata=search(Range(0.5, 2.0)))
    weight: float = field(default=3.0, metadata=search(Range(1.0, 100.0, "log")))
    count: int = field(default=1, metadata=search(Range(0, 5, integer=True)))
    shape: str = field(default="wide", metadata=search(Choice(("narrow", "wide", "deep"))))


def toy_space() -> SearchSpace:
    return build_search_space(ToyConfig())


class Sphere:
    """Fitness = minus the squared distance to TARGET in unit coordinates (decoded configs,
    so integer and choice steps count); ``delay`` seconds per candidate; writes the running
    generation to ``progress`` (for the kill test)."""

    def __init__(self, delay: float = 0.0, progress: str | None = None) -> None:
        self.delay = delay
        self.progress = progress
        self.space = toy_space()
        self.target = self.space.encode(TARGET)

    def definition(self) -> dict[str, Any]:
        return {"kind": "sphere", "target": TARGET}

    def evaluate(self, generation: int, configs: list[dict[str, Any]],
                 reporter: Any) -> list[CandidateScore]:
        if self.progress:
            Path(self.progress).write_text(str(generation))
        scores = []
        for config in configs:
            time.sleep(self.delay)
            x = self.space.encode(config)
            scores.append(CandidateScore(-float(np.sum((x - self.target) ** 2))))
        return scores


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_converges_on_a_synthetic_fitness(tmp_path, seed):
    state = np.random.get_state()[1].copy()
    result = optimize("sphere", tmp_path / "o.sqlite", toy_space(), Sphere(), generations=30,
                      settings=SearchSettings(seed=seed, popsize=8, sigma0=0.3))
    rec = result.recommended
    assert rec["count"] == 4 and rec["shape"] == "deep"
    assert rec["speed"] == pytest.approx(1.6, abs=0.05)
    assert rec["weight"] == pytest.approx(30.0, rel=0.1)
    first = np.mean([s["fitness"] for s in result.generations[0].scores])
    last = np.mean([s["fitness"] for s in result.generations[-1].scores])
    assert last > first
    assert (np.random.get_state()[1] == state).all()  # cma never touched the global state
    assert all(0 <= u <= 1 for u in result.generations[-1].mean)  # the mean in the unit cube


def _trace(db: Path, name: str) -> list[tuple[Any, ...]]:
    return [(g.generation, g.candidates, g.scores, g.mean, g.sigma)
            for g in load_result(db, name).generations]


def test_same_seed_same_search_and_resume_extends_it(tmp_path):
    settings = SearchSettings(seed=5, popsize=6)
    optimize("a", tmp_path / "a.sqlite", toy_space(), Sphere(), generations=6, settings=settings)
    optimize("b", tmp_path / "b.sqlite", toy_space(), Sphere(), generations=3, settings=settings)
    optimize("b", tmp_path / "b.sqlite", None, Sphere(), generations=6, resume=True)
    assert _trace(tmp_path / "a.sqlite", "a") == _trace(tmp_path / "b.sqlite", "b")
    optimize("c", tmp_path / "c.sqlite", toy_space(), Sphere(), generations=6,
             settings=SearchSettings(seed=6, popsize=6))
    assert _trace(tmp_path / "c.sqlite", "c")[0][1] != _trace(tmp_path / "a.sqlite", "a")[0][1]


def test_resume_refuses_a_changed_definition_and_a_new_run_an_existing_name(tmp_path):
    db = tmp_path / "o.sqlite"
    optimize("r", db, toy_space(), Sphere(), generations=1, settings=SearchSettings(seed=1))
    with pytest.raises(OptimizeError, match="already exists"):
        optimize("r", db, toy_space(), Sphere(), generations=2)
    with pytest.raises(OptimizeError, match="definition differs"):
        optimize("r", db, toy_space(), Sphere(), generations=2,
                 settings=SearchSettings(seed=2), resume=True)
    with pytest.raises(OptimizeError, match="no optimization run 'x'"):
        optimize("x", db, None, Sphere(), generations=2, resume=True)
    with pytest.raises(OptimizeError, match="sigma0"):
        SearchSettings(sigma0=0.0)


_CHILD = """
import sys
from pathlib import Path
from teamenv.optimize.cmaes_loop import SearchSettings, optimize
from tests.teamenv.optimize.test_optimize_cmaes import Sphere, toy_space
db, progress = sys.argv[1], sys.argv[2]
optimize("kill", db, toy_space(), Sphere(delay=0.03, progress=progress), generations=8,
         settings=SearchSettings(seed=11, popsize=6), resume=True)
"""


def test_sigkill_mid_generation_then_resume_is_the_uninterrupted_search(tmp_path):
    db, progress = tmp_path / "kill.sqlite", tmp_path / "progress"
    child = subprocess.Popen([sys.executable, "-c", _CHILD, str(db), str(progress)], cwd=ROOT,
                             env={**os.environ, "PYTHONPATH": str(ROOT)})
    deadline = time.monotonic() + 300  # generous: a loaded machine imports slowly
    while time.monotonic() < deadline and child.poll() is None:
        if progress.exists() and progress.read_text() == "3":
            break
        time.sleep(0.01)
    time.sleep(0.08)  # a few candidates into generation 3 (6 x 0.03 s)
    assert child.poll() is None, "the run ended before it could be killed"
    os.kill(child.pid, signal.SIGKILL)
    child.wait()
    with CheckpointStore(db) as store:
        gens = store.generations(store.find_run("kill")[0])
    assert gens[-1].generation == 3 and not gens[-1].told  # killed inside generation 3
    optimize("kill", db, None, Sphere(), generations=8, resume=True)
    optimize("whole", tmp_path / "whole.sqlite", toy_space(), Sphere(), generations=8,
             settings=SearchSettings(seed=11, popsize=6))
    killed, whole = _trace(db, "kill"), _trace(tmp_path / "whole.sqlite", "whole")
    assert len(killed) == 8
    assert json.dumps(killed) == json.dumps(whole)
