"""paramkit.Registry: names -> values or factories, one way for every kind of profile."""

from __future__ import annotations

import pytest

from paramkit import Registry


class Bad(ValueError):
    pass


def test_values_and_factories_by_name():
    made = []
    reg: Registry[int] = Registry("number", Bad)
    reg.register("one", 1)
    reg.register("two", factory=lambda: made.append(1) or 2)
    assert reg.names() == ["one", "two"] and list(reg) == ["one", "two"] and len(reg) == 2
    assert "two" in reg and "three" not in reg and 3 not in reg
    assert made == []  # a factory runs on the first get only
    assert reg.get("two") == 2 and reg["two"] == 2 and made == [1]
    assert dict(reg) == {"one": 1, "two": 2} and reg.items() == [("one", 1), ("two", 2)]


def test_unknown_names_list_the_choices():
    reg = Registry("vision profile", Bad)
    reg.register("simspark", object())
    reg.register("mj", object())
    with pytest.raises(Bad, match=r"^unknown vision profile 'nao'; choose one of \['mj', "
                                  r"'simspark'\]$"):
        reg.get("nao")
    with pytest.raises(Bad, match="unknown vision profile"):
        reg[["not", "hashable"]]


def test_a_name_is_registered_once_unless_replaced():
    reg = Registry("channel profile", Bad)
    reg.register("a", 1)
    with pytest.raises(Bad, match="'a' is registered already"):
        reg.register("a", 2)
    reg.register("a", factory=lambda: 3, replace=True)
    assert reg.get("a") == 3
    with pytest.raises(Bad, match="a value or a factory"):
        reg.register("b")
    with pytest.raises(Bad, match="a value or a factory"):
        reg.register("b", 1, factory=lambda: 1)
    with pytest.raises(Bad, match="non-empty string"):
        reg.register("", 1)
    reg.unregister("a")
    assert "a" not in reg
    with pytest.raises(Bad, match="unknown channel profile 'a'"):
        reg.unregister("a")
