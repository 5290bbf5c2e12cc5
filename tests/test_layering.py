"""The import rules of DESIGN.md: strategy -> teamenv -> {locomotion, comms} -> {portable_math,
paramkit}; teams are plugins."""

import ast
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def imports_of(package: str) -> dict[str, set[str]]:
    found = {}
    for path in (ROOT / package).rglob("*.py"):
        names = set()
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Import):
                names.update(alias.name for alias in node.names)
            elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
                names.add(node.module)
        found[str(path.relative_to(ROOT))] = names
    return found


def top(name: str) -> str:
    return name.split(".")[0]


@pytest.mark.parametrize("leaf", ["comms", "locomotion"])
def test_leaves_import_nothing_of_ours(leaf):
    # ... but the two packages below every package: the portable float math (same bits on
    # every CPU) and paramkit (registries, parameter checks)
    ours = {"comms", "locomotion", "teamenv", "strategy"} - {leaf}
    for path, names in imports_of(leaf).items():
        assert not {top(n) for n in names} & ours, path


def test_portable_math_imports_only_numpy():
    for path, names in imports_of("portable_math").items():
        assert {top(n) for n in names} - set(sys.stdlib_module_names) <= {"numpy"}, path


def test_paramkit_imports_only_the_standard_library():
    for path, names in imports_of("paramkit").items():
        assert {top(n) for n in names} - set(sys.stdlib_module_names) <= {"paramkit"}, path


def test_teamenv_never_imports_strategy():
    for path, names in imports_of("teamenv").items():
        assert "strategy" not in {top(n) for n in names}, path


def test_simulation_core_knows_no_rl_api_or_pygame():
    for path, names in imports_of("teamenv/sim").items():
        assert not {top(n) for n in names} & {"gymnasium", "pettingzoo", "pygame"}, path


def test_strategy_uses_only_public_teamenv():
    for path, names in imports_of("strategy").items():
        assert not any(n.startswith("teamenv.sim") for n in names), path
        assert "locomotion" not in {top(n) for n in names}, path


def test_heavy_dependencies_only_where_used():
    for path, names in imports_of("teamenv").items():
        tops = {top(n) for n in names}
        if "render" not in path:
            assert "pygame" not in tops, path
        if "tournament" not in path:
            assert "ray" not in tops, path
    for path, names in imports_of("locomotion").items():
        if "humanoid" not in path:
            assert not {top(n) for n in names} & {"jax", "brax", "mujoco"}, path


# The agent's layers, lowest first: each may import only the layers before it (and the shared
# modules geometry and memo); none imports teams/.
STRATEGY_LAYERS = ("perception", "positioning", "behaviours", "decision", "teams")


@pytest.mark.parametrize("k", range(len(STRATEGY_LAYERS)))
def test_strategy_layers_import_only_lower_layers(k):
    layer = STRATEGY_LAYERS[k]
    above = {f"strategy.{name}" for name in STRATEGY_LAYERS[k + 1:]}
    for path, names in imports_of(f"strategy/{layer}").items():
        bad = {n for n in names if any(n == a or n.startswith(a + ".") for a in above)}
        assert not bad, f"{path} imports {sorted(bad)} (a layer above {layer})"


def test_strategy_has_its_layers_as_folders():
    for layer in STRATEGY_LAYERS:
        assert (ROOT / "strategy" / layer / "__init__.py").is_file(), layer
    assert not (ROOT / "strategy" / "worldmodel.py").exists()
