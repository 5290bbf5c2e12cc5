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
        if self.name.endswith("_Left"):
            return 0
        if self.name.endswith("_Right"):
            return 1
        return None

    @property
    def kind(self) -> str:
        """The mode without its team suffix, e.g. ``CornerKick``."""
        return self.name.rsplit("_", 1)[0] if self.team is not None else self.name

    @classmethod
    def of(cls, kind: str, team: int) -> PlayMode:
        """The mode ``kind`` for team 0 (left) or 1 (right)."""
        return cls[f"{kind}_{'Left' if team == 0 else 'Right'}"]

    def for_team(self, team: int) -> PlayMode:
        """This mode as team ``team`` sees it: its own modes are ``_Left``."""
        if team == 0 or self.team is None:
            return self
        return PlayMode.of(self.kind, 1 - self.team)


PLAY_MODES: tuple[str, ...] = tuple(m.name for m in PlayMode)
SET_PLAYS = frozenset({"KickIn", "CornerKick", "GoalKick"})
