"""A torch-free stand-in learner for the league's tests: it plays the training env with its
network for ``steps`` decisions (so opponents are drawn and episodes recorded for real) and
then moves its weights by seeded noise. Not a learning algorithm; it exercises everything the
league does with a learner in a fraction of PPO's time."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from teamenv.policy_team import MLPPolicy
from teamenv.selfplay.batch_env import TeamBatchEnv
from teamenv.selfplay.learner import PolicyWeights
from teamenv.selfplay.pfsp import OpponentMix
from teamenv.selfplay.training_setup import TrainingSetup


class NoiseLearner:
    def __init__(self, setup: TrainingSetup, seed: int = 0, copies: int = 1,
                 hidden: int = 8) -> None:
        self.batch = TeamBatchEnv(setup, OpponentMix.single("static", seed), copies, seed)
        rng = np.random.default_rng(seed)
        size, out = self.batch.observation_size, self.batch.action_size
        self.layers = [(rng.normal(0, 0.2, (size, hidden)), np.zeros(hidden)),
                       (rng.normal(0, 0.2, (hidden, out)), np.zeros(out))]
        self.last_episodes: list = []

    def initial_weights(self) -> PolicyWeights:
        return PolicyWeights.of(self.layers)

    def _network(self) -> MLPPolicy:
        # an MLPPolicy needs 9 outputs: pad the learned entries, use the first ones
        w, b = self.layers[-1]
        pad = 9 - w.shape[1]
        return MLPPolicy([*self.layers[:-1], (np.pad(w, ((0, 0), (0, pad))),
                                              np.pad(b, (0, pad)))])

    def train(self, steps: int, opponents: OpponentMix, seed: int) -> PolicyWeights:
        self.batch.start(opponents, seed)
        obs = self.batch.reset()
        network = self._network()
        for _ in range(max(1, steps // self.batch.n_slots)):
            actions = network.network_actions(obs)[:, :self.batch.action_size]
            obs, *_ = self.batch.step(actions)
        self.last_episodes = list(self.batch.episodes)
        rng = np.random.default_rng(seed)
        self.layers = [(w + rng.normal(0, 0.05, w.shape), b + rng.normal(0, 0.05, b.shape))
                       for w, b in self.layers]
        return PolicyWeights.of(self.layers)

    def save(self, directory: Path) -> None:
        np.savez(Path(directory) / "noise.npz",
                 **{f"{k}{i}": a for i, layer in enumerate(self.layers)
                    for k, a in zip("wb", layer, strict=True)})

    def load(self, directory: Path) -> None:
        data = np.load(Path(directory) / "noise.npz")
        self.layers = [(data[f"w{i}"], data[f"b{i}"]) for i in range(len(self.layers))]
