"""LocalServer's quick reader of our effector text (``local_actions``) gives rcsssmj's
actions: on every message of a match and on malformed ones, which go to rcsssmj's reader."""

from __future__ import annotations

import pytest

pytestmark = pytest.mark.humanoid
pytest.importorskip("rcsssmj")
pytest.importorskip("mujoco")

from teamenv.league import local_server as ls  # noqa: E402
from teamenv.league.local_actions import local_action_parser  # noqa: E402
from teamenv.league.match import LeagueMatchOptions, play_league_match  # noqa: E402
from tests.teamenv.league.test_league_local_perception import bits  # noqa: E402


def _actions(actions) -> list:
    return [(type(a).__name__, bits({k: v for k, v in vars(a).items()})) for a in actions]


def _same(message: str, prefix: str = "A_3-") -> list:
    from rcsssmj.games.soccer.server.soccer_action_parser import SoccerActionParser

    data = message.encode("ascii")
    theirs = SoccerActionParser().parse_action(data, prefix)
    ours = local_action_parser().parse_action(data, prefix)
    assert _actions(ours) == _actions(theirs), message
    return theirs


MALFORMED = [
    "", "(syn)", "(he1 1 2 3 4 5)", "(beam 1 2 90)(he1 1 2 3 4 5)", "(beam 1 2)",
    "(beam 1 2 3 4 5)", "(syn 1 2 3 4 5)", "(SPK say 100 AAEC)", "(SPK say 100 A)",
    "(SPK say 100)", "(SPK say x AAEC)(he1 1 2 3 4 5)", "(he1 1 2 3 4 x)(he2 1 2 3 4 5)",
    "(he1 1 2 3 4 5)(he2 1 2 3 4 x)", "(he1 1 2 3 4 5", "he1 1 2 3 4 5", "()(he1 1 2 3 4 5)",
    "(he1  1 2 3 4 5)", "(he1 1 2 3 4 5)junk(he2 1 2 3 4 5)", "(he1 (1) 2 3 4 5)",
    "(he1 1 2 3 4 5))", "(he1 1e400 -0 inf nan 1_0)", "(he1\t1 2 3 4 5)", "(a b)(c d e)",
    "(he1 1 2 3 4 5 6)", " (he1 1 2 3 4 5)", "(he1 1 2 3 4 5) ",
]


@pytest.mark.parametrize("message", MALFORMED)
def test_odd_and_malformed_messages_read_as_rcsssmj_reads_them(message) -> None:
    _same(message)


def test_every_message_of_a_match_reads_as_rcsssmj_reads_it(monkeypatch) -> None:
    seen: list[str] = []
    original = ls.LocalServer.cycle

    def cycle(self, answers=None):
        seen.extend((answers or {}).values())
        return original(self, answers)

    monkeypatch.setattr(ls.LocalServer, "cycle", cycle)
    play_league_match("full", "chaser", LeagueMatchOptions(team_size=2, game_s=1.0,
                                                           server="local"), seed=1)
    assert len(seen) > 4 * 50
    kinds = set()
    for message in seen:
        kinds.update(type(a).__name__ for a in _same(message))
    assert {"MotorAction", "BeamAction", "SpeakerAction"} <= kinds, kinds
