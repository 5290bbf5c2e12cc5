"""Two helpers every package of the project shares: named registries (``Registry``) and the
checks of a parameter dataclass's fields (``check_fields``).

Why a package of its own: ``comms`` and ``locomotion`` are leaves that may import nothing of
``teamenv`` or ``strategy`` (``tests/test_layering.py``), yet they hold profiles and parameter
dataclasses too, and a newcomer should add a vision profile, a channel profile and a
locomotion profile the same way, and get the same message for a bad number in any package.
``portable_math`` is the other leaf below them, but it is the portable float math and nothing
else. So this is the second leaf at the bottom: it imports only the standard library, knows no
error type of any package (each caller passes its own: ``teamenv.errors.ConfigError``,
``comms.errors.ChannelError`` ...), and nothing in it is specific to robot soccer.

- ``paramkit.registry``: ``Registry``, name -> value or factory, ``get``/``names``/``register``.
- ``paramkit.checks``: ``check_fields``, the rules a field's type annotation implies, the
  field metadata ``in_range``/``positive``/``non_negative``/``one_of``, and one message
  format: ``"<Class>.<field> must be <rule>, got <value>"``.
"""

from paramkit.checks import (
    Bounds,
    check_fields,
    field_problem,
    in_range,
    invalid,
    non_negative,
    one_of,
    positive,
    value_repr,
)
from paramkit.registry import Registry

__all__ = [
    "Bounds",
    "Registry",
    "check_fields",
    "field_problem",
    "in_range",
    "invalid",
    "non_negative",
    "one_of",
    "positive",
    "value_repr",
]
