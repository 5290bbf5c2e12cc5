"""The ``teamenv optimize`` command: CMA-ES over a team's config, fitness from tournaments."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from teamenv.match import MatchOptions
from teamenv.optimize.checkpoint import OptimizeError


def add_parser(subparsers: argparse._SubParsersAction) -> None:
    """Register ``optimize`` on the ``teamenv`` parser (sets ``func(args) -> exit code``)."""
    p = subparsers.add_parser(
        "optimize", help="CMA-ES search of a team's config parameters by seeded matches",
        description="CMA-ES over the declared parameters of TEAM's config; each candidate "
        "plays seeded matches against the --against field (common seeds within a "
        "generation); checkpointed in --db, resumable; exports the result as a team override "
        "(TEAM@NAME in tournaments).")
    p.add_argument("team", nargs="?", help="the team to tune, with fixed overrides if any: "
                   "full, or full:communicate=false (omit with --resume)")
    p.add_argument("--against", nargs="+", default=None, metavar="SPEC",
                   help="the fixed field of opponents (team specs as in tournaments)")
    p.add_argument("--db", type=Path, default=Path("optimize.sqlite"),
                   help="SQLite file for checkpoints and matches (default optimize.sqlite)")
    p.add_argument("--name", default="opt", help="the run's name (default 'opt')")
    p.add_argument("--resume", action="store_true", help="continue the stored run --name "
                   "(definition from the database; --generations may be raised)")
    p.add_argument("--params", default=None, help="comma-separated fields to search "
                   "(default: every field whose config declares a search range)")
    p.add_argument("--bounds", action="append", default=[], metavar="NAME=LOW:HIGH[:log][:int]",
                   help="a search domain replacing the declared one (or NAME=a|b|c choices); "
                   "repeat for several")
    p.add_argument("--list-params", action="store_true", help="print the team's search space "
                   "and exit")
    p.add_argument("--generations", type=int, default=10, help="generations to score (total)")
    p.add_argument("--popsize", type=int, default=None, help="candidates per generation "
                   "(default cma's 4 + 3 ln n)")
    p.add_argument("--sigma0", type=float, default=0.2,
                   help="initial step size, a fraction of every parameter's range")
    p.add_argument("--seed", type=int, default=0, help="seed of CMA-ES's sampler")
    p.add_argument("--tune-seed", type=int, default=7000, help="generation g's matches use "
                   "tournament seed TUNE_SEED + g (keep held-out checks at other seeds, e.g. "
                   "9000)")
    p.add_argument("--games", type=int, default=1, help="seeded rounds per opponent per "
                   "candidate, each played from both sides")
    p.add_argument("--metric", choices=("territory", "xg"), default="territory",
                   help="the finer match metric added to the goal difference: territory (mean "
                   "ball x in half-lengths, -1..1) or xg (expected-goals difference, "
                   "teamenv.analytics)")
    p.add_argument("--metric-weight", type=float, default=1.0, help="fitness = goal "
                   "difference + this x the metric; 0: goal difference alone")
    MatchOptions.add_arguments(p)
    p.add_argument("--cycle-budget", type=float, default=None,
                   help="a team whose act() takes longer (s) in any cycle forfeits")
    p.add_argument("--stall-timeout", type=float, default=10.0,
                   help="a cycle running longer than this (s) forfeits the acting team")
    p.add_argument("--backend", choices=("process", "ray", "serial"), default="process",
                   help="process: local worker pool (default); ray: Ray tasks; serial: "
                   "every match in this process")
    p.add_argument("-j", "--jobs", type=int, default=None,
                   help="worker processes (default: all cores) / local Ray CPUs")
    p.add_argument("--ray-address", default=None, help="Ray cluster address (e.g. auto)")
    p.add_argument("--export", type=Path, default=None, help="write the result (the search "
                   "distribution's mean) as a team override file here (default "
                   "overrides/NAME.json; use it as TEAM@NAME)")
    p.add_argument("--plot", type=Path, default=None,
                   help="convergence plot PNG (default NAME-convergence.png beside --db)")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.set_defaults(func=_run)


def _run(args: argparse.Namespace) -> int:
    from rich.console import Console

    from teamenv.optimize.cmaes_loop import SearchSettings, load_result, optimize
    from teamenv.optimize.plot import plot_convergence
    from teamenv.optimize.progress import RichReporter
    from teamenv.optimize.team_space import team_search_space
    from teamenv.optimize.tournament_fitness import TournamentFitness
    from teamenv.tournament.overrides import OVERRIDE_DIR
    from teamenv.tournament.spec import parse_team_spec

    console = Console(stderr=True)
    execution = {"backend": args.backend, "jobs": args.jobs, "ray_address": args.ray_address}
    options = MatchOptions.from_arguments(args)
    if args.resume:
        if args.team or args.against or args.params or args.bounds:
            raise OptimizeError("--resume takes the run's definition from the database: give "
                                "only --db, --name, --generations and execution options")
        stored = load_result(args.db, args.name)
        evaluator = TournamentFitness.from_definition(stored.definition["evaluator"], args.db,
                                                      args.name, **execution)
        space, settings, team = None, None, evaluator.team
    else:
        if not args.team:
            raise OptimizeError("give the TEAM to optimize (or --resume a stored run)")
        spec = parse_team_spec(args.team)
        only = [s.strip() for s in args.params.split(",") if s.strip()] if args.params else None
        space = team_search_space(spec.name, spec.config_dict, options, only=only,
                                  bounds=args.bounds)
        if args.list_params:
            print(f"search space of {spec.label} ({space.dimension} parameters):")
            print(space.describe())
            return 0
        if not args.against:
            raise OptimizeError("--against: give the field of opponents (e.g. --against chaser)")
        clash = sorted(set(spec.config_dict) & set(space.names))
        if clash:
            raise OptimizeError(f"{spec.label}: {clash} are fixed by the team spec and searched "
                                "too; drop them from one (--params)")
        settings = SearchSettings(seed=args.seed, popsize=args.popsize, sigma0=args.sigma0)
        evaluator = TournamentFitness(
            args.db, args.name, spec.name, args.against, base_config=spec.config_dict,
            options=options, games=args.games, tune_seed=args.tune_seed,
            metric=args.metric, metric_weight=args.metric_weight, cycle_time_budget_s=args.cycle_budget,
            stall_timeout_s=args.stall_timeout, **execution)
        team = spec.name
    plot_path = args.plot or args.db.with_name(f"{_safe(args.name)}-convergence.png")
    reporter = RichReporter(console, enabled=not args.no_progress)
    with reporter:
        result = optimize(args.name, args.db, space, evaluator, args.generations, settings,
                          resume=args.resume, reporter=reporter,
                          after_generation=lambda r: plot_convergence(r, plot_path))
    export = args.export or OVERRIDE_DIR / f"{_safe(args.name)}.json"
    _export(result, team, evaluator.base_config, export)
    _print_summary(result, export, plot_path)
    return 0


def _export(result: Any, team: str, base_config: dict[str, Any], path: Path) -> None:
    from teamenv.tournament.overrides import write_team_override

    told = [g for g in result.generations if g.told]
    write_team_override(path, team, {**base_config, **result.recommended}, source={
        "run": result.name, "generations": len(told), "matches": result.matches,
        "chosen": "the CMA-ES distribution mean after the last generation",
        "evaluator": result.definition.get("evaluator")})


def _print_summary(result: Any, export: Path, plot: Path) -> None:
    told = [g for g in result.generations if g.told]
    print(f"optimization {result.name!r}: {len(told)} generations, {result.matches} matches, "
          f"{result.wall_s:.1f} s in this call" +
          (f"; cma stopped: {result.stop}" if result.stop else ""))
    best = result.best_observed()
    if best is not None:
        g, _config, score = best
        print(f"best candidate seen: generation {g}, fitness {score['fitness']:.3f} "
              f"(goal difference {score['goal_difference']}, fine metric {score['fine']})")
    print("result (distribution mean):")
    for name, value in result.recommended.items():
        print(f"  {name} = {value!r}")
    print(f"team override: {export}  (use as {export.stem!r}: TEAM@{export.stem})")
    print(f"convergence plot: {plot}")


def _safe(name: str) -> str:
    return "".join(c if c.isalnum() or c in "-_" else "_" for c in name)

