"""LocalServer's reading of our effector text: rcsssmj's ``SoccerActionParser``, the same
actions, with a quicker reader of the text for the messages our effectors write.

rcsssmj reads an agent's message byte by byte in Python (``SExpression._parse``), ~320 motor
effectors a cycle in a 7 v 7. Our effectors (``teamenv.league.effectors``) write flat
expressions of atoms separated by one space, ``(name q dq kp kd tau)(beam x y t)(SPK say v
b64)``; for a message that is exactly a sequence of such expressions, ``LocalActionParser``
splits it with one regular expression and builds each action as rcsssmj's ``parse_node``
does (the same tests, the same ``float`` of the same atoms, ``radians``, names with the
agent's prefix). Every other message — nested or empty expressions, other spacing, atoms
outside an expression, a number that does not read, any error — goes to rcsssmj's own
``parse_action``, which then decides (it drops the rest of a message at an error).
``tests/teamenv/league/test_league_local_actions.py`` compares both on recorded and on
malformed messages.
"""

from __future__ import annotations

import base64
import binascii
import re
from math import radians
from typing import Any

#: a message of flat expressions: "(" atom (" " atom)* ")", repeated, nothing else
_FLAT = re.compile(r"(?:\([^() ]+(?: [^() ]+)*\))*")
_EXPR = re.compile(r"\(([^()]*)\)")


def quick_actions(data: bytes | bytearray, model_prefix: str) -> list | None:
    """rcsssmj's actions of a flat message (the module doc), or None: let rcsssmj read it."""
    from rcsssmj.games.soccer.sim.soccer_actions import BeamAction
    from rcsssmj.sim.actions import MotorAction, SpeakerAction

    try:
        text = bytes(data).decode("ascii")
    except UnicodeDecodeError:
        return None
    if not _FLAT.fullmatch(text):
        return None
    actions = []
    try:
        for body in _EXPR.findall(text):
            node = body.split(" ")
            n = len(node)
            head = node[0]
            # SoccerActionParser.parse_node, then DefaultActionParser.parse_node
            if head == "beam" and n == 4:
                actions.append(BeamAction(model_prefix + "beam", (
                    float(node[1]), float(node[2]), radians(float(node[3])))))
            elif head == "syn":
                continue
            elif head == "SPK" and n > 3:
                try:
                    actions.append(SpeakerAction(model_prefix + node[1], float(node[2]) / 100,
                                                 base64.b64decode(node[3], validate=True)))
                except binascii.Error:
                    continue
            elif n == 6:
                actions.append(MotorAction(
                    model_prefix + head, radians(float(node[1])), radians(float(node[2])),
                    float(node[3]), float(node[4]), float(node[5])))
    except Exception:  # noqa: BLE001 - rcsssmj decides what an error drops
        return None
    return actions


def local_action_parser() -> Any:
    """A ``SoccerActionParser`` that reads flat messages with ``quick_actions`` (rcsssmj
    imported here: the humanoid extra)."""
    from rcsssmj.games.soccer.server.soccer_action_parser import SoccerActionParser

    class LocalActionParser(SoccerActionParser):
        """``SoccerActionParser`` with the quick reader for flat messages (module doc)."""

        def parse_action(self, data: bytes | bytearray, model_prefix: str) -> list:
            actions = quick_actions(data, model_prefix)
            if actions is None:
                return super().parse_action(data, model_prefix)
            return actions

    return LocalActionParser()
