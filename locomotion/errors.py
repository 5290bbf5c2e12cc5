"""Exception types raised by the locomotion package (all subclass ValueError)."""

from __future__ import annotations

__all__ = ["LocomotionError", "ProfileError", "StepInputError"]


class LocomotionError(ValueError):
    """Base class of every error raised by :mod:`locomotion`."""


class ProfileError(LocomotionError):
    """A profile file is missing, malformed, or a parameter is out of range.

    The message always names the profile, the field and the offending value.
    """

    def __init__(self, profile: str, field: str, value: object, problem: str) -> None:
        self.profile = profile
        self.field = field
        self.value = value
        self.problem = problem
        super().__init__(f"profile {profile!r}: field {field!r} = {value!r}: {problem}")


class StepInputError(LocomotionError):
    """An argument of :meth:`locomotion.Bodies.step` has the wrong shape or value."""

    def __init__(self, field: str, value: object, problem: str) -> None:
        self.field = field
        self.value = value
        self.problem = problem
        super().__init__(f"Bodies.step: argument {field!r} = {value!r}: {problem}")
