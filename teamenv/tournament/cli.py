"""The ``teamenv tournament`` commands (run and resume, table, matches, list, replay) and
``teamenv report`` (an HTML page of a replay or a tournament database)."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from teamenv.errors import Terminated
from teamenv.match import MatchOptions

DEFAULT_NAME = "tournament"


def add_report_command(subparsers: argparse._SubParsersAction) -> None:
    """Register ``report REPLAY|DB -o page.html`` on the ``teamenv`` parser."""
    report = subparsers.add_parser(
        "report", help="one self-contained HTML page of a match (replay) or a tournament (DB)")
    report.add_argument("source", type=Path, help="a replay (.npz) or a tournament database")
    report.add_argument("-o", "--out", type=Path, required=True, help="HTML file to write")
    report.add_argument("--name", default=None, help="tournament in the database "
                        "(default: the only one)")
    report.add_argument("--xg-model", type=Path, default=None,
                        help="an xG model JSON (default: the shipped one)")
    report.set_defaults(func=_write_report)


def _write_report(args: argparse.Namespace) -> int:
    from teamenv.analytics.xg import XGModel
    from teamenv.tournament.report import write_report

    page = write_report(args.source, args.out, name=args.name, model=XGModel.load(args.xg_model))
    print(f"report: {page}")
    return 0


def add_tournament_commands(subparsers: argparse._SubParsersAction) -> None:
    """Register ``tournament {run,table,matches,list,replay}`` on the ``teamenv`` parser.

    Each command sets ``func(args) -> exit code``.
    """
    top = subparsers.add_parser(
        "tournament", help="batch tournaments: run/resume, tables, ratings, plots, replays",
        description="Batch strategy tournaments stored in SQLite.")
    sub = top.add_subparsers(dest="tournament_command", required=True)

    run = sub.add_parser("run", help="run (or --resume) a round robin or gauntlet")
    run.add_argument("teams", nargs="*", help="team specs: name, module:Class, with optional "
                     "overrides name:key=value,key2=value2 (a gauntlet's opponents)")
    run.add_argument("--db", type=Path, required=True, help="results database (SQLite file)")
    run.add_argument("--name", default=None, help=f"tournament name (default {DEFAULT_NAME!r})")
    run.add_argument("--format", choices=("round-robin", "gauntlet"), default="round-robin",
                     help="round-robin: every team meets every other (default); gauntlet: "
                     "--challenger meets each of the teams")
    run.add_argument("--challenger", default=None, help="the gauntlet's challenger spec")
    run.add_argument("--games", type=int, default=2, help="seeded rounds per pairing")
    run.add_argument("--no-swap", action="store_true", help="do not replay each round with "
                     "sides swapped (default: each seed is played once from each side)")
    run.add_argument("--seed", type=int, default=0, help="tournament seed")
    MatchOptions.add_arguments(run)
    run.add_argument("--cycle-budget", type=float, default=None,
                     help="a team whose act() takes longer (s) in any cycle forfeits")
    run.add_argument("--stall-timeout", type=float, default=10.0,
                     help="a cycle running longer than this (s) forfeits the acting team")
    run.add_argument("-j", "--jobs", type=int, default=None,
                     help="worker processes (default: all cores) / local Ray CPUs")
    run.add_argument("--backend", choices=("process", "ray", "serial"), default="process",
                     help="process: local worker pool (default); ray: Ray tasks; serial: "
                     "every match in this process (no fault isolation; for debugging)")
    run.add_argument("--ray-address", default=None,
                     help="with --backend ray: join this Ray cluster (auto, HOST:PORT or "
                          "ray://HOST:PORT); default: a private local Ray instance with --jobs "
                          "CPUs, whatever other Ray cluster runs on the machine")
    run.add_argument("--replay-dir", type=Path, default=None, help="record every match here")
    run.add_argument("--resume", action="store_true", help="continue a stored tournament: "
                     "play only the missing matches (teams/options may be omitted)")
    run.add_argument("--no-progress", action="store_true", help="no progress bar / live table")
    run.add_argument("--stop-when-separated", action="store_true",
                     help="play round by round and stop a pairing once its matches separate "
                          "its teams at 95 %% on --rank-by")
    _add_output_args(run)
    run.set_defaults(func=_run)

    table = sub.add_parser("table", help="league table and ratings of a stored tournament")
    table.add_argument("--db", type=Path, required=True, help="results database (SQLite file)")
    table.add_argument("--name", default=None, help="tournament (default: the only one)")
    _add_output_args(table)
    table.set_defaults(func=_table)

    matches = sub.add_parser("matches", help="list the stored matches (ids for replay)")
    matches.add_argument("--db", type=Path, required=True, help="results database (SQLite file)")
    matches.add_argument("--name", default=None, help="tournament (default: the only one)")
    matches.set_defaults(func=_matches)

    lst = sub.add_parser("list", help="list the tournaments in a database")
    lst.add_argument("--db", type=Path, required=True, help="results database (SQLite file)")
    lst.set_defaults(func=_list)

    rep = sub.add_parser("replay", help="replay a stored match to a GIF/MP4 (needs [render])")
    rep.add_argument("match_id", type=int, help="match id (see `tournament matches`)")
    rep.add_argument("--db", type=Path, required=True, help="results database (SQLite file)")
    rep.add_argument("--out", type=Path, default=None, help="GIF/MP4 to write")
    rep.add_argument("--replay-out", type=Path, default=None, help="also keep the .npz here")
    rep.add_argument("--fps", type=int, default=10,
                     help="frames per second of the GIF/MP4 (default 10)")
    rep.add_argument("--every", type=int, default=5, help="render every k-th cycle")
    rep.add_argument("--no-verify", action="store_true",
                     help="do not check the replayed score against the database")
    rep.set_defaults(func=_replay)


def _add_output_args(p: argparse.ArgumentParser) -> None:
    p.add_argument("--csv", type=Path, default=None, help="write the table + ratings as CSV")
    p.add_argument("--json", type=Path, default=None, help="write the table + ratings as JSON")
    p.add_argument("--plots", type=Path, default=None,
                   help="write ratings.png and goal_difference.png into this folder")
    p.add_argument("--bootstrap", type=int, default=200,
                   help="bootstrap resamples for the rating intervals (0: none)")
    p.add_argument("--ratings-seed", type=int, default=0, help="seed of the bootstrap")
    from teamenv.analytics.ranking import RANK_METRICS

    p.add_argument("--rank-by", choices=RANK_METRICS, default="goals",
                   help="also rank teams by mean margin per match on goals, expected goals, "
                        "the composite or territory (docs/analytics.md), with bootstrap "
                        "intervals, and show each pairing's margin with its t interval")


def _definition(args: argparse.Namespace) -> Any:
    from teamenv.tournament.schedule import Tournament

    options = MatchOptions.from_arguments(args)
    return Tournament(
        name=args.name or DEFAULT_NAME, teams=tuple(args.teams),
        format=args.format.replace("-", "_"), challenger=args.challenger,
        games_per_pairing=args.games, swap_sides=not args.no_swap, seed=args.seed,
        options=options, cycle_time_budget_s=args.cycle_budget,
        stall_timeout_s=args.stall_timeout)


def _console() -> Any:
    """A rich Console; wide (160 columns) when the output is not a terminal (logs, pipes)."""
    import sys

    from rich.console import Console

    return Console(width=None if sys.stdout.isatty() else 160)


def _run(args: argparse.Namespace) -> int:
    from teamenv.tournament.runner import run_tournament

    tournament = None if (args.resume and not args.teams and not args.challenger) \
        else _definition(args)
    console = _console()
    try:
        summary = run_tournament(tournament, args.db, name=args.name, resume=args.resume,
                                 backend=args.backend, jobs=args.jobs,
                                 ray_address=args.ray_address, replay_dir=args.replay_dir,
                                 progress=not args.no_progress, console=console,
                                 stop_when_separated=args.rank_by if args.stop_when_separated
                                 else None)
    except Terminated:
        raise                   # the command's exit status says SIGTERM (143)
    except KeyboardInterrupt:
        return 130
    console.print(summary.describe())
    _report(args, summary.db_path, summary.tournament.name, console, print_table=args.no_progress)
    return 0 if summary.complete or summary.separated else 1


def _table(args: argparse.Namespace) -> int:
    _report(args, args.db, args.name, _console(), print_table=True)
    return 0


def _report(args: argparse.Namespace, db: Path, name: str | None, console: Any,
            print_table: bool) -> None:
    from teamenv.tournament.ratings import compute_ratings
    from teamenv.tournament.store import ResultStore
    from teamenv.tournament.table import (
        goal_difference_matrix,
        league_table,
        rich_ratings,
        rich_table,
        write_csv,
        write_json,
    )

    with ResultStore(db) as store:
        tid, tournament = store.get_tournament(name)
        records = store.matches(tid)
        failures = store.failures(tid)
        scheduled = len(tournament.schedule())
        team_stats = store.team_stats(tid)
    teams = [t.label for t in tournament.all_teams]
    rows = league_table(records, teams)
    ratings = compute_ratings(records, teams, n_bootstrap=args.bootstrap,
                              seed=args.ratings_seed) if records else None
    if print_table:
        console.print(rich_table(rows, title=f"{tournament.name}: {len(records)}/{scheduled} "
                                 "matches"))
    if ratings is not None:
        console.print(rich_ratings(ratings, title=f"{tournament.name}: ratings"))
    if records:
        from teamenv.analytics.ranking import head_to_head, match_margins, rank_teams, usable
        from teamenv.tournament.table import rich_head_to_head, rich_rank

        rank_by = getattr(args, "rank_by", "goals")
        margins = usable(match_margins(records, team_stats), rank_by)
        ranks = rank_teams(margins, rank_by, teams, n_bootstrap=max(args.bootstrap, 1),
                           seed=args.ratings_seed)
        console.print(rich_rank(ranks, title=f"{tournament.name}: ranked by {rank_by}",
                                used=len(margins), total=len(records)))
        console.print(rich_head_to_head(head_to_head(margins, rank_by),
                                        title=f"{tournament.name}: head to head on {rank_by}"))
    for idx, err in failures:
        console.print(f"match #{idx} missing: {err}")
    extra = {"tournament": tournament.to_json(), "matches_stored": len(records),
             "matches_scheduled": scheduled}
    if args.csv:
        console.print(f"csv: {write_csv(rows, args.csv, ratings)}")
    if args.json:
        console.print(f"json: {write_json(rows, args.json, ratings, extra)}")
    if args.plots:
        from teamenv.tournament.plots import plot_goal_difference, plot_ratings

        if ratings is not None:
            console.print(f"plot: {plot_ratings(ratings, args.plots / 'ratings.png')}")
        matrix = goal_difference_matrix(records, teams)
        console.print(f"plot: {plot_goal_difference(teams, matrix, args.plots / 'goal_difference.png')}")


def _matches(args: argparse.Namespace) -> int:
    from teamenv.tournament.store import ResultStore

    with ResultStore(args.db) as store:
        tid, tournament = store.get_tournament(args.name)
        print(f"{'id':>6s}  {'#idx':<6s} {'seed':<15s} left score right  wall  [forfeit]  "
              "goals (game time s:side)")
        for r in store.matches(tid):
            forfeit = f"  forfeit {r.forfeit_side}: {r.forfeit_reason}" if r.forfeit_side else ""
            goals = " ".join(f"{g.time_s:.1f}s:{g.side}" for g in r.goals)
            print(f"{r.id:6d}  #{r.idx:<5d} seed {r.seed:<10d} {r.left_team} "
                  f"{r.left_score}-{r.right_score} {r.right_team}  {r.wall_s:.2f}s wall"
                  f"{forfeit}  {goals}")
    return 0


def _list(args: argparse.Namespace) -> int:
    from teamenv.tournament.store import ResultStore

    with ResultStore(args.db) as store:
        for name in store.tournament_names():
            tid, tournament = store.get_tournament(name)
            print(f"{name}: {tournament.format}, {len(tournament.all_teams)} teams, "
                  f"{store.count_matches(tid)}/{len(tournament.schedule())} matches")
    return 0


def _replay(args: argparse.Namespace) -> int:
    from teamenv.tournament.replays import match_replay

    replay = match_replay(args.db, args.match_id, replay_out=args.replay_out,
                          verify=not args.no_verify)
    print(f"replay: {replay}")
    if args.out:
        from teamenv.render import render_replay_gif

        print(f"video: {render_replay_gif(replay, args.out, fps=args.fps, every=args.every)}")
    return 0
