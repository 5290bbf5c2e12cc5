"""The league server's reference walking network as a ``LocomotionController``, in numpy.

The rcssservermj repository publishes a walking policy for the T1 (``example/nn_client``, MIT
licence; the weights ship unchanged in ``data/t1_reference_walk.npz`` with their licence in
``data/LICENSE``, converted by ``scripts/convert_reference_walk_network.py``). It is an MLP
78 -> 512 (LayerNorm, ELU) -> 256 (ELU) -> 128 (ELU) -> 23, its output clipped to +-10, read
each cycle as joint targets ``nominal + 0.5 * action`` for PD motors with kp 25, kd 0.6.

The observation (78 values) is, in the network's training convention:

* per joint, in the T1's motor order (``he1`` ... ``rle6``), three values: the angle in the
  training simulation's sign convention minus the nominal pose, over 4.6; the joint velocity
  (same signs) over 110; the previous action over 10 (69 values);
* the torso gyro (rad/s) over 50, clipped to +-1;
* the goal velocity (vx m/s, vy m/s, turn rad/s, body frame);
* gravity (0, 0, -1) rotated into the torso frame;

all clipped to +-10. Angles and rates are radians here (our parser converts the wire's
degrees, the reference converts them itself).

The forward pass is float64 on the float32 weights (the reference evaluates float32 in torch:
the actions agree to ~1e-5) and uses ``portable_math``'s matrix product (einsum, not BLAS) and
``expm1``, so it gives the same bits on every CPU and has no random state. What stays
machine-dependent in a walk is the server's physics (MuJoCo), not the controller.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

import numpy as np

import portable_math as pm

from . import effectors
from .controller import WalkEnvelope
from .errors import LeagueError
from .network_batch import WalkBatch
from .perception import Perception
from .t1 import T1_MOTORS, joint_sensor

#: the T1's motors in the network's joint order (the server's MJCF order)
NETWORK_MOTORS: tuple[str, ...] = tuple(T1_MOTORS)
#: the pose the network's actions are offsets from (rad, training convention)
NOMINAL_POSE = np.array([
    0.0, 0.0,
    0.0, 1.4, 0.0, -0.4,
    0.0, -1.4, 0.0, 0.4,
    0.0,
    -0.4, 0.0, 0.0, 0.8, -0.4, 0.0,
    0.4, 0.0, 0.0, -0.8, 0.4, 0.0,
])
#: per joint, the sign that turns the server's joint angle into the training simulation's
TRAINING_SIGN = np.array([
    1.0, -1.0,
    1.0, -1.0, -1.0, 1.0,
    -1.0, -1.0, 1.0, 1.0,
    1.0,
    1.0, -1.0, -1.0, 1.0, 1.0, -1.0,
    -1.0, -1.0, -1.0, -1.0, -1.0, -1.0,
])
#: the reference's motor gains and action scale (targets = nominal + scale * action)
KP, KD, ACTION_SCALE = 25.0, 0.6, 0.5
#: observation normalisers of the training: angle, velocity, previous action, gyro
ANGLE_SCALE, VELOCITY_SCALE, ACTION_OBS_SCALE, GYRO_SCALE = 4.6, 110.0, 10.0, 50.0
#: observations and actions are clipped to +-this
CLIP = 10.0
OBSERVATION_SIZE = 3 * len(NETWORK_MOTORS) + 9
WEIGHTS_FILE = "t1_reference_walk.npz"

#: the commands the network walks safely on the server's physics (LocalServer, 8 trials of 6 s
#: per command from seeded start poses, ``benchmarks/league_walk_compare.py --envelope``): up
#: in every trial forward to 1.6 (1.28 m/s achieved; 1.8 fell 7 of 8), backward to 1.0,
#: turning to 2.5 rad/s, sideways to 0.12 (0.15 fell 1 of 8 to the right, 0.2 1 and 2 of 8);
#: half-axes with a margin below those, sideways at the largest that never fell. Some curves
#: inside it still fall at times (docs/league.md)
NETWORK_ENVELOPE = WalkEnvelope(vx_forward=1.5, vx_backward=0.8, vy=0.12, turn=2.0)


@dataclass(frozen=True)
class WalkNetwork:
    """The reference MLP's weights (float32 values held as float64, ``w*`` as (in, out))."""

    w1: np.ndarray
    b1: np.ndarray
    ln_gain: np.ndarray
    ln_bias: np.ndarray
    w2: np.ndarray
    b2: np.ndarray
    w3: np.ndarray
    b3: np.ndarray
    w4: np.ndarray
    b4: np.ndarray

    #: LayerNorm's epsilon in the reference
    LN_EPS = 1e-6

    @classmethod
    def load(cls, path: str | Path | None = None) -> WalkNetwork:
        """The shipped weights (or an ``.npz`` at ``path`` with the same arrays)."""
        if path is None:
            with resources.as_file(resources.files("teamenv.league") / "data" / WEIGHTS_FILE) as p:
                return cls.load(p)
        names = ("fc1_weight", "fc1_bias", "layer_norm_weight", "layer_norm_bias", "fc2_weight",
                 "fc2_bias", "fc3_weight", "fc3_bias", "fc4_weight", "fc4_bias")
        with np.load(path) as z:
            missing = [k for k in names if k not in z.files]
            if missing:
                raise LeagueError(f"walk network {path}: no array {missing[0]!r} "
                                  f"(has {z.files})")
            arrays = {k: np.asarray(z[k], dtype=np.float32).astype(np.float64) for k in names}
        net = cls(
            w1=np.ascontiguousarray(arrays["fc1_weight"].T), b1=arrays["fc1_bias"],
            ln_gain=arrays["layer_norm_weight"], ln_bias=arrays["layer_norm_bias"],
            w2=np.ascontiguousarray(arrays["fc2_weight"].T), b2=arrays["fc2_bias"],
            w3=np.ascontiguousarray(arrays["fc3_weight"].T), b3=arrays["fc3_bias"],
            w4=np.ascontiguousarray(arrays["fc4_weight"].T), b4=arrays["fc4_bias"])
        if net.w1.shape != (OBSERVATION_SIZE, 512) or net.w4.shape != (128, len(NETWORK_MOTORS)):
            raise LeagueError(f"walk network {path}: layers {net.w1.shape} ... {net.w4.shape} "
                              f"are not {OBSERVATION_SIZE} -> ... -> {len(NETWORK_MOTORS)}")
        return net

    def __call__(self, observation: np.ndarray) -> np.ndarray:
        """Actions (23,) for one observation (78,), or (n, 23) for (n, 78); float64."""
        x = np.asarray(observation, dtype=np.float64)
        h = pm.matmul(x, self.w1) + self.b1
        mean = h.mean(axis=-1, keepdims=True)
        var = np.square(h - mean).mean(axis=-1, keepdims=True)
        h = (h - mean) / np.sqrt(var + self.LN_EPS) * self.ln_gain + self.ln_bias
        h = _elu(h)
        h = _elu(pm.matmul(h, self.w2) + self.b2)
        h = _elu(pm.matmul(h, self.w3) + self.b3)
        return np.clip(pm.matmul(h, self.w4) + self.b4, -CLIP, CLIP)


