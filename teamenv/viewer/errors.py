"""The viewer's exception types; each carries the HTTP status the server answers with."""

from __future__ import annotations

from teamenv.errors import TeamEnvError


class ViewerError(TeamEnvError):
    """The viewer cannot show what was asked; ``status`` is the HTTP status to answer with
    (404: no such match or page, 422: a replay or database that cannot be read)."""

    def __init__(self, message: str, status: int = 422) -> None:
        super().__init__(message)
        self.status = status
