"""The league's play modes, named as SimSpark names them, and their team-relative mirror."""

from __future__ import annotations

from enum import IntEnum


class PlayMode(IntEnum):
    """Play modes. ``_Left``/``_Right`` name the team (left = the team listed first)."""

    BeforeKickOff = 0
    KickOff_Left = 1
    KickOff_Right = 2
    PlayOn = 3
    KickIn_Left = 4
    KickIn_Right = 5
    CornerKick_Left = 6
    CornerKick_Right = 7
    GoalKick_Left = 8
    GoalKick_Right = 9
    Goal_Left = 10
    Goal_Right = 11
    GameOver = 12

    @property
    def team(self) -> int | None:
        """0 for a ``_Left`` mode, 1 for ``_Right``, None for modes of neither team."""
        return _TEAM[self]

    @property
    def kind(self) -> str:
        """The mode without its team suffix, e.g. ``CornerKick``."""
        return _KIND[self]

    @classmethod
    def of(cls, kind: str, team: int) -> PlayMode:
        """The mode ``kind`` for team 0 (left) or 1 (right)."""
        return cls[f"{kind}_{'Left' if team == 0 else 'Right'}"]

    def for_team(self, team: int) -> PlayMode:
        """This mode as team ``team`` sees it: its own modes are ``_Left``."""
        if team == 0:
            return self
        return _MIRROR[self]


def _team_of_name(name: str) -> int | None:
    if name.endswith("_Left"):
        return 0
    if name.endswith("_Right"):
        return 1
    return None


# Looked up per cycle by the referee and perception: tables instead of string work.
_TEAM: dict[PlayMode, int | None] = {m: _team_of_name(m.name) for m in PlayMode}
_KIND: dict[PlayMode, str] = {
    m: m.name.rsplit("_", 1)[0] if _TEAM[m] is not None else m.name for m in PlayMode}
_MIRROR: dict[PlayMode, PlayMode] = {
    m: m if _TEAM[m] is None else PlayMode.of(_KIND[m], 1 - _TEAM[m]) for m in PlayMode}


PLAY_MODES: tuple[str, ...] = tuple(m.name for m in PlayMode)
SET_PLAYS = frozenset({"KickIn", "CornerKick", "GoalKick"})
