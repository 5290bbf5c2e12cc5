"""The exception types of the league client; messages name the agent, perceptor and value."""

from __future__ import annotations

from teamenv.errors import TeamEnvError


class LeagueError(TeamEnvError, RuntimeError):
    """Base class of the league client's errors."""


class ProtocolError(LeagueError, ValueError):
    """The server sent something the protocol does not allow (bad frame, bad S-expression)."""


class UnknownPerceptorError(ProtocolError):
    """A perception holds a perceptor kind this client does not know (strict parsing)."""


class ServerDiedError(LeagueError):
    """The server process exited or closed the connection while a client still needed it."""
