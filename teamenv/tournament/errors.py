"""The exception types of the tournament layer; messages name the team spec, field and value."""

from __future__ import annotations

from teamenv.errors import ConfigError, TeamEnvError, TeamLoadError


class TournamentError(TeamEnvError):
    """Base class of every error the tournament layer raises on purpose."""


class TeamSpecError(TournamentError, TeamLoadError):
    """A team spec is malformed, names an unknown team, or its config overrides are rejected."""


class TournamentConfigError(TournamentError, ConfigError):
    """A tournament definition is invalid (format, games, seeds, match options, backend)."""


class StoreError(TournamentError, RuntimeError):
    """The results database cannot be used as asked (missing tournament, definition mismatch)."""
