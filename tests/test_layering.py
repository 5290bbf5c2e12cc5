"""The import rules; docs/architecture.md draws them and says why.

Between packages: strategy -> teamenv -> {locomotion, comms} -> {portable_math, paramkit};
teams are plugins. Inside teamenv: a core that imports no application, and applications above
it that import each other one way (``APPLICATION_TIERS``). Every rule reads every import of a file,
function-level and relative ones included, so a late import cannot hide a back edge.
"""

import ast
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("portable_math", "comms", "locomotion", "teamenv", "strategy")


def module_of(path: Path) -> str:
    parts = path.relative_to(ROOT).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def is_module(name: str) -> bool:
    base = ROOT.joinpath(*name.split("."))
    return base.with_suffix(".py").is_file() or (base / "__init__.py").is_file()


def imported_modules(path: Path) -> set[str]:
    """Every module ``path`` imports, anywhere in the file: ``import a.b``, ``from a import b``
    (``a.b`` when that is a module, else ``a``), relative imports made absolute, and
    ``__import__``/``importlib.import_module`` of a literal name."""
    module = module_of(path)
    package = module if path.name == "__init__.py" else module.rpartition(".")[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = package.split(".")[:len(package.split(".")) - node.level + 1]
                base = ".".join(anchor + ([node.module] if node.module else []))
            for alias in node.names:
                name = f"{base}.{alias.name}"
                found.add(name if is_module(name) else base)
        elif isinstance(node, ast.Call) and node.args \
                and isinstance(node.args[0], ast.Constant) and isinstance(node.args[0].value, str) \
                and ((isinstance(node.func, ast.Name) and node.func.id == "__import__")
                     or (isinstance(node.func, ast.Attribute) and node.func.attr == "import_module")):
            found.add(node.args[0].value)
    return found


def imports_of(package: str) -> dict[str, set[str]]:
    return {str(path.relative_to(ROOT)): imported_modules(path)
            for path in sorted((ROOT / package).rglob("*.py"))}


def top(name: str) -> str:
    return name.split(".")[0]


@pytest.mark.parametrize("leaf", ["comms", "locomotion"])
def test_leaves_import_nothing_of_ours(leaf):
    # ... but the two packages below every package: the portable float math (same bits on
    # every CPU) and paramkit (registries, parameter checks)
    ours = {"comms", "locomotion", "teamenv", "strategy"} - {leaf}
    for path, names in imports_of(leaf).items():
        assert not {top(n) for n in names} & ours, path


def test_portable_math_imports_only_numpy_and_numba():
    # numba compiles its loops over the C library (portable_math.c_library_loops)
    for path, names in imports_of("portable_math").items():
        outside = {top(n) for n in names} - set(sys.stdlib_module_names) - {"portable_math"}
        assert outside <= {"numpy", "numba"}, path


def test_only_portable_math_jit_imports_numba():
    # it switches Intel's SVML off before numba reads its config (portable_math/jit.py): a
    # loop compiled with SVML rounds exp/pow by the CPU, not as the C library does
    for package in PACKAGES:
        for path, names in imports_of(package).items():
            if path != "portable_math/jit.py":
                assert "numba" not in {top(n) for n in names}, path


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
        if path != "teamenv/pygame_renderer.py" and not path.startswith("teamenv/render/"):
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


def test_no_module_imports_itself_back():
    """No import cycle between any two modules of ours, through any chain of imports."""
    graph = {}
    for package in PACKAGES:
        for path in (ROOT / package).rglob("*.py"):
            graph[module_of(path)] = imported_modules(path)
    for module in graph:
        graph[module] = {name for name in graph[module] if name in graph and name != module}
    done: set[str] = set()

    def visit(module: str, chain: list[str]) -> None:
        if module in chain:
            pytest.fail("import cycle: " + " -> ".join(chain[chain.index(module):] + [module]))
        if module in done:
            return
        for name in sorted(graph[module]):
            visit(name, chain + [module])
        done.add(module)

    for module in sorted(graph):
        visit(module, [])


# -- inside teamenv: the core and the applications above it ----------------------------------

# teamenv's applications, lowest tier first. An application imports the core, its own modules
# and the applications of lower tiers: never one of its own tier, never one above. Everything
# else in teamenv is the core, which imports no application. A ``python -m`` program
# (``__main__.py``, wherever it sits) belongs to the command line.
APPLICATION_TIERS = (
    ("match", "analytics", "render", "policy_team"),
    ("headtohead", "tournament"),
    ("optimize", "viewer", "league", "selfplay"),
    ("cli",),
)
TIER_OF = {app: k for k, tier in enumerate(APPLICATION_TIERS) for app in tier}


def application_of(module: str) -> str | None:
    """The application a module of teamenv (dotted name) belongs to; None for the core."""
    parts = module.split(".")
    if parts[-1] == "__main__":
        return "cli"
    return parts[1] if len(parts) > 1 and parts[1] in TIER_OF else None


def teamenv_imports() -> list[tuple[str, str]]:
    """(importer, imported) for every import of a teamenv module by a teamenv module."""
    return [(module_of(path), name) for path in sorted((ROOT / "teamenv").rglob("*.py"))
            for name in sorted(imported_modules(path)) if top(name) == "teamenv"]


def test_every_named_application_exists():
    for app in TIER_OF:
        assert is_module(f"teamenv.{app}"), app


def test_teamenv_core_imports_no_application():
    bad = [f"{a} -> {b}" for a, b in teamenv_imports()
           if application_of(a) is None and application_of(b) is not None]
    assert not bad, "the core imports an application:\n" + "\n".join(bad)


def test_teamenv_applications_import_one_way():
    bad = []
    for a, b in teamenv_imports():
        importer, imported = application_of(a), application_of(b)
        if importer and imported and imported != importer \
                and TIER_OF[imported] >= TIER_OF[importer]:
            bad.append(f"{a} -> {b} ({importer} may not import {imported})")
    assert not bad, "\n".join(bad)


def test_team_plugins_import_only_the_teamenv_core():
    # the plugin API (field, teams, config, search space...) is core; a team that imported an
    # application would load the tournament or optimizer into every match
    for path, names in imports_of("strategy").items():
        bad = {n for n in names if top(n) == "teamenv" and application_of(n)}
        assert not bad, f"{path} imports {sorted(bad)}"


def test_light_modules_load_neither_pettingzoo_nor_pymunk():
    # what a team plugin imports; the env (pettingzoo, pymunk) loads on first use
    code = ("import sys; sys.path.insert(0, sys.argv[1]); "
            "import teamenv.field, teamenv.config, teamenv.teams, teamenv.team_config, "
            "teamenv.search_space; from teamenv import FieldSpec, PlayMode, ConfigError; "
            "print(' '.join(sorted({'pettingzoo', 'pymunk'} & set(sys.modules))))")
    run = subprocess.run([sys.executable, "-c", code, str(ROOT)], capture_output=True,
                         text=True, env={**os.environ, "PYTHONWARNINGS": "ignore"})
    assert run.returncode == 0, run.stderr
    assert run.stdout.split() == []


def test_the_env_loads_on_first_use():
    import importlib

    import teamenv

    importlib.import_module("teamenv.env")  # the submodule loads (if it had not) ...
    assert teamenv.SoccerParallelEnv is sys.modules["teamenv.env"].SoccerParallelEnv
    assert teamenv.parallel_env is sys.modules["teamenv.env"].parallel_env
    assert callable(teamenv.env) and teamenv.env.__module__ == "teamenv"  # ... and env() stays
    # the AEC constructor, not the submodule
    assert set(teamenv.__all__) <= set(dir(teamenv))
