"""The ``policy`` team plugin: every agent of a side driven by one policy (one batched call a
cycle), Dict observations flattened to the Box rows the policy takes, its Box actions made
Dict actions (``teamenv.box_layout`` both ways)."""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from teamenv.box_layout import (
    ACTION_SIZE,
    StateLayout,
    decode_box_actions,
    flatten_observation,
)
from teamenv.field import FieldSpec
from teamenv.policy_team.mlp_file import MLP_FORMAT, PolicyFileError, load_policy
from teamenv.sim.vision import vision_layout
from teamenv.team_config import team_config
from teamenv.teams import TeamContext

PolicyFn = Callable[[np.ndarray], np.ndarray]


def box_to_dict_actions(actions: np.ndarray, walk_low: Sequence[float],
                        walk_high: Sequence[float], field: FieldSpec) -> list[dict[str, Any]]:
    """Box actions (n, 9), clipped to [-1, 1], as the Dict actions the env's Box parser would
    make of them (``teamenv.box_layout.decode_box_actions``)."""
    box = np.clip(np.asarray(actions, dtype=float).reshape(-1, ACTION_SIZE), -1.0, 1.0)
    d = decode_box_actions(box, walk_low, walk_high, field.half_length, field.half_width)
    return [{"walk": d.walk[k], "kick": np.array([d.kick_power[k], d.kick_direction[k]]),
             "beam_request": int(d.beam_request[k]), "beam": d.beam[k]}
            for k in range(len(box))]


def box_to_dict_action(action: np.ndarray, walk_low: Sequence[float],
                       walk_high: Sequence[float], field: FieldSpec) -> dict[str, Any]:
    """One Box action in [-1, 1]^9 as the Dict action the env's box parser would make of it
    (walk scaled to the profile's range, asymmetric; kick power <= 0: no kick; beam)."""
    return box_to_dict_actions(action, walk_low, walk_high, field)[0]


def expected_observation_size(context: TeamContext) -> int:
    """The flat observation length the env gives the agents of ``context``."""
    import comms

    heard = int(comms.get_profile(context.channel).max_heard)
    if context.observation_mode == "state":
        return StateLayout(context.team_size, heard).size
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
        if actions.shape != (len(agents), ACTION_SIZE) or not np.isfinite(actions).all():
            raise PolicyFileError(f"policy team ({self.context.side}): the policy returned "
                                  f"{actions.shape} (finite: {np.isfinite(actions).all()}), "
                                  f"expected ({len(agents)}, {ACTION_SIZE}) finite values")
        ctx = self.context
        return dict(zip(agents, box_to_dict_actions(actions, ctx.walk_low, ctx.walk_high,
                                                    ctx.field), strict=True))
