"""A team plugin driven by a policy: a frozen MLP loaded from an ``.npz`` file, or any callable.

Register name ``policy`` (entry point): ``right="policy", right_config={"path": "w.npz"}``, or
in-process ``right_config={"policy": fn}`` with ``fn(obs_batch) -> actions``: ``obs_batch``
(n_agents, obs_size) float32 flat (Box) observations of the team's agents in uniform-number
order, ``actions`` (n_agents, 9) flat (Box) actions in [-1, 1] (clipped). Both are the env's
``observation_format="box"`` / ``action_format="box"`` layouts (``teamenv.box_layout``), so a
policy trained on ``teamenv.single_agent.PlayerEnv`` or with the box formats plays here
unchanged.

One concept per module:

- ``mlp_file``: the network (``MLPPolicy``) and its file format (``MLP_FORMAT``,
  ``save_mlp_policy``, ``load_policy``, ``PolicyFileError``);
- ``reflexes``: the kick gate and the walk at the ball a file may ask for (``gate_kicks``,
  ``approach_ball``, ``apply_reflexes``);
- ``team``: the plugin (``PolicyTeam``, ``PolicyTeamConfig``) and the Box -> Dict action
  conversion it plays with (``box_to_dict_action``).

Everything is importable from ``teamenv.policy_team`` itself, as before the split.
"""

from __future__ import annotations

from teamenv.box_layout import flatten_observation
from teamenv.policy_team.mlp_file import (
    ACTIVATIONS,
    MLP_FORMAT,
    MLPPolicy,
    PolicyFileError,
    load_policy,
    save_mlp_policy,
)
from teamenv.policy_team.reflexes import apply_reflexes, approach_ball, gate_kicks
from teamenv.policy_team.team import (
    PolicyFn,
    PolicyTeam,
    PolicyTeamConfig,
    box_to_dict_action,
    box_to_dict_actions,
    expected_observation_size,
)

__all__ = [
    "ACTIVATIONS", "MLP_FORMAT", "MLPPolicy", "PolicyFileError", "PolicyFn", "PolicyTeam",
    "PolicyTeamConfig", "apply_reflexes", "approach_ball", "box_to_dict_action",
    "box_to_dict_actions", "expected_observation_size", "flatten_observation", "gate_kicks",
    "load_policy", "save_mlp_policy",
]
