"""LocalServer's cached motor command (``local_motors``) writes what rcsssmj's own writes."""

from __future__ import annotations

import math

import numpy as np
import pytest

pytestmark = pytest.mark.humanoid
pytest.importorskip("rcsssmj")
pytest.importorskip("mujoco")

from teamenv.league import effectors  # noqa: E402
from teamenv.league.local_motors import CachedMotorCommand  # noqa: E402
from teamenv.league.local_server import LocalServer  # noqa: E402
from teamenv.league.t1 import T1_MOTORS  # noqa: E402


def _message(k: int, unum: int) -> str:
    """Every motor, targets, gains and torques changing with the cycle and the robot."""
    return effectors.message(*(
        effectors.motor(m, 0.3 * math.sin(0.1 * k + i + unum), 0.1 * math.cos(0.2 * k + i),
                        20.0 + i + 3 * unum + k % 5, 0.5 + 0.1 * i, 0.01 * (k % 3) - 0.01)
        for i, m in enumerate(T1_MOTORS)))


def _state(server: LocalServer) -> list[bytes]:
    m, d = server.sim.mj_model, server.sim.mj_data
    return [a.tobytes() for a in (d.ctrl, m.actuator_gainprm, m.actuator_biasprm, d.qpos,
                                  d.qvel)]


def test_the_cached_command_writes_rcsssmjs_controls_and_gains() -> None:
    servers = [LocalServer(shortcuts=cached) for cached in (False, True)]
    assert not isinstance(servers[0].sim.ctrl_motor, CachedMotorCommand)
    assert isinstance(servers[1].sim.ctrl_motor, CachedMotorCommand)
    for s in servers:
        s.join("A", 1)
    for k in range(8):
        states = [(s.cycle({("A", 1): _message(k, 1)}), _state(s))[1] for s in servers]
        assert states[0] == states[1], k
    # a join recompiles the world (new model, data, actuator ids): still the same
    for s in servers:
        s.join("B", 2)
    for k in range(8, 16):
        states = [(s.cycle({("A", 1): _message(k, 1), ("B", 2): _message(k, 2)}),
                   _state(s))[1] for s in servers]
        assert states[0] == states[1], k
    m = servers[1].sim.mj_model
    assert np.any(m.actuator_gainprm[:, 0] != 0)                    # the gains were written


def test_an_unknown_motor_raises_as_rcsssmj_does() -> None:
    server = LocalServer()
    server.join("A", 1)
    command = server.sim.ctrl_motor
    with pytest.raises(KeyError) as theirs:
        command.original("no_such_motor", 0.0, 0.0, 1.0, 1.0, 0.0)
    with pytest.raises(KeyError) as ours:
        command("no_such_motor", 0.0, 0.0, 1.0, 1.0, 0.0)
    assert str(ours.value) == str(theirs.value)
