"""paramkit.checks: the rules a field's annotation and metadata imply, and the one message."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Literal

import numpy as np
import pytest

from paramkit import check_fields, field_problem, in_range, invalid, non_negative, one_of, positive


class Bad(ValueError):
    pass


@dataclass(frozen=True)
class Demo:
    count: int = field(default=1, metadata=in_range(1))
    ratio: float = field(default=0.5, metadata=in_range(0.0, 1.0, low_open=True))
    horizon: float = field(default=math.inf, metadata=positive(infinite=True))
    flag: bool = False
    mode: str = field(default="a", metadata=one_of("a", "b"))
    order: Literal["x", "y"] = "x"
    span: tuple[float, float] = field(default=(0.0, 1.0), metadata=non_negative())
    sizes: tuple[int, ...] = (1, 2)
    where: Path | None = None
    hook: Callable[[], None] | None = None
    limit: int | None = field(default=None, metadata=in_range(0, 6))

    def __post_init__(self) -> None:
        check_fields(self, Bad)


def test_good_values_pass_numpy_numbers_too():
    Demo()
    Demo(count=np.int64(3), ratio=np.float32(1.0), horizon=5, flag=True, mode="b",
         order="y", span=[0.5, 2.0], sizes=(), where=Path("x"), hook=print, limit=6)


@pytest.mark.parametrize(("kwargs", "message"), [
    ({"count": 0}, "Demo.count must be >= 1, got 0"),
    ({"count": 2.0}, "Demo.count must be an integer, got 2.0"),
    ({"count": True}, "Demo.count must be an integer, got True"),
    ({"ratio": 0.0}, r"Demo.ratio must be in \(0, 1\], got 0.0"),
    ({"ratio": math.nan}, "Demo.ratio must be a finite number, got nan"),
    ({"ratio": math.inf}, "Demo.ratio must be a finite number, got inf"),
    ({"ratio": "0.5"}, "Demo.ratio must be a finite number, got '0.5'"),
    ({"horizon": -math.inf}, "Demo.horizon must be > 0, got -inf"),
    ({"horizon": math.nan}, r"Demo.horizon must be a number \(not NaN\), got nan"),
    ({"flag": 1}, "Demo.flag must be true or false, got 1"),
    ({"mode": "c"}, r"Demo.mode must be one of \['a', 'b'\], got 'c'"),
    ({"order": "z"}, r"Demo.order must be one of \['x', 'y'\], got 'z'"),
    ({"span": (1.0,)}, r"Demo.span must be 2 finite numbers, got \(1.0,\)"),
    ({"span": (-1.0, 1.0)}, r"Demo.span must be 2 numbers, each >= 0, got \(-1.0, 1.0\)"),
    ({"sizes": (1, 2.5)}, r"Demo.sizes must be integers, got \(1, 2.5\)"),
    ({"where": 3}, r"Demo.where must be a path \(string\) or null, got 3"),
    ({"hook": "print"}, "Demo.hook must be a callable or null, got 'print'"),
    ({"limit": 7}, r"Demo.limit must be in \[0, 6\], got 7"),
    ({"count": -10 ** 400}, "Demo.count must be >= 1, got <int of 1329 bits>"),  # short
])
def test_a_bad_value_names_the_class_field_rule_and_value(kwargs, message):
    with pytest.raises(Bad, match=f"^{message}$"):
        Demo(**kwargs)


def test_a_default_range_covers_the_number_fields_that_declare_none():
    @dataclass(frozen=True)
    class Loose:
        a: float = 1.0
        b: float = field(default=-1.0, metadata=in_range(high=0.0))
        c: str = "text"

        def __post_init__(self) -> None:
            check_fields(self, Bad, default=non_negative())

    Loose()
    with pytest.raises(Bad, match=r"^Loose.a must be >= 0, got -2.0$"):
        Loose(a=-2.0)


def test_cross_field_rules_use_the_same_message():
    @dataclass(frozen=True)
    class Pair:
        low: float = 0.0
        high: float = 1.0

    error = invalid(Pair(2.0, 1.0), "low", "< high (1.0)", Bad)
    assert isinstance(error, Bad) and str(error) == "Pair.low must be < high (1.0), got 2.0"


def test_field_problem_is_the_rule_alone():
    assert field_problem(3, int, in_range(1)) is None
    assert field_problem(0, int, in_range(1)) == ">= 1"
    assert field_problem(None, int | None) is None
    assert field_problem(True, int) == "an integer"
