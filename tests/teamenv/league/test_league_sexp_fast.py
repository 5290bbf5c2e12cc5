"""The S-expression reader's fast path reads exactly what the offset-keeping one reads, and
unbalanced text still names the offset."""

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from teamenv.league.errors import ProtocolError
from teamenv.league.perception import parse_perception
from teamenv.league.sexp import _parse_with_offsets, parse_all

ATOMS = st.text(st.sampled_from("abcXYZ019.-_+=/"), min_size=1, max_size=6)
EXPRS = st.recursive(ATOMS, lambda inner: st.lists(inner, max_size=4), max_leaves=20)


def _text(expr, space: str) -> str:
    if isinstance(expr, str):
        return expr
    return "(" + space.join(_text(e, space) for e in expr) + ")"


@settings(max_examples=300, deadline=None)
@given(st.lists(EXPRS, max_size=5), st.sampled_from([" ", "  ", "\n", " \t"]))
def test_fast_reader_equals_the_offset_reader(exprs, space):
    text = "".join(_text(e, space) for e in exprs)
    assert parse_all(text) == _parse_with_offsets(text)


@pytest.mark.parametrize("text, where", [("(a (b c)", "unclosed '(' at offset 0"),
                                         ("(a) b)", "unbalanced ')' at offset 5"),
                                         ("((x)", "unclosed '(' at offset 0")])
def test_unbalanced_text_names_the_offset(text, where):
    with pytest.raises(ProtocolError, match=where.replace("(", r"\(").replace(")", r"\)")):
        parse_all(text)


def test_hinge_joint_fast_path_equals_the_checked_path():
    p = parse_perception("(HJ (n he1)(ax 12.5)(vx -3.25))(HJ (n he2)(ax 1e-3)(vx 0))")
    assert p.joints["he1"].angle == pytest.approx(0.2181661564992912, abs=0)
    assert p.joints["he1"].velocity == -0.05672320068981571
    assert p.joints["he2"].angle == 1e-3 * 3.141592653589793 / 180.0
    for bad, why in [("(HJ (n he1)(ax inf)(vx 0))", "not finite"),
                     ("(HJ (n he1)(ax x)(vx 0))", "expected a number"),
                     ("(HJ (n he1)(vx 0)(ax 1))", r"expected \(ax"),
                     ("(HJ (n (he1))(ax 1)(vx 0))", "expected a name")]:
        with pytest.raises(ProtocolError, match=why):
            parse_perception(bad)
