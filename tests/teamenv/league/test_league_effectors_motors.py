"""``effectors.motors`` (a robot's motor effectors at once) is ``motor``'s text exactly."""

from __future__ import annotations

import numpy as np
import pytest

from teamenv.league import effectors
from teamenv.league.effectors import EffectorError
from teamenv.league.t1 import T1_MOTORS

NAMES = tuple(T1_MOTORS)


def _one_by_one(names, *columns) -> str:
    return effectors.message(*(
        effectors.motor(m, *(c if np.ndim(c) == 0 else c[k] for c in columns))
        for k, m in enumerate(names)))


def test_motors_is_the_text_of_motor_for_every_motor() -> None:
    rng = np.random.default_rng(0)
    n = len(NAMES)
    for trial in range(200):
        scale = 10.0 ** rng.integers(-9, 5, size=(5, n))
        columns = list(rng.standard_normal((5, n)) * scale)
        columns[0][trial % n] = -0.0                       # "-0"
        columns[1][(trial + 3) % n] = 1e-300               # tiny: exponent form
        assert effectors.motors(NAMES, *columns) == _one_by_one(NAMES, *columns)
    # one number for every motor, lists, float32 and int values, default fields
    q = rng.standard_normal(n).astype(np.float32)
    for columns in ([q, 0.0, 25.0, 0.6], [list(q), -0.0, 25, np.float64(0.6), 1],
                    [q.tolist(), np.zeros(n), np.arange(n), [0.5] * n]):
        assert effectors.motors(NAMES, *columns) == _one_by_one(NAMES, *columns)
    assert effectors.motors([], []) == "(syn)" == effectors.message()


@pytest.mark.parametrize("names, columns", [
    (NAMES, [np.r_[0.0, np.nan, np.zeros(21)], 0.0, 1.0, 1.0]),   # not finite
    (NAMES, [np.zeros(23), np.inf, 1.0, 1.0]),
    (NAMES, [np.full(23, 1e307), 0.0, 1.0, 1.0]),                 # finite, inf in degrees
    (("ok", "bad name"), [[0.0, 0.0], 0.0, 1.0, 1.0]),            # not a name
    (NAMES, [["x"] * 23, 0.0, 1.0, 1.0]),                         # not a number
])
def test_motors_raises_motors_error(names, columns) -> None:
    with pytest.raises(EffectorError) as theirs:
        _one_by_one(names, *columns)
    with pytest.raises(EffectorError) as ours:
        effectors.motors(names, *columns)
    assert str(ours.value) == str(theirs.value)


def test_motors_needs_a_value_per_motor() -> None:
    with pytest.raises(EffectorError, match="22 values of a field for 23 motors"):
        effectors.motors(NAMES, np.zeros(22))


def test_the_walk_network_and_our_walker_send_motors_text() -> None:
    pytest.importorskip("mujoco")
    from teamenv.league.controller import WalkerController, shared_t1
    from teamenv.league.network_walk import KD, KP, NETWORK_MOTORS

    rng = np.random.default_rng(1)
    targets = rng.standard_normal(len(NETWORK_MOTORS))
    assert effectors.motors(NETWORK_MOTORS, targets, 0.0, KP, KD) == _one_by_one(
        NETWORK_MOTORS, targets, 0.0, KP, KD)
    walkers = [WalkerController(), WalkerController()]
    assert walkers[0]._t1.model is walkers[1]._t1.model is shared_t1().model  # compiled once
    with pytest.raises(ValueError, match="read-only"):
        shared_t1().q_stance[0] = 1.0
    q, dq = rng.standard_normal((2, 23))
    w = walkers[0]
    assert w._motor_message(q, dq) == _one_by_one(w._motors, q, dq, w._t1.kp, w._t1.kd)
