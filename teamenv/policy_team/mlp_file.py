"""The MLP policy file: a frozen network over flat (Box) observations, and its ``.npz`` format.

The file format (``MLP_FORMAT``, torch-free, numpy only), an ``.npz`` with:

- ``format``: the string "teamenv-mlp-v1";
- ``n_layers``: L; ``W0..W{L-1}`` (in, out) float32 weights, ``b0..b{L-1}`` (out,) biases:
  ``h = act(h @ Wi + bi)`` for the hidden layers, ``out = out_act(h @ W{L-1} + b{L-1})``,
  then clipped to [-1, 1];
- ``activation``: "tanh", "relu" or "identity" (hidden layers); ``output_activation``: the
  same choices (SB3's PPO ``MlpPolicy``: tanh hidden layers, an identity output = the mean);
- ``observation_mode``: "state" or "vision" (the mode it was trained on; the observation
  format is always "box", the action format "box"); ``observation_size``: W0's rows;
- optional ``obs_mean``, ``obs_std`` (observation_size,): the input is
  ``(obs - obs_mean) / obs_std`` (SB3 VecNormalize: ``std = sqrt(var + eps)``), then clipped
  to +-``obs_clip`` when that is given;
- optional ``team_size`` (what it was trained with; informative, the size check is exact);
- optional ``kick_gate_m`` (state mode only): on every row whose observation puts the ball
  farther than this from the player (``ball.rel_x``, ``ball.rel_y``), the kick power is set
  to 0 (no kick). A kick request starts the kick motion whether or not the ball is in reach
  (the player stands still for the kick's duration, and the kick moves the ball only if it is
  in reach when it fires), so a policy that asks for a kick every cycle never walks; with the
  gate it kicks when the ball is in reach, as the chaser does (``gate_kicks``);
- optional ``walk_to_ball`` (bool, needs ``kick_gate_m``): the walk entries are replaced by
  a walk at the ball (``approach_ball``: forward when it is within 0.6 rad of the heading,
  turning towards it) while the ball is farther than ``kick_gate_m``, and by standing still
  within it; the network then chooses only the kick (power, direction);
- optional ``action_repeat`` (int >= 1, default 1): the ``policy`` team runs the network every
  ``action_repeat``-th cycle of an episode (the first included) and repeats its output in
  between, as a policy trained with that frame skip acts; the kick gate is applied every
  cycle to the current observation;
- optional ``option_team`` (a team spec) and ``option_count`` (int k): the first k Box
  outputs are scores of k options that team plays, not actions
  (``teamenv.selfplay.option_policy_team`` plays such a file:
  ``load_policy(path, option_team=spec)``); the ``policy`` team refuses it with a message
  naming the team to play it with.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

import portable_math as pm
from teamenv.box_layout import ACTION_SIZE
from teamenv.errors import ConfigError
from teamenv.input_files import read_npz
from teamenv.policy_team.reflexes import apply_reflexes

MLP_FORMAT = "teamenv-mlp-v1"
ACTIVATIONS: dict[str, Callable[[np.ndarray], np.ndarray]] = {
    "tanh": lambda x: pm.tanh(x).astype(x.dtype),
    "relu": lambda x: np.maximum(x, 0.0),
    "identity": lambda x: x,
}


class PolicyFileError(ConfigError):
    """A policy file is missing, malformed, or does not fit the env it is asked to play in."""


class MLPPolicy:
    """A frozen MLP over flat observations: ``policy(obs_batch) -> actions`` in [-1, 1].

    ``layers``: (W, b) pairs, W of shape (in, out). See the module docstring for the rest.
    """

    def __init__(self, layers: Sequence[tuple[np.ndarray, np.ndarray]], *,
                 activation: str = "tanh", output_activation: str = "identity",
                 observation_mode: str = "state", obs_mean: np.ndarray | None = None,
                 obs_std: np.ndarray | None = None, obs_clip: float | None = None,
                 team_size: int | None = None, kick_gate_m: float | None = None,
                 walk_to_ball: bool = False, action_repeat: int = 1,
                 source: str = "MLPPolicy") -> None:
        def fail(why: str) -> PolicyFileError:
            return PolicyFileError(f"policy {source}: {why}")

        if not layers:
            raise fail("no layers")
        self.layers = []
        for k, (w, b) in enumerate(layers):
            w = np.asarray(w, dtype=np.float32)
            b = np.asarray(b, dtype=np.float32)
            if w.ndim != 2 or b.shape != (w.shape[1],):
                raise fail(f"layer {k}: W{k} must be (in, out) and b{k} (out,), got "
                           f"{w.shape} and {b.shape}")
            if self.layers and self.layers[-1][0].shape[1] != w.shape[0]:
                raise fail(f"layer {k}: W{k} has {w.shape[0]} inputs, the layer before gives "
                           f"{self.layers[-1][0].shape[1]}")
            if not (np.isfinite(w).all() and np.isfinite(b).all()):
                raise fail(f"layer {k}: non-finite weights")
            self.layers.append((w, b))
        if self.layers[-1][0].shape[1] != ACTION_SIZE:
            raise fail(f"the last layer gives {self.layers[-1][0].shape[1]} outputs; a box "
                       f"action has {ACTION_SIZE}")
        for name, value in (("activation", activation),
                            ("output_activation", output_activation)):
            if value not in ACTIVATIONS:
                raise fail(f"{name}: {value!r} is not one of {sorted(ACTIVATIONS)}")
        if observation_mode not in ("state", "vision"):
            raise fail(f"observation_mode: {observation_mode!r} is not 'state' or 'vision'")
        self.activation, self.output_activation = activation, output_activation
        self.observation_mode = observation_mode
        self.observation_size = int(self.layers[0][0].shape[0])
        self.team_size = None if team_size is None else int(team_size)
        self.obs_mean = self.obs_std = None
        for name, value in (("obs_mean", obs_mean), ("obs_std", obs_std)):
            if value is None:
                continue
            value = np.asarray(value, dtype=np.float32)
            if value.shape != (self.observation_size,):
                raise fail(f"{name}: shape {value.shape}, expected ({self.observation_size},)")
            setattr(self, name, value)
        if self.obs_std is not None and not (self.obs_std > 0).all():
            raise fail("obs_std: every entry must be > 0")
        if obs_clip is not None and not (math.isfinite(obs_clip) and obs_clip > 0):
            raise fail(f"obs_clip: must be a finite number > 0, got {obs_clip!r}")
        self.obs_clip = None if obs_clip is None else float(obs_clip)
        if kick_gate_m is not None:
            if observation_mode != "state":
                raise fail("kick_gate_m: only for observation_mode 'state' (it reads the "
                           "ball's relative position)")
            if not (math.isfinite(kick_gate_m) and kick_gate_m > 0):
                raise fail(f"kick_gate_m: must be a finite number > 0, got {kick_gate_m!r}")
        self.kick_gate_m = None if kick_gate_m is None else float(kick_gate_m)
        if walk_to_ball and kick_gate_m is None:
            raise fail("walk_to_ball: needs kick_gate_m (where the walk stops for the kick)")
        self.walk_to_ball = bool(walk_to_ball)
        if isinstance(action_repeat, bool) or int(action_repeat) != action_repeat or \
                action_repeat < 1:
            raise fail(f"action_repeat: must be an integer >= 1, got {action_repeat!r}")
        self.action_repeat = int(action_repeat)
        self.source = source

    def __call__(self, obs_batch: np.ndarray) -> np.ndarray:
        """The actions for ``obs_batch``: the network's output, kick-gated."""
        return self.gate(obs_batch, self.network_actions(obs_batch))

    def gate(self, obs_batch: np.ndarray, actions: np.ndarray) -> np.ndarray:
        """``actions`` with the file's kick gate (and walk to the ball) applied for
        ``obs_batch``, if it has them."""
        return apply_reflexes(obs_batch, actions, self.kick_gate_m, self.walk_to_ball)

    def network_actions(self, obs_batch: np.ndarray) -> np.ndarray:
        """The network's output for ``obs_batch``, clipped to [-1, 1] (no gate)."""
        x = np.asarray(obs_batch, dtype=np.float32)
        if x.ndim != 2 or x.shape[1] != self.observation_size:
            raise PolicyFileError(f"policy {self.source}: observations of shape {x.shape}, "
                                  f"expected (n, {self.observation_size})")
        if self.obs_mean is not None:
            x = x - self.obs_mean
        if self.obs_std is not None:
            x = x / self.obs_std
        if self.obs_clip is not None:
            x = np.clip(x, -self.obs_clip, self.obs_clip)
        hidden, last = ACTIVATIONS[self.activation], len(self.layers) - 1
        for k, (w, b) in enumerate(self.layers):
            x = pm.matmul(x, w) + b
            x = ACTIVATIONS[self.output_activation](x) if k == last else hidden(x)
        return np.clip(x, -1.0, 1.0)


