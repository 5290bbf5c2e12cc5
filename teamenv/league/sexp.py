"""A small S-expression reader for the league's messages: lists of atoms (str) and lists.

The server's grammar is tiny (parentheses, whitespace-separated atoms, no quoting, no
comments), so a regex tokenizer beats a general library (sexpdata would turn atoms into
Symbol/number objects we would have to undo, and is several times slower per perception).
"""

from __future__ import annotations

import re
from typing import TypeAlias

from .errors import ProtocolError

SExp: TypeAlias = "str | list[SExp]"

_TOKEN = re.compile(r"\(|\)|[^\s()]+")
_BAD_ATOM = re.compile(r"[\s()]")


def parse_all(text: str) -> list[SExp]:
    """Every top-level expression in ``text``; atoms stay strings.

    Raises ProtocolError on an unbalanced parenthesis (naming its offset)."""
    # One findall and a loop over plain strings: a perception is ~300 tokens, 14-22 of them
    # each cycle, so the per-token cost matters; offsets are only looked up for an error.
    root: list[SExp] = []
    top = root
    stack: list[list[SExp]] = []
    push, pop = stack.append, stack.pop
    for tok in _TOKEN.findall(text):
        if tok == "(":
            new: list[SExp] = []
            top.append(new)
            push(top)
            top = new
        elif tok == ")":
            if not stack:
                return _parse_with_offsets(text)
            top = pop()
        else:
            top.append(tok)
    if stack:
        return _parse_with_offsets(text)
    return root


def _parse_with_offsets(text: str) -> list[SExp]:
    """The same reading, slower, keeping offsets: only for unbalanced text, to name where."""
    stack: list[list[SExp]] = [[]]
    opened: list[int] = []
    for match in _TOKEN.finditer(text):
        tok = match.group()
        if tok == "(":
            new: list[SExp] = []
            stack[-1].append(new)
            stack.append(new)
            opened.append(match.start())
        elif tok == ")":
            if len(stack) == 1:
                raise ProtocolError(f"unbalanced ')' at offset {match.start()} in {text[:80]!r}")
            stack.pop()
            opened.pop()
        else:
            stack[-1].append(tok)
    if len(stack) != 1:
        raise ProtocolError(f"unclosed '(' at offset {opened[-1]} in {text[:80]!r}")
    return stack[0]


def to_text(expr: SExp) -> str:
    """The S-expression text of ``expr`` (inverse of ``parse_all`` for one expression)."""
    if isinstance(expr, str):
        if not expr or _BAD_ATOM.search(expr):
            raise ProtocolError(f"atom {expr!r} is empty or holds a parenthesis or whitespace")
        return expr
    return "(" + " ".join(to_text(e) for e in expr) + ")"
