"""The learner interface of the self-play league: any trainer that can train a team against a
mix of opponents and hand back a network plugs in.

A learner implements ``Learner``:

- ``initial_weights()``: the untrained network (the league's generation-0 snapshot, the
  baseline every later snapshot is rated against);
- ``train(steps, opponents, seed)``: train for ``steps`` agent-decisions (every player's
  decision counts) in ``teamenv.selfplay.batch_env.TeamBatchEnv`` episodes against opponents
  drawn from ``opponents`` (an ``OpponentMix``), every random draw of the call seeded from
  ``seed``; return the network now (``PolicyWeights``);
- ``save(directory)`` / ``load(directory)``: everything ``train`` needs to continue exactly
  (weights, optimiser state, normalisation statistics): a league resumed after a kill loads
  the last saved state and must train on as if it had never stopped.

Optionally ``last_episodes``: the ``EpisodeRecord`` list of the last ``train`` call, which
the league summarises per opponent in its state file.

The network maps the training observation (``TrainingSetup.observation``) to the learned
action entries (``ActionSetup.learned``, in the range ``ActionSetup.bounds``); the league
folds the action setup and reflexes into the snapshot's policy file.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Protocol, runtime_checkable

import numpy as np

from teamenv.selfplay.pfsp import OpponentMix


@dataclass(frozen=True)
class PolicyWeights:
    """A feed-forward network: ``h = act(h @ W + b)`` per hidden layer, ``out_act`` on the last;
    inputs normalised as ``clip((obs - obs_mean) / obs_std, -obs_clip, obs_clip)`` first (each
    optional). The ``teamenv-mlp-v1`` conventions (``teamenv.policy_team``)."""

    layers: tuple[tuple[np.ndarray, np.ndarray], ...]
    activation: str = "tanh"
    output_activation: str = "identity"
    obs_mean: np.ndarray | None = None
    obs_std: np.ndarray | None = None
    obs_clip: float | None = None

    @classmethod
    def of(cls, layers: Sequence[tuple[np.ndarray, np.ndarray]], **kwargs) -> PolicyWeights:
        return cls(tuple((np.array(w, dtype=np.float32), np.array(b, dtype=np.float32))
                         for w, b in layers), **kwargs)


@runtime_checkable
class Learner(Protocol):
    """What the league needs of a trainer (see the module docstring)."""

    def initial_weights(self) -> PolicyWeights: ...

    def train(self, steps: int, opponents: OpponentMix, seed: int) -> PolicyWeights: ...

    def save(self, directory: Path) -> None: ...

    def load(self, directory: Path) -> None: ...
