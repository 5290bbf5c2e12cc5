"""A team plugin driven by a policy: a frozen MLP loaded from an ``.npz`` file, or any callable.

Register name ``policy`` (entry point): ``right="policy", right_config={"path": "w.npz"}``, or
in-process ``right_config={"policy": fn}`` with ``fn(obs_batch) -> actions``: ``obs_batch``
(n_agents, obs_size) float32 flat (Box) observations of the team's agents in uniform-number
order, ``actions`` (n_agents, 9) flat (Box) actions in [-1, 1] (clipped). Both are the env's
``observation_format="box"`` / ``action_format="box"`` layouts (its docstring), so a policy
trained on ``teamenv.single_agent.PlayerEnv`` or with the box formats plays here unchanged.

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
  cycle to the current observation.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

import portable_math as pm
from teamenv.actions import BOX_SIZE
from teamenv.errors import ConfigError
from teamenv.field import FieldSpec
from teamenv.input_files import read_npz
from teamenv.sim.perception import N_PLAY_MODES, flat_observation_size
from teamenv.sim.vision import VisionLayout, vision_layout
from teamenv.slots import SELF_COLUMNS
from teamenv.team_config import team_config
from teamenv.teams import TeamContext

MLP_FORMAT = "teamenv-mlp-v1"
ACTIVATIONS: dict[str, Callable[[np.ndarray], np.ndarray]] = {
    "tanh": lambda x: pm.tanh(x).astype(x.dtype),
    "relu": lambda x: np.maximum(x, 0.0),
    "identity": lambda x: x,
}

PolicyFn = Callable[[np.ndarray], np.ndarray]

#: Columns of the ball's position relative to the player (body frame) in a state-mode Box
#: observation: right after the 7 ``self`` values (``teamenv.slots``).
_BALL_REL = slice(len(SELF_COLUMNS), len(SELF_COLUMNS) + 2)


def gate_kicks(obs_batch: np.ndarray, actions: np.ndarray, gate_m: float) -> np.ndarray:
    """``actions`` (Box, one row per agent) with the kick power (entry 3) set to 0 on rows
    whose state-mode observation puts the ball farther than ``gate_m`` metres away."""
    rel = np.asarray(obs_batch, dtype=np.float64)[:, _BALL_REL]
    far = np.hypot(rel[:, 0], rel[:, 1]) > gate_m
    if far.any():
        actions = actions.copy()
        actions[far, 3] = 0.0
    return actions



def approach_ball(obs_batch: np.ndarray, actions: np.ndarray, gate_m: float) -> np.ndarray:
    """``actions`` with the walk entries (0-2, Box units) replaced: towards the ball (turn
    rate 2 x its bearing, clipped; full speed ahead when the bearing is within 0.6 rad, 0.2
    otherwise) on rows whose state-mode observation puts the ball farther than ``gate_m``,
    zero (stand for the kick) on the others."""
    rel = np.asarray(obs_batch, dtype=np.float64)[:, _BALL_REL]
    bearing = pm.arctan2(rel[:, 1], rel[:, 0])
    far = np.hypot(rel[:, 0], rel[:, 1]) > gate_m
    actions = actions.copy()
    actions[:, 0] = np.where(far, np.where(np.abs(bearing) < 0.6, 1.0, 0.2), 0.0)
    actions[:, 1] = 0.0
    actions[:, 2] = np.where(far, np.clip(2.0 * bearing, -1.0, 1.0), 0.0)
    return actions


def apply_reflexes(obs_batch: np.ndarray, actions: np.ndarray, kick_gate_m: float | None,
                   walk_to_ball: bool) -> np.ndarray:
    """A policy file's reflexes on ``actions``: the walk at the ball (``walk_to_ball``), then
    the kick gate (``kick_gate_m``; None: neither)."""
    if kick_gate_m is None:
        return actions
    if walk_to_ball:
        actions = approach_ball(obs_batch, actions, kick_gate_m)
    return gate_kicks(obs_batch, actions, kick_gate_m)


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
        if self.layers[-1][0].shape[1] != BOX_SIZE:
            raise fail(f"the last layer gives {self.layers[-1][0].shape[1]} outputs; a box "
                       f"action has {BOX_SIZE}")
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


def load_policy(path: str | Path) -> MLPPolicy:
    """Read a policy file written by ``save_mlp_policy`` (or any writer of the format)."""
    path = Path(path)
    if not path.is_file():
        raise PolicyFileError(f"policy file {str(path)!r} not found")
    data = read_npz(path, f"policy file {str(path)!r}", PolicyFileError,
                    what=f"{MLP_FORMAT} policy file")
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


# -- observations and actions between the Dict form (teams) and the Box form (policies) ----
#: Box order of the parts of a Dict observation, per mode (the env's docstring; vision's is
#: ``VisionLayout.parts``). ``heard_text`` has no place in the Box.
STATE_BOX_ORDER = ("self", "ball", "teammates", "opponents", "play_mode", "game", "heard")
VISION_BOX_ORDER = tuple(key for key, _ in VisionLayout(0, 0, 0, 0).parts)


def flatten_observation(obs: Mapping[str, Any]) -> np.ndarray:
    """One Dict-form observation as the env's flat Box row (float32): its numeric parts in
    Box order, ``play_mode`` one-hot, ``heard_text`` left out (state or vision mode)."""
    parts = []
    for key in STATE_BOX_ORDER if "self" in obs else VISION_BOX_ORDER:
        value = obs[key]
        if key == "play_mode":
            one_hot = np.zeros(N_PLAY_MODES, dtype=np.float32)
            one_hot[int(value)] = 1.0
            parts.append(one_hot)
        else:
            parts.append(np.asarray(value, dtype=np.float32).ravel())
    return np.concatenate(parts)


def box_to_dict_action(action: np.ndarray, walk_low: Sequence[float],
                       walk_high: Sequence[float], field: FieldSpec) -> dict[str, Any]:
    """A Box action in [-1, 1]^9 as the Dict action the env's box parser would make of it
    (walk scaled to the profile's range, asymmetric; kick power <= 0: no kick; beam)."""
    a = np.clip(np.asarray(action, dtype=float), -1.0, 1.0)
    low, high = np.asarray(walk_low, dtype=float), np.asarray(walk_high, dtype=float)
    walk = np.where(a[:3] >= 0, a[:3] * high, -a[:3] * low)
    return {"walk": walk, "kick": np.array([max(a[3], 0.0), a[4] * math.pi]),
            "beam_request": int(a[5] > 0.0),
            "beam": np.array([(a[6] - 1.0) * 0.5 * field.half_length, a[7] * field.half_width,
                              a[8] * math.pi])}


def expected_observation_size(context: TeamContext) -> int:
    """The flat observation length the env gives the agents of ``context``."""
    import comms

    heard = int(comms.get_profile(context.channel).max_heard)
    if context.observation_mode == "state":
        return flat_observation_size(context.team_size, heard)
    return vision_layout(context.field, context.team_size, heard, context.perception).size


@dataclass(frozen=True)
class PolicyTeamConfig:
    """The policy team's options, exactly one of them: ``path`` (an ``MLP_FORMAT`` file) or
    ``policy`` (a callable ``obs_batch -> actions``, or an ``MLPPolicy``)."""

    path: str | Path | None = None
    policy: PolicyFn | None = None


class PolicyTeam:
    """Drives every agent of a side with one policy (shared weights, one batched call a cycle).

    Config: ``path`` (an ``MLP_FORMAT`` file) or ``policy`` (a callable ``obs_batch ->
    actions``, or an ``MLPPolicy``), exactly one of them (``PolicyTeamConfig``).
    """

    def __init__(self, context: TeamContext, **config: Any) -> None:
        options = team_config("policy", PolicyTeamConfig, config, error=PolicyFileError)
        path, policy = options.path, options.policy
        if (path is None) == (policy is None):
            raise PolicyFileError(f"policy team ({context.side}): give exactly one of 'path' "
                                  f"(a {MLP_FORMAT} .npz file) or 'policy' (a callable)")
        if path is not None:
            policy = load_policy(path)
        elif not callable(policy):
            raise PolicyFileError(f"policy team ({context.side}): 'policy' must be callable "
                                  f"(obs_batch -> actions), got {policy!r}")
        self.context = context
        self.policy = policy
        self.observation_size = expected_observation_size(context)
        mode = getattr(policy, "observation_mode", None)
        if mode is not None and mode != context.observation_mode:
            raise PolicyFileError(f"policy {getattr(policy, 'source', '')}: trained on "
                                  f"observation_mode {mode!r}, the env uses "
                                  f"{context.observation_mode!r}")
        size = getattr(policy, "observation_size", None)
        if size is not None and size != self.observation_size:
            trained = getattr(policy, "team_size", None)
            raise PolicyFileError(
                f"policy {getattr(policy, 'source', '')}: takes observations of {size} values"
                f"{'' if trained is None else f' (trained with team_size {trained})'}; this "
                f"env gives {self.observation_size} (team_size {context.team_size}, "
                f"{context.observation_mode} mode, {context.channel} channel)")

        self.action_repeat = int(getattr(policy, "action_repeat", 1))
        self._cycle = 0
        self._held: np.ndarray | None = None

    def reset(self, seed: int) -> None:
        """A frozen policy draws no random numbers; a new episode restarts its repeat count."""
        self._cycle = 0
        self._held = None

    def act(self, observations: Mapping[str, Mapping[str, Any]]) -> dict[str, dict[str, Any]]:
        agents = list(observations)
        if not agents:
            return {}
        batch = np.stack([flatten_observation(observations[a]) for a in agents])
        if self.action_repeat == 1:
            actions = np.asarray(self.policy(batch), dtype=float)
        else:  # an MLPPolicy with a frame skip: the network every k-th cycle, gated each cycle
            if self._cycle % self.action_repeat == 0 or self._held is None or \
                    len(self._held) != len(agents):
                self._held = np.asarray(self.policy.network_actions(batch), dtype=float)
            self._cycle += 1
            actions = np.asarray(self.policy.gate(batch, self._held), dtype=float)
        if actions.shape != (len(agents), BOX_SIZE) or not np.isfinite(actions).all():
            raise PolicyFileError(f"policy team ({self.context.side}): the policy returned "
                                  f"{actions.shape} (finite: {np.isfinite(actions).all()}), "
                                  f"expected ({len(agents)}, {BOX_SIZE}) finite values")
        ctx = self.context
        return {a: box_to_dict_action(row, ctx.walk_low, ctx.walk_high, ctx.field)
                for a, row in zip(agents, actions, strict=True)}