@functools.lru_cache(maxsize=1)
def shipped_network() -> WalkNetwork:
    """``WalkNetwork.load()`` once per process, its arrays read-only: the controllers of a
    match share it (and so can share a ``WalkBatch``)."""
    network = WalkNetwork.load()
    for f in dataclasses.fields(network):
        getattr(network, f.name).flags.writeable = False
    return network


def _elu(x: np.ndarray) -> np.ndarray:
    """x where x > 0, else expm1(min(x, 0)) (``portable_math``: one C-library call per
    element, so only the elements that keep it are computed; min(-0.0, 0) is +0.0, NaN stays
    NaN: the bits of ``where(x > 0, x, expm1(minimum(x, 0)))``)."""
    out = np.array(x, dtype=np.float64)
    rest = ~(out > 0)
    out[rest] = pm.expm1(np.minimum(out[rest], 0.0))
    return out


def projected_gravity(quat: tuple[float, float, float, float]) -> np.ndarray:
    """World gravity direction (0, 0, -1) in the frame of a body at orientation ``quat``
    (w, x, y, z; normalised here)."""
    w, x, y, z = quat
    n = math.sqrt(w * w + x * x + y * y + z * z)
    if not n > 0:
        raise LeagueError(f"torso quaternion {quat} has no length")
    w, x, y, z = w / n, x / n, y / n, z / n
    # minus the third row of the rotation matrix (R^T applied to -e_z)
    return -np.array([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)])


