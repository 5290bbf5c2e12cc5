"""A Stable-Baselines3 PPO learner for the self-play league (needs the ``rl`` extra).

``PPOLearner`` trains SB3's PPO (``MlpPolicy``: tanh 64-64 actor and critic) on the league's
``TeamBatchEnv`` through a ``VecEnv`` adapter (``LeagueVecEnv``: every player of every env
copy is one slot, all sharing the policy), with observations and rewards normalised by SB3's
``VecNormalize``. A snapshot is the actor's mean network plus the normalisation statistics,
which is what the ``teamenv-mlp-v1`` format holds, so the snapshot plays as the learner's
deterministic policy.

Determinism: each ``train`` call seeds SB3 (``set_random_seed``: torch, and numpy's and
Python's global generators, which SB3 itself draws from; teamenv draws from none of them) and
restarts the env copies' episode schedule with the call's seed; torch uses one thread.
``save`` writes the model (weights and Adam state) and the normalisation statistics; the
league loads them before every generation.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from teamenv.errors import MissingExtraError
from teamenv.selfplay.batch_env import TeamBatchEnv
from teamenv.selfplay.learner import PolicyWeights
from teamenv.selfplay.pfsp import OpponentMix
from teamenv.selfplay.training_setup import TrainingSetup

MODEL_FILE = "ppo.zip"
NORMALIZE_FILE = "vecnormalize.pkl"


def _sb3():
    try:
        import stable_baselines3
        import torch
    except ImportError as exc:
        raise MissingExtraError(f"the PPO learner needs Stable-Baselines3 and torch ({exc}); "
                                "install the rl extra: pip install -e '.[rl]'") from None
    return stable_baselines3, torch


def league_vec_env(batch: TeamBatchEnv):
    """An SB3 ``VecEnv`` over ``batch`` (one sub-env per slot)."""
    _sb3()
    from gymnasium import spaces
    from stable_baselines3.common.vec_env import VecEnv

    class LeagueVecEnv(VecEnv):
        """SB3's view of a ``TeamBatchEnv``: ``num_envs`` = its slots; it resets finished
        episodes itself, reporting ``terminal_observation`` as SB3 expects."""

        def __init__(self, batch: TeamBatchEnv) -> None:
            self.batch = batch
            self._actions: np.ndarray | None = None
            super().__init__(batch.n_slots,
                             spaces.Box(-np.inf, np.inf, (batch.observation_size,), np.float32),
                             spaces.Box(batch.action_low, batch.action_high, dtype=np.float32))

        def reset(self):
            return self.batch.reset()

        def step_async(self, actions: np.ndarray) -> None:
            self._actions = np.asarray(actions)

        def step_wait(self):
            return self.batch.step(self._actions)

        def close(self) -> None:
            self.batch.close()

        def get_attr(self, attr_name: str, indices=None) -> list[Any]:
            value = None if attr_name == "render_mode" else getattr(self.batch, attr_name)
            return [value] * len(self._get_indices(indices))

        def set_attr(self, attr_name: str, value: Any, indices=None) -> None:
            setattr(self.batch, attr_name, value)

        def env_method(self, method_name: str, *args, indices=None, **kwargs) -> list[Any]:
            result = getattr(self.batch, method_name)(*args, **kwargs)
            return [result] * len(self._get_indices(indices))

        def env_is_wrapped(self, wrapper_class, indices=None) -> list[bool]:
            return [False] * len(self._get_indices(indices))

    return LeagueVecEnv(batch)


class PPOLearner:
    """SB3 PPO on the league's training env.

    Args:
        setup: the ``TrainingSetup`` (its ``gamma`` is PPO's discount per decision).
        seed: the run's seed (the initial network).
        copies: env copies (matches played at once; ``copies * team_size`` slots).
        n_steps: decisions per slot per PPO rollout; batch_size, n_epochs, learning_rate,
            gae_lambda, ent_coef, clip_range: PPO's; log_std_init: initial log std of the
            Gaussian actions; hidden: width of the two tanh layers.
    """

    def __init__(self, setup: TrainingSetup, seed: int = 0, copies: int = 2,
                 n_steps: int = 256, batch_size: int = 256, n_epochs: int = 10,
                 learning_rate: float = 3e-4, gae_lambda: float = 0.95, ent_coef: float = 0.0,
                 clip_range: float = 0.2, log_std_init: float = -1.0, hidden: int = 64) -> None:
        _, torch = _sb3()
        from stable_baselines3 import PPO
        from stable_baselines3.common.vec_env import VecNormalize

        torch.set_num_threads(1)  # small networks; also keeps training bit-for-bit repeatable
        self.setup = setup
        placeholder = OpponentMix.single("static", seed)
        self.batch = TeamBatchEnv(setup, placeholder, copies=copies, seed=seed)
        self.vec_env = VecNormalize(league_vec_env(self.batch), norm_obs=True,
                                    norm_reward=True, clip_obs=10.0, gamma=setup.gamma)
        self.model = PPO("MlpPolicy", self.vec_env, n_steps=n_steps, batch_size=batch_size,
                         n_epochs=n_epochs, learning_rate=learning_rate, gamma=setup.gamma,
                         gae_lambda=gae_lambda, ent_coef=ent_coef, clip_range=clip_range,
                         policy_kwargs={"log_std_init": log_std_init,
                                        "net_arch": {"pi": [hidden, hidden],
                                                     "vf": [hidden, hidden]}},
                         seed=seed, device="cpu", verbose=0)
        self.last_episodes: list = []

    def initial_weights(self) -> PolicyWeights:
        return self.weights()

    def train(self, steps: int, opponents: OpponentMix, seed: int) -> PolicyWeights:
        self.batch.start(opponents, seed)
        self.model.set_env(self.vec_env)  # a fresh reset: the episodes of this call's seed
        self.model.set_random_seed(seed)
        self.model.learn(total_timesteps=steps, reset_num_timesteps=False)
        self.last_episodes = list(self.batch.episodes)
        return self.weights()

    def weights(self) -> PolicyWeights:
        """The actor's mean network (tanh hidden layers, identity output) and the
        observation normalisation, as ``PolicyWeights``."""
        import torch

        policy = self.model.policy
        linears = [m for m in policy.mlp_extractor.policy_net if isinstance(m, torch.nn.Linear)]
        linears.append(policy.action_net)
        layers = [(lin.weight.detach().numpy().T.copy(), lin.bias.detach().numpy().copy())
                  for lin in linears]
        rms = self.vec_env.obs_rms
        return PolicyWeights.of(
            layers, activation="tanh", output_activation="identity",
            obs_mean=rms.mean.astype(np.float32),
            obs_std=np.sqrt(rms.var + self.vec_env.epsilon).astype(np.float32),
            obs_clip=float(self.vec_env.clip_obs))

    def act(self, observations: np.ndarray) -> np.ndarray:
        """The deterministic (mean) actions for raw training observations (checks)."""
        actions, _ = self.model.predict(self.vec_env.normalize_obs(observations),
                                        deterministic=True)
        return actions

    def save(self, directory: Path) -> None:
        directory = Path(directory)
        self.model.save(directory / MODEL_FILE)
        self.vec_env.save(directory / NORMALIZE_FILE)

    def load(self, directory: Path) -> None:
        from stable_baselines3 import PPO
        from stable_baselines3.common.vec_env import VecNormalize

        directory = Path(directory)
        self.vec_env = VecNormalize.load(str(directory / NORMALIZE_FILE),
                                         league_vec_env(self.batch))
        self.model = PPO.load(directory / MODEL_FILE, env=self.vec_env, device="cpu")
