"""The simulation and the built-in teams call no NumPy function whose result depends on the
CPU: no SIMD-dispatched transcendental ufunc (AVX-512 and AVX2 kernels round the last bit
differently) and no BLAS product (OpenBLAS picks its kernels by CPU). They call
``portable_math`` instead. Two checks: a static one over the source (every reference to such
a function, ``@``, ``**`` with a non-integral exponent) and a dynamic one that plays short
matches (state and vision, both say channels, every scripted team) with recording proxies in
place of the NumPy ufuncs. Applications (analytics, rendering, viewer, league bridge,
optimizer, tournaments) are outside: they do not feed back into a match."""

from __future__ import annotations

import ast
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import numpy as np
import pytest

import teamenv
from teamenv.config import RulesConfig

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("comms", "locomotion", "strategy", "teamenv")
APPLICATIONS = ("teamenv/analytics", "teamenv/render", "teamenv/viewer", "teamenv/league",
                "teamenv/optimize", "teamenv/tournament", "teamenv/cli.py",
                "teamenv/__main__.py", "locomotion/humanoid")

# float64 ufuncs whose kernels differ between AVX-512 and AVX2 or the SSE baseline (numpy 2.4:
# compared bit for bit under NPY_DISABLE_CPU_FEATURES); sin and cos are the same for float64
# but not for float32, so float32 input is refused for them too
DISPATCHED = ("tan", "arctan", "arctan2", "arcsin", "arccos", "exp", "expm1", "log", "log1p",
              "log2", "log10", "sinh", "cosh", "tanh", "power", "float_power", "cbrt", "exp2",
              "arcsinh", "arccosh", "arctanh", "logaddexp", "logaddexp2")
DISPATCHED_FLOAT32 = ("sin", "cos")
BLAS = ("dot", "matmul", "vdot", "inner", "tensordot")
# scalar ``**`` sites checked by hand: Python numbers, so the C library's pow, with an
# integral exponent (exact)
SCALAR_POWERS = {
    ("teamenv/sim/vision.py", "10.0 ** cfg.truncate_decimals"),
    ("strategy/positioning/roles/voting.py", "float(n) ** (n - 1 - i)"),
    ("strategy/positioning/roles/voting.py", "float(n) ** n"),
    ("comms/codec.py", "n ** k"),
    ("comms/codec.py", "len(profile.charset) ** profile.max_chars"),
    ("comms/fields.py", "element.cardinality ** count"),
}


def on_match_path(path: Path) -> bool:
    rel = path.relative_to(ROOT).as_posix()
    return rel.split("/")[0] in PACKAGES and not rel.startswith(APPLICATIONS)


def source_files() -> list[Path]:
    return sorted(p for pkg in PACKAGES for p in (ROOT / pkg).rglob("*.py") if on_match_path(p))


def cpu_dependent_constructs(rel: str, source: str) -> list[str]:
    """What in ``source`` (the file ``rel``) may round differently on another CPU."""
    found = []
    for node in ast.walk(ast.parse(source)):
        where = f"{rel}:{getattr(node, 'lineno', '?')}"
        if isinstance(node, ast.BinOp) and isinstance(node.op, ast.MatMult):
            found.append(f"{where}: @ (BLAS): {ast.unparse(node)}")
        elif isinstance(node, ast.BinOp) and isinstance(node.op, ast.Pow):
            e = node.right
            integral = isinstance(e, ast.Constant) and (isinstance(e.value, int) or e.value == 2.0)
            if not integral and (rel, ast.unparse(node)) not in SCALAR_POWERS:
                found.append(f"{where}: ** with exponent {ast.unparse(e)}: {ast.unparse(node)}")
        elif isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) \
                and node.value.id in ("np", "numpy") and node.attr in DISPATCHED + BLAS:
            found.append(f"{where}: np.{node.attr}")
        elif isinstance(node, ast.Attribute) and node.attr == "dot":
            found.append(f"{where}: .dot (BLAS)")
        elif isinstance(node, ast.Attribute) and isinstance(node.value, ast.Attribute) \
                and node.value.attr == "linalg":
            found.append(f"{where}: np.linalg.{node.attr} (LAPACK/BLAS)")
        elif isinstance(node, ast.ImportFrom) and node.module \
                and node.module.split(".")[0] == "numpy" and node.module != "numpy.typing":
            found.append(f"{where}: from {node.module} import ... (bypasses the check below)")
        elif isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) \
                and node.func.attr == "einsum" \
                and any(k.arg == "optimize" for k in node.keywords):
            found.append(f"{where}: einsum(optimize=...) may call BLAS")
    return found