def save_mlp_policy(path: str | Path, layers: Sequence[tuple[np.ndarray, np.ndarray]], *,
                    activation: str = "tanh", output_activation: str = "identity",
                    observation_mode: str = "state", obs_mean: np.ndarray | None = None,
                    obs_std: np.ndarray | None = None, obs_clip: float | None = None,
                    team_size: int | None = None, kick_gate_m: float | None = None,
                    walk_to_ball: bool = False, action_repeat: int = 1) -> Path:
    """Write an MLP policy file (format ``MLP_FORMAT``); checks it as ``load_policy`` would.
    ``layers``: (W (in, out), b (out,)) pairs, input layer first. Returns the path."""
    policy = MLPPolicy(layers, activation=activation, output_activation=output_activation,
                       observation_mode=observation_mode, obs_mean=obs_mean, obs_std=obs_std,
                       obs_clip=obs_clip, team_size=team_size, kick_gate_m=kick_gate_m,
                       walk_to_ball=walk_to_ball, action_repeat=action_repeat,
                       source=str(path))
    arrays: dict[str, Any] = {
        "format": np.array(MLP_FORMAT), "n_layers": np.array(len(policy.layers)),
        "activation": np.array(activation), "output_activation": np.array(output_activation),
        "observation_mode": np.array(observation_mode),
        "observation_size": np.array(policy.observation_size),
    }
    for k, (w, b) in enumerate(policy.layers):
        arrays[f"W{k}"], arrays[f"b{k}"] = w, b
    for name, value in (("obs_mean", policy.obs_mean), ("obs_std", policy.obs_std),
                        ("obs_clip", obs_clip), ("team_size", team_size),
                        ("kick_gate_m", kick_gate_m),
                        ("walk_to_ball", walk_to_ball or None),
                        ("action_repeat", None if action_repeat == 1 else action_repeat)):
        if value is not None:
            arrays[name] = np.asarray(value)
    path = Path(path)
    with path.open("wb") as fh:  # a file object: numpy would append .npz to a bare name
        np.savez(fh, **arrays)
    return path


