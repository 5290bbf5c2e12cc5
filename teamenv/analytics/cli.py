"""The ``teamenv stats`` command (registered by ``add_parser``). ``teamenv report``, which also
reads tournament databases, is the tournament's (``teamenv.tournament.cli``)."""

from __future__ import annotations

import argparse
import json
from pathlib import Path


def add_parser(subparsers: argparse._SubParsersAction) -> None:
    """Register ``stats REPLAY [--json]``."""
    stats = subparsers.add_parser("stats", help="match statistics of a replay (.npz)")
    stats.add_argument("replay", type=Path, help="a replay written by `teamenv match --replay`")
    stats.add_argument("--json", action="store_true", help="print MatchStats.to_json()")
    stats.add_argument("--xg-model", type=Path, default=None,
                       help="an xG model JSON (default: the shipped one)")
    stats.set_defaults(func=_stats)


def _model(path: Path | None):
    from teamenv.analytics.xg import XGModel

    return XGModel.load(path)


def _stats(args: argparse.Namespace) -> int:
    from teamenv.analytics.stats import replay_stats

    stats = replay_stats(args.replay, _model(args.xg_model))
    print(json.dumps(stats.to_json(), indent=2) if args.json else stats.summary())
    return 0

