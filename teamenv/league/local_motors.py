"""rcsssmj's motor command (``Simulation.ctrl_motor``) with the actuator look-ups done once.

Every motor effector of every robot, every cycle, ends in ``ctrl_motor(name, q, dq, kp, kd,
tau)``, which finds the motor's three actuators (``<name>_tau``, ``_pos``, ``_vel``) by name in
the MuJoCo model and data (six named look-ups, ~3 µs each) and writes the command into their
controls and gains. A 7 v 7 sends 14 x 23 of them per cycle: about a tenth of a LocalServer
match's CPU went into the look-ups. ``CachedMotorCommand`` keeps each motor's actuator ids (for
the model they were found in: a join recompiles it) and writes the *same* values into the same
places, in ``mj_data.ctrl`` and ``mj_model.actuator_gainprm`` / ``actuator_biasprm``.
A name the model lacks goes to rcsssmj's own method, which raises as the server does.

``LocalServer`` installs it on its simulation (``shortcuts=True``, the default); the test
(``tests/teamenv/league/test_league_local_motors.py``) compares the controls and gains it
writes with rcsssmj's, and a match's replay with either.
"""

from __future__ import annotations

from typing import Any

SUFFIXES = ("_tau", "_pos", "_vel")


class CachedMotorCommand:
    """``sim.ctrl_motor`` with cached actuator ids; install with ``install(sim)``."""

    def __init__(self, sim: Any) -> None:
        self.sim = sim
        self.original = type(sim).ctrl_motor.__get__(sim)   # rcsssmj's, bound to ``sim``
        self._model: Any = None
        self._data: Any = None
        self._ids: dict[str, tuple[int, int, int]] = {}

    @classmethod
    def install(cls, sim: Any) -> CachedMotorCommand:
        """Put a cached command on ``sim`` (an instance attribute: rcsssmj's agents call
        ``sim.ctrl_motor``); returns it."""
        command = cls(sim)
        sim.ctrl_motor = command
        return command

    def _arrays(self) -> None:
        model, data = self.sim.mj_model, self.sim.mj_data
        if model is not self._model or data is not self._data:   # a recompile: new ids
            self._model, self._data, self._ids = model, data, {}
            self._ctrl = data.ctrl
            self._gain, self._bias = model.actuator_gainprm, model.actuator_biasprm

    def __call__(self, name: str, q: float, dq: float, kp: float, kd: float,
                 tau: float) -> None:
        self._arrays()
        ids = self._ids.get(name)
        if ids is None:
            model = self._model
            try:
                ids = tuple(model.actuator(name + s).id for s in SUFFIXES)
            except (KeyError, TypeError):
                return self.original(name, q, dq, kp, kd, tau)     # raises as rcsssmj does
            self._ids[name] = ids
        t, p, v = ids
        ctrl, gain, bias = self._ctrl, self._gain, self._bias
        # rcsssmj's ctrl_motor, the same values in the same places
        ctrl[t] = tau
        ctrl[p] = q
        ctrl[v] = dq
        gain[p, 0] = kp
        bias[p, 1] = -kp
        gain[v, 0] = kd
        bias[v, 2] = -kd
        return None