#: The entries of a file whose outputs score options (module docstring).
OPTION_TEAM_KEY, OPTION_COUNT_KEY = "option_team", "option_count"


def option_team(path: str | Path) -> tuple[str, int] | None:
    """(team spec name, option count) of a policy file that scores options, else None."""
    data = read_npz(path, f"policy file {str(path)!r}", PolicyFileError,
                    what=f"{MLP_FORMAT} policy file")
    return _option_team(data, Path(path))


def _option_team(data: Mapping[str, np.ndarray], path: Path) -> tuple[str, int] | None:
    if OPTION_TEAM_KEY not in data:
        return None
    try:
        return str(data[OPTION_TEAM_KEY]), int(data[OPTION_COUNT_KEY])
    except (KeyError, TypeError, ValueError) as exc:
        raise PolicyFileError(f"policy file {str(path)!r}: {OPTION_TEAM_KEY!r} needs an "
                              f"integer {OPTION_COUNT_KEY!r} entry ({exc})") from None


def load_policy(path: str | Path, option_team: str | None = None) -> MLPPolicy:
    """Read a policy file written by ``save_mlp_policy`` (or any writer of the format).
    A file that scores options is read only by the team it names (``option_team``)."""
    path = Path(path)
    if not path.is_file():
        raise PolicyFileError(f"policy file {str(path)!r} not found")
    data = read_npz(path, f"policy file {str(path)!r}", PolicyFileError,
                    what=f"{MLP_FORMAT} policy file")
    chooser = _option_team(data, path)
    if option_team is not None and chooser is None:
        raise PolicyFileError(f"policy file {str(path)!r}: its outputs are Box actions; the "
                              f"{option_team!r} team plays a file that scores its options "
                              f"(an {OPTION_TEAM_KEY!r} entry naming it)")
    if chooser is not None and chooser[0] != option_team:
        raise PolicyFileError(f"policy file {str(path)!r} scores {chooser[1]} options for the "
                              f"{chooser[0]!r} team, not Box actions: play it with "
                              f"teamenv.selfplay.option_policy_team:OptionPolicyTeam "
                              f"(path={path})")
    try:
        return _policy_from_arrays(data, path)
    except PolicyFileError:
        raise
    except (TypeError, ValueError, OverflowError, IndexError) as exc:  # an entry of odd shape
        raise PolicyFileError(f"policy file {str(path)!r}: malformed entry ({exc})") from None


