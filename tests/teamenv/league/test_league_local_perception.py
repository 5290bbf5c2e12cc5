"""LocalServer's perceptions straight from rcsssmj's objects (``local_perception``) are the
wire text's perceptions bit for bit, and a match plays the same with either path."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

pytestmark = pytest.mark.humanoid
pytest.importorskip("rcsssmj")
pytest.importorskip("mujoco")

from teamenv.league import local_server as ls  # noqa: E402
from teamenv.league.local_perception import perception_from_objects, perception_text  # noqa: E402
from teamenv.league.match import LeagueMatchOptions, play_league_match  # noqa: E402
from teamenv.league.perception import parse_perception  # noqa: E402
from tests.teamenv.league.recorders import play_on_checking_server  # noqa: E402


def bits(value):
    """``value`` with every float as its bit pattern (``-0.0 != 0.0``, NaN == NaN), dict
    orders and types kept: equal ``bits`` is equal bit for bit."""
    if isinstance(value, float):
        return ("f", np.float64(value).view(np.int64).item())
    if dataclasses.is_dataclass(value):
        return (type(value).__name__,
                *(bits(getattr(value, f.name)) for f in dataclasses.fields(value)))
    if isinstance(value, dict):
        return ("d", *((k, bits(v)) for k, v in value.items()))
    if isinstance(value, (list, tuple)):
        return (type(value).__name__, *(bits(v) for v in value))
    return (type(value).__name__, value)


def test_bits_tell_apart_what_equality_does_not() -> None:
    from teamenv.league.perception import Perception

    assert bits(0.0) != bits(-0.0) and bits(float("nan")) == bits(float("nan"))
    a, b = Perception(positions={"a": (1.0,), "b": (2.0,)}), Perception(
        positions={"b": (2.0,), "a": (1.0,)})
    assert a == b and bits(a) != bits(b)                    # the dict order counts


class _Both(ls.LocalServer):
    """Every perception through both paths: they must agree bit for bit."""

    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        self._perceiver = None          # the objects' reader, not the direct perceiver
        self.compared = 0
        self.seen = {"vision": 0, "players": 0, "heard": 0, "joints": 0}

    def _perceive(self, key):
        objects = self._agents[key].perceptions
        text = perception_text(objects, self._encoder)
        parsed = parse_perception(text)
        direct = perception_from_objects(objects)
        assert direct is not None, text
        assert bits(direct) == bits(parsed), text
        self.compared += 1
        self.seen["vision"] += direct.vision is not None and bool(direct.vision.objects)
        self.seen["players"] += direct.vision is not None and bool(direct.vision.players)
        self.seen["heard"] += bool(direct.heard)
        self.seen["joints"] += len(direct.joints) == 23
        return direct


def test_a_match_perceives_the_same_bits_without_the_text(monkeypatch) -> None:
    # "full" talks (MIC), both sides see marks, the ball and players; a goal-less kick-off
    server = play_on_checking_server(
        monkeypatch, _Both, "full", "chaser",
        LeagueMatchOptions(team_size=2, game_s=1.5, server="local"), seed=3)
    assert server.compared >= 4 * 80
    assert min(server.seen.values()) > 0, server.seen


def _objects():
    """One agent's perception objects after a few cycles of a fresh LocalServer."""
    server = ls.LocalServer()
    server._perceiver = None            # the server's objects are made (and read)
    server.join("A", 1)
    server.join("B", 1)
    for _ in range(3):
        server.cycle({})
    return server, list(server._agents[("A", 1)].perceptions)


def test_what_the_text_would_refuse_or_read_otherwise_goes_through_the_text() -> None:
    from rcsssmj.sim.perceptions import PositionPerception, TimePerception

    server, objects = _objects()
    assert perception_from_objects(objects) is not None
    assert perception_from_objects([]) is None                    # the text is "(syn)"
    for odd in (PositionPerception("torso_pos", float("nan"), 0.0, 0.0),   # not finite
                PositionPerception("a name", 0.0, 0.0, 0.0),                # not one atom
                PositionPerception("torso_pos", True, 0.0, 0.0),            # "True"
                TimePerception("later", 1.0),                               # not (now ..)
                object()):                                                  # unknown kind
        assert perception_from_objects([*objects, odd]) is None, odd
    # numbers that are no float64 read as their text does (a float32 as its float64 value)
    for x in (np.float32(0.1), np.float16(-2.5), np.int32(3), 7):
        odd = PositionPerception("torso_pos", x, 0.0, 0.0)
        direct = perception_from_objects([*objects, odd])
        assert direct is not None and direct.positions["torso_pos"][0] == float(x)
        assert bits(direct) == bits(parse_perception(perception_text([*objects, odd],
                                                                     server._encoder)))


def test_a_non_finite_value_raises_the_parsers_error(monkeypatch) -> None:
    from rcsssmj.sim.perceptions import PositionPerception

    from teamenv.league.errors import ProtocolError

    server, objects = _objects()
    agent = server._agents[("A", 1)]
    agent.set_perceptions([*objects, PositionPerception("torso_pos", math.inf, 0.0, 0.0)])
    with pytest.raises(ProtocolError, match="agent A 1: perceptor pos torso_pos"):
        server._perceive(("A", 1))


def _replay(tmp_path, name: str, fast: bool, monkeypatch) -> dict:
    from teamenv.replay import load_replay

    original = ls.LocalServer

    def make(*args, **kwargs):
        return original(*args, shortcuts=fast, **kwargs)

    monkeypatch.setattr(ls, "LocalServer", make)
    path = tmp_path / name
    result = play_league_match("full", "chaser", LeagueMatchOptions(team_size=2, game_s=2.0,
                                                                    server="local"),
                               seed=5, replay_path=path)
    monkeypatch.setattr(ls, "LocalServer", original)
    replay = load_replay(path)
    return {"score": result.score, **{k: getattr(replay, k) for k in (
        "ball", "players", "fallen", "play_mode", "touch_cycle", "kick_cycle")}}


def test_a_match_replays_the_same_on_rcsssmjs_own_paths_and_ours(tmp_path, monkeypatch) -> None:
    """rcsssmj's own paths (the wire text both ways, its motor command) v the shortcuts."""
    text = _replay(tmp_path, "text.npz", False, monkeypatch)
    direct = _replay(tmp_path, "direct.npz", True, monkeypatch)
    assert text["score"] == direct["score"]
    for name in ("ball", "players", "fallen", "play_mode", "touch_cycle", "kick_cycle"):
        np.testing.assert_array_equal(text[name], direct[name])
        assert text[name].tobytes() == direct[name].tobytes()
    assert np.ptp(direct["players"][:, :, 0]) > 0               # something moved
