"""The ``teamenv stats`` and ``teamenv report`` commands (registered by ``add_parser``)."""

from __future__ import annotations

import argparse
import json
from pathlib import Path


def add_parser(subparsers: argparse._SubParsersAction) -> None:
    """Register ``stats REPLAY [--json]`` and ``report REPLAY|DB -o page.html``."""
    stats = subparsers.add_parser("stats", help="match statistics of a replay (.npz)")
    stats.add_argument("replay", type=Path, help="a replay written by `teamenv match --replay`")
    stats.add_argument("--json", action="store_true", help="print MatchStats.to_json()")
    stats.add_argument("--xg-model", type=Path, default=None,
                       help="an xG model JSON (default: the shipped one)")
    stats.set_defaults(func=_stats)

    report = subparsers.add_parser(
        "report", help="one self-contained HTML page of a match (replay) or a tournament (DB)")
    report.add_argument("source", type=Path, help="a replay (.npz) or a tournament database")
    report.add_argument("-o", "--out", type=Path, required=True, help="HTML file to write")
    report.add_argument("--name", default=None, help="tournament in the database "
                        "(default: the only one)")
    report.add_argument("--xg-model", type=Path, default=None,
                        help="an xG model JSON (default: the shipped one)")
    report.set_defaults(func=_report)


def _model(path: Path | None):
    from teamenv.analytics.xg import XGModel

    return XGModel.load(path)


def _stats(args: argparse.Namespace) -> int:
    from teamenv.analytics.stats import replay_stats

    stats = replay_stats(args.replay, _model(args.xg_model))
    print(json.dumps(stats.to_json(), indent=2) if args.json else stats.summary())
    return 0


def _report(args: argparse.Namespace) -> int:
    from teamenv.analytics.report import write_report

    print(f"report: {write_report(args.source, args.out, name=args.name, model=_model(args.xg_model))}")
    return 0
