"""LocalServer's perceptions computed straight from the simulation (``local_perceiver``) are
the wire text's bit for bit, with the same draws from the hearing model's generator; where
they cannot be, the server's own generation runs."""

from __future__ import annotations

import math

import numpy as np
import pytest

pytestmark = pytest.mark.humanoid
pytest.importorskip("rcsssmj")
pytest.importorskip("mujoco")

from teamenv.league import local_server as ls  # noqa: E402
from teamenv.league.local_perceiver import LocalPerceiver, Unhandled, supported  # noqa: E402
from teamenv.league.local_perception import perception_text  # noqa: E402
from teamenv.league.match import LeagueMatchOptions  # noqa: E402
from teamenv.league.perception import parse_perception  # noqa: E402
from tests.teamenv.league.recorders import play_on_checking_server  # noqa: E402
from tests.teamenv.league.test_league_local_perception import bits  # noqa: E402


def _state_bits(state) -> tuple:
    return (state[0], state[1].tobytes(), *state[2:])


class _Both(ls.LocalServer):
    """Every cycle through the perceiver and through the server's generation and the wire
    text, from the same generator state: the same perceptions and the same draws."""

    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        assert self._perceiver is not None
        self.compared = self.drawn = 0
        self.seen = {"vision": 0, "players": 0, "heard": 0}

    def _generate(self, keys):
        keys = list(keys)
        start = self._np_state
        direct = self._in_own_rng(self._perceiver.perceive)
        after_direct, self._np_state = self._np_state, start
        self._in_own_rng(self.sim.generate_perceptions)
        assert _state_bits(self._np_state) == _state_bits(after_direct)
        self.drawn += _state_bits(start) != _state_bits(after_direct)
        out = {}
        for key in keys:
            agent = self._agents[key]
            text = perception_text(agent.perceptions, self._encoder)
            ours = direct[agent]
            assert bits(ours) == bits(parse_perception(text)), text
            self.compared += 1
            self.seen["vision"] += ours.vision is not None and bool(ours.vision.objects)
            self.seen["players"] += ours.vision is not None and bool(ours.vision.players)
            self.seen["heard"] += bool(ours.heard)
            out[key] = ours
        return out


def test_rcsssmj_is_the_release_mirrored() -> None:
    assert supported()


def test_a_match_perceives_the_wires_bits_from_the_simulation(monkeypatch) -> None:
    server = play_on_checking_server(
        monkeypatch, _Both, "full", "full",
        LeagueMatchOptions(team_size=3, game_s=1.2, server="local"), seed=2)
    assert server.compared >= 6 * 60
    assert min(server.seen.values()) > 0, server.seen


def test_five_talkers_draw_from_the_generator_as_the_server_does() -> None:
    """More than three messages heard: the hearing model drops some at random."""
    from teamenv.league import effectors
    from teamenv.league.t1 import T1_MOTORS

    server = _Both(seed=11)
    keys = [("A", 1), ("A", 2), ("A", 3), ("B", 1), ("B", 2)]
    server.join_many(keys)
    stand = effectors.message(*(effectors.motor(m, 0.0, 0.0, 50.0, 1.0) for m in T1_MOTORS))
    for k in range(12):
        server.cycle({key: stand + effectors.say(bytes([k, i + 1, 7]))
                      for i, key in enumerate(keys)})
    assert server.drawn >= 5 and server.seen["heard"] > 0, (server.drawn, server.seen)


def test_what_the_wire_would_refuse_goes_through_the_servers_generation() -> None:
    from teamenv.league.errors import ProtocolError

    server = ls.LocalServer()
    server.join("A", 1)
    server.cycle({})
    perceiver = server._perceiver
    assert isinstance(perceiver, LocalPerceiver)
    adr = int(server.sim.mj_model.sensor("r-0-1-q_hj1").id)
    adr = int(server.sim.mj_model.sensor_adr[adr])
    calls = []
    original = server.sim.generate_perceptions

    def generate(*args, **kwargs):
        calls.append(1)
        return original(*args, **kwargs)

    server.sim.generate_perceptions = generate
    server.sim.mj_data.sensordata[adr] = math.nan
    with pytest.raises(Unhandled):
        perceiver.perceive()
    state = server._np_state
    with pytest.raises(ProtocolError, match="agent A 1: perceptor HJ"):
        server._generate([("A", 1)])           # the server's generation and the parser
    assert calls == [1] and _state_bits(server._np_state) == _state_bits(state)


def test_shortcuts_off_use_the_servers_generation() -> None:
    server = ls.LocalServer(shortcuts=False)
    assert server._perceiver is None
    server.join("A", 1)
    p = server.cycle({})[("A", 1)]
    assert len(p.joints) == 23 and np.isfinite(p.time)