#: the joint sensor of each of ``NETWORK_MOTORS``
_SENSORS: tuple[str, ...] = tuple(joint_sensor(motor) for motor in NETWORK_MOTORS)


def observation(perception: Perception, goal: tuple[float, float, float],
                previous_action: np.ndarray) -> np.ndarray:
    """The network's input (78,) from one perception, the goal velocity and last action."""
    joints = perception.joints
    try:
        states = [joints[sensor] for sensor in _SENSORS]
    except KeyError as exc:
        raise LeagueError(f"perception has no joint {exc.args[0]!r} (T1 expected)") from None
    angles = np.array([js.angle for js in states], dtype=float)
    rates = np.array([js.velocity for js in states], dtype=float)
    try:
        gyro = np.asarray(perception.gyros["torso_gyro"], dtype=float)
        quat = perception.orientations["torso_quat"]
    except KeyError as exc:
        raise LeagueError(f"perception has no {exc.args[0]} (the walk network needs it)") from None
    joints = np.stack([
        (angles * TRAINING_SIGN - NOMINAL_POSE) / ANGLE_SCALE,
        rates * TRAINING_SIGN / VELOCITY_SCALE,
        np.asarray(previous_action, dtype=float) / ACTION_OBS_SCALE,
    ], axis=1).reshape(-1)  # per joint: angle, velocity, previous action
    obs = np.concatenate([
        joints,
        np.clip(gyro / GYRO_SCALE, -1.0, 1.0),
        np.asarray(goal, dtype=float),
        projected_gravity(quat),
    ])
    return np.clip(obs, -CLIP, CLIP)


class NetworkWalkController:
    """The reference walking network driving the server's motors (numpy only).

    ``step`` limits the command to ``envelope`` (None: as given), feeds it to the network as
    the goal velocity and sends every motor its target with the reference's gains. ``stand``
    is the network at a zero goal: it steps on the spot to keep its balance, as the reference
    client does before it walks (a held nominal pose under the same gains falls over; see
    docs/league.md). ``reset`` forgets the previous action (as after a fresh connection)."""

    def __init__(self, envelope: WalkEnvelope | None = NETWORK_ENVELOPE,
                 network: WalkNetwork | None = None, batch: WalkBatch | None = None) -> None:
        self.envelope = envelope
        self.network = network or (batch.network if batch is not None else shipped_network())
        #: with a batch, ``stand``/``step`` return a placeholder that the batch's ``resolve``
        #: replaces by the message (``teamenv.league.network_batch``: one pass per team)
        self.batch = batch
        self._previous_action = np.zeros(len(NETWORK_MOTORS))

    def _settle(self) -> None:
        """Let a pass of this controller still pending in its batch happen now."""
        if self.batch is not None and self.batch.holds(self):
            self.batch.flush()

    def reset(self) -> None:
        self._settle()
        self._previous_action = np.zeros(len(NETWORK_MOTORS))

    def stand(self, perception: Perception) -> str:
        return self._act((0.0, 0.0, 0.0), perception)

    def step(self, command: tuple[float, float, float], perception: Perception) -> str:
        if self.envelope is not None:
            command = self.envelope.limit(command)
        return self._act(command, perception)

    def _act(self, goal: tuple[float, float, float], perception: Perception) -> str:
        self._settle()                      # a second message this cycle follows the first
        obs = observation(perception, goal, self._previous_action)
        if self.batch is not None:
            return self.batch.submit(self, obs)
        return self.finish(self.network(obs))

    def finish(self, action: np.ndarray) -> str:
        """The motor effectors of the network's ``action`` (23,), remembered as the previous
        action (the batch calls this after its pass)."""
        self._previous_action = action
        targets = (NOMINAL_POSE + ACTION_SCALE * action) * TRAINING_SIGN
        return effectors.motors(NETWORK_MOTORS, targets, 0.0, KP, KD)
