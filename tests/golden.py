"""Replay hashes of seeded matches and env runs, to show that a speed-up changed no result.

``python -m tests.golden`` prints the current hashes; ``tests/golden_hashes.json`` holds the
committed ones (recorded before the speed work) and
``tests/test_golden_hashes.py`` compares the two under this CPU's own NumPy/OpenBLAS kernels,
under AVX2-only kernels and under ``PINNED_ENV`` (NumPy's SSE baseline, OpenBLAS's Haswell
kernels): the simulation and the built-in teams use ``portable_math`` where those kernels round
differently, so all three give the same hashes. A hash covers every cycle's full state
(``env.state()``: bodies, velocities, play mode, clock, score) and what each built-in team
believed (``annotations()``: own pose, ball, role) of a whole match, or for the
bare env every value that ``reset``/``step`` return, in a canonical byte form (so a lazily
built mapping hashes like an eager one).
"""

from __future__ import annotations

import hashlib
import json
import sys
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

import teamenv
from teamenv.config import RulesConfig

HASH_FILE = Path(__file__).with_name("golden_hashes.json")
PINNED_ENV = {"NPY_DISABLE_CPU_FEATURES": "X86_V3 X86_V4 AVX512_ICL AVX512_SPR",
              "OPENBLAS_CORETYPE": "Haswell", "OPENBLAS_NUM_THREADS": "1"}

MATCHES: dict[str, dict[str, Any]] = {
    # name: env keyword arguments; each match plays to the end of its second half (seed 33
    # of the 5 v 5 match has a goal and set plays)
    "full-chaser-simspark11-state": dict(left="full", right="chaser", field="simspark",
                                         team_size=11, half_time_s=12.0, seed=11),
    "full-full-mj7v7-state": dict(left="full", right="full", field="mj7v7", team_size=7,
                                  half_time_s=12.0, seed=12),
    "full-chaser-simspark5-goals-state": dict(left="full", right="chaser", field="simspark",
                                              team_size=5, half_time_s=30.0, seed=33),
    "silent-static-simspark5-state": dict(left="silent", right="static", field="simspark",
                                          team_size=5, half_time_s=8.0, seed=13),
    "full-chaser-mj7v7-vision-mj": dict(left="full", right="chaser", field="mj7v7",
                                        team_size=7, half_time_s=5.0, seed=14,
                                        observation_mode="vision", vision="mj"),
    "full-silent-simspark11-vision": dict(left="full", right="silent", field="simspark",
                                          team_size=11, half_time_s=3.0, seed=15,
                                          observation_mode="vision"),
    "full-chaser-mj7v7-vision-mj_noisy": dict(left="full", right="chaser", field="mj7v7",
                                              team_size=7, half_time_s=4.0, seed=16,
                                              observation_mode="vision", vision="mj_noisy"),
}

ENV_RUNS: dict[str, dict[str, Any]] = {
    # random Dict actions, a message from every agent every cycle
    "random-dict-say-simspark11-state": dict(team_size=11, steps=400, seed=21),
    "random-dict-say-mj7v7-vision": dict(team_size=7, field="mj7v7", steps=300, seed=22,
                                         observation_mode="vision", vision="mj"),
}


def _feed(h: Any, value: Any) -> None:
    """Hash ``value`` canonically: arrays by dtype, shape and bytes; mappings by sorted key."""
    if isinstance(value, np.ndarray):
        h.update(f"a{value.dtype.str}{value.shape}".encode())
        h.update(np.ascontiguousarray(value).tobytes())
    elif isinstance(value, Mapping):
        h.update(b"{")
        for key in sorted(value, key=str):
            h.update(repr(key).encode())
            _feed(h, value[key])
        h.update(b"}")
    elif isinstance(value, (list, tuple)):
        h.update(b"[")
        for item in value:
            _feed(h, item)
        h.update(b"]")
    elif isinstance(value, np.generic):
        _feed(h, value.item())
    elif isinstance(value, (bool, int, float, str, bytes)) or value is None:
        h.update(f"{type(value).__name__}:{value!r};".encode())
    else:  # dataclasses and other records: their public fields
        _feed(h, {k: v for k, v in vars(value).items() if not k.startswith("_")})


def match_hash(left: str, right: str, field: str, team_size: int, half_time_s: float,
               seed: int, **options: Any) -> str:
    env = teamenv.parallel_env(left=left, right=right, field=field, team_size=team_size,
                               rules=RulesConfig(half_time_s=half_time_s), **options)
    env.reset(seed=seed)
    h = hashlib.sha256()
    while not env.episode_over:
        env.step({})
        h.update(env.state().tobytes())
        for side in sorted(env.teams):  # the teams' beliefs show a last-bit change at once
            annotations = getattr(env.teams[side], "annotations", None)
            if annotations is not None:
                _feed(h, annotations())
    h.update(repr(tuple(env.sim.referee.score)).encode())
    env.close()
    return h.hexdigest()


def env_run_hash(team_size: int, steps: int, seed: int, field: str = "simspark",
                 **options: Any) -> str:
    env = teamenv.parallel_env(field=field, team_size=team_size, **options)
    h = hashlib.sha256()
    _feed(h, env.reset(seed=seed))
    rng = np.random.default_rng(seed)
    alphabet = list("abcdefXYZ0123456789")
    low, high = env.parser.walk_low, env.parser.walk_high
    for _ in range(steps):
        actions = {}
        for agent in env.agents:
            power = rng.uniform(0.0, 1.0) if rng.uniform() < 0.2 else 0.0
            actions[agent] = {
                "walk": rng.uniform(low, high).astype(np.float32),
                "kick": np.array([power, rng.uniform(-np.pi, np.pi)], dtype=np.float32),
                "say": "".join(rng.choice(alphabet, size=int(rng.integers(1, 11)))),
            }
        _feed(h, env.step(actions))
        if not env.agents:
            break
    env.close()
    return h.hexdigest()


def current_hashes() -> dict[str, str]:
    out = {name: match_hash(**spec) for name, spec in MATCHES.items()}
    out.update({name: env_run_hash(**spec) for name, spec in ENV_RUNS.items()})
    return out


if __name__ == "__main__":
    # python -m tests.golden [--write]: any NumPy/OpenBLAS setting gives the same hashes
    hashes = current_hashes()
    json.dump(hashes, sys.stdout, indent=2, sort_keys=True)
    print()
    if "--write" in sys.argv:
        HASH_FILE.write_text(json.dumps(hashes, indent=2, sort_keys=True) + "\n")
