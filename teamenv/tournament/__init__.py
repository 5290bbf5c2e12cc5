"""Batch strategy tournaments: schedules, execution backends, SQLite results, ratings, tables.

An application (docs/architecture.md): imports teamenv's core, the match runner and the
analytics, never an application above it (optimize, viewer, league, cli); must never import
``strategy`` (teams are entry-point plugins) and imports ray only inside the Ray backend.
"""

from __future__ import annotations

from teamenv.tournament.errors import (
    StoreError,
    TeamSpecError,
    TournamentConfigError,
    TournamentError,
)
from teamenv.tournament.runner import TournamentSummary, run_tournament
from teamenv.tournament.schedule import MatchTask, Tournament, gauntlet, round_robin
from teamenv.tournament.spec import TeamSpec, parse_team_spec, validate_specs
from teamenv.tournament.store import ResultStore

__all__ = [
    "MatchTask", "ResultStore", "StoreError", "TeamSpec", "TeamSpecError", "Tournament",
    "TournamentConfigError", "TournamentError", "TournamentSummary", "gauntlet",
    "parse_team_spec", "round_robin", "run_tournament", "validate_specs",
]