def test_sources_use_portable_math_for_cpu_dependent_functions():
    files = source_files()
    assert len(files) > 50 and ROOT / "teamenv/sim/vision.py" in files
    found = [hit for path in files
             for hit in cpu_dependent_constructs(path.relative_to(ROOT).as_posix(),
                                                 path.read_text())]
    assert not found, "use portable_math (its function or matmul) instead:\n" + "\n".join(found)


def test_the_static_check_sees_what_it_refuses():
    text = ("import numpy as np\nfrom numpy import exp\n"
            "a = np.arctan2(1, 2) + np.ones(2) @ np.ones(2) + np.ones(3).dot(np.ones(3))\n"
            "b = np.ones(2) ** 1.5 + x ** 2 + np.linalg.solve(m, v)\nc = np.sin(0.3)\n")
    found = cpu_dependent_constructs("strategy/probe.py", text)
    kinds = " ".join(found)
    for expected in ("from numpy", "np.arctan2", "@ (BLAS)", ".dot", "exponent 1.5",
                     "np.linalg.solve"):
        assert expected in kinds, (expected, found)
    assert len(found) == 6, found  # x ** 2 and np.sin are fine


class RecordingUfunc:
    """Stands in for a NumPy ufunc: records calls made from the match path's own code with
    input that takes a CPU-dependent kernel, then calls the real ufunc."""

    def __init__(self, name: str, real: np.ufunc, calls: list, allowed: list) -> None:
        self.name, self.real, self.calls, self.allowed = name, real, calls, allowed

    def __getattr__(self, attr: str):
        return getattr(self.real, attr)

    def __call__(self, *args, **kwargs):
        frame = sys._getframe(1)
        path = Path(frame.f_code.co_filename)
        if path.is_relative_to(ROOT) and on_match_path(path):
            dtype = np.result_type(*[np.asarray(a) for a in args[:self.real.nin]])
            where = f"{path.relative_to(ROOT)}:{frame.f_lineno}"
            if self.name in DISPATCHED and dtype.kind in "biuf":
                self.calls.append(f"{where}: np.{self.name} on {dtype}")
            elif self.name in DISPATCHED_FLOAT32 and dtype.kind == "f" and dtype.itemsize < 8:
                self.calls.append(f"{where}: np.{self.name} on {dtype}")
            else:
                self.allowed.append(self.name)
        return self.real(*args, **kwargs)


@contextmanager
def recording_ufuncs() -> Iterator[tuple[list, list]]:
    calls: list[str] = []
    allowed: list[str] = []
    saved = {name: getattr(np, name) for name in DISPATCHED + DISPATCHED_FLOAT32}
    try:
        for name, real in saved.items():
            setattr(np, name, RecordingUfunc(name, real, calls, allowed))
        yield calls, allowed
    finally:
        for name, real in saved.items():
            setattr(np, name, real)


MATCHES = [
    dict(left="full", right="chaser", field="mj7v7", team_size=7, seed=5,
         observation_mode="vision", vision="mj", channel="mj"),
    dict(left="full", right="silent", field="simspark", team_size=5, seed=6,
         observation_mode="vision", channel="simspark"),
    dict(left="chaser", right="full", field="simspark", team_size=5, seed=7, channel="mj"),
    dict(left="static", right="full", field="mj7v7", team_size=4, seed=8, channel="simspark"),
]


@pytest.mark.parametrize("spec", MATCHES, ids=lambda s: f"{s['left']}-{s['right']}-"
                         f"{s.get('observation_mode', 'state')}-{s['channel']}")
def test_matches_call_no_cpu_dependent_ufunc(spec):
    spec = dict(spec)
    seed = spec.pop("seed")
    with recording_ufuncs() as (calls, allowed):
        env = teamenv.parallel_env(rules=RulesConfig(half_time_s=1.0), **spec)
        env.reset(seed=seed)
        while not env.episode_over:
            env.step({})
        env.close()
    assert not calls, "\n".join(sorted(set(calls)))
    assert "cos" in allowed  # the proxies were in place: float64 cosines went through them


@pytest.mark.parametrize("channel", ["simspark", "mj"])
def test_env_with_walking_kicking_talking_agents_calls_no_cpu_dependent_ufunc(channel):
    rng = np.random.default_rng(3)
    with recording_ufuncs() as (calls, allowed):
        env = teamenv.parallel_env(field="simspark", team_size=4, channel=channel,
                                   observation_mode="vision")
        env.reset(seed=4)
        low, high = env.parser.walk_low, env.parser.walk_high
        for _ in range(120):
            env.step({agent: {"walk": rng.uniform(low, high).astype(np.float32),
                              "kick": np.array([rng.uniform(), rng.uniform(-3, 3)], np.float32),
                              "say": "ab12"} for agent in env.agents})
        env.close()
    assert not calls, "\n".join(sorted(set(calls)))
    assert "cos" in allowed