def _policy_from_arrays(data: Mapping[str, np.ndarray], path: Path) -> MLPPolicy:
    """The policy a file's arrays describe (``load_policy``)."""
    def text(key: str, default: str | None = None) -> str:
        if key not in data:
            if default is None:
                raise PolicyFileError(f"policy file {str(path)!r}: no {key!r} entry "
                                      f"(format {MLP_FORMAT})")
            return default
        return str(data[key])

    fmt = text("format")
    if fmt != MLP_FORMAT:
        raise PolicyFileError(f"policy file {str(path)!r}: format {fmt!r}, expected "
                              f"{MLP_FORMAT!r}")
    n_layers = int(data["n_layers"]) if "n_layers" in data else 0
    missing = [k for i in range(n_layers) for k in (f"W{i}", f"b{i}") if k not in data]
    if n_layers < 1 or missing:
        raise PolicyFileError(f"policy file {str(path)!r}: n_layers {n_layers}, missing "
                              f"{missing}")
    layers = [(data[f"W{i}"], data[f"b{i}"]) for i in range(n_layers)]
    optional = {k: data[k] for k in ("obs_mean", "obs_std") if k in data}
    policy = MLPPolicy(
        layers, activation=text("activation", "tanh"),
        output_activation=text("output_activation", "identity"),
        observation_mode=text("observation_mode", "state"),
        obs_clip=float(data["obs_clip"]) if "obs_clip" in data else None,
        team_size=int(data["team_size"]) if "team_size" in data else None,
        kick_gate_m=float(data["kick_gate_m"]) if "kick_gate_m" in data else None,
        walk_to_ball=bool(data["walk_to_ball"]) if "walk_to_ball" in data else False,
        action_repeat=int(data["action_repeat"]) if "action_repeat" in data else 1,
        source=repr(str(path)), **optional)
    if "observation_size" in data and \
            int(data["observation_size"]) != policy.observation_size:
        raise PolicyFileError(f"policy file {str(path)!r}: observation_size "
                              f"{int(data['observation_size'])} but W0 has "
                              f"{policy.observation_size} rows")
    return policy
