"""The exception types teamenv raises; messages name the agent, field and value."""

from __future__ import annotations

from paramkit.checks import value_repr as value_repr  # the one short, never-failing repr


class TeamEnvError(Exception):
    """Base class of every error teamenv raises on purpose."""


class ConfigError(TeamEnvError, ValueError):
    """A config value or key is not valid (unknown key, out of range, wrong type)."""


class ActionError(TeamEnvError, ValueError):
    """An action is malformed: unknown or missing agent, wrong shape, NaN/inf, out of range."""


class MessageError(ActionError):
    """A ``say`` message breaks the channel's rules (too long, illegal character)."""


class TeamLoadError(TeamEnvError, LookupError):
    """A team spec does not name a registered team or an importable ``module:Class``."""


class MissingExtraError(TeamEnvError, ImportError):
    """An optional dependency is missing; the message names the extra to install."""

    def __init__(self, extra: str, package: str, feature: str) -> None:
        super().__init__(
            f"{feature} needs the '{extra}' extra ({package} is not installed): "
            f"pip install -e '.[{extra}]' in the teamenv checkout"
        )
        self.extra = extra
        self.package = package


class TeamFault(TeamEnvError, RuntimeError):
    """A team plugin failed during a cycle: it raised, returned invalid actions, or was too slow.

    ``side`` is "left" or "right"; ``reason`` one of "raised", "invalid_action", "too_slow".
    """

    def __init__(self, side: str, reason: str, detail: str) -> None:
        super().__init__(f"team on the {side} side: {reason}: {detail}")
        self.side = side
        self.reason = reason
        self.detail = detail


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised by the ``teamenv`` command in its main thread like Ctrl-C, so a command
    stops the same clean way (a tournament's worker pool, fork server and resource tracker
    shut down; what is stored stays stored)."""
