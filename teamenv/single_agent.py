"""Single-agent Gymnasium views of the env: one player (``PlayerEnv``) or one whole team
(``TeamEnv``) controlled by the caller, everybody else driven by registered teams.

Both use the env's flat formats (``observation_format="box"``, ``action_format="box"``; the
layouts are in ``teamenv.SoccerParallelEnv``'s docstring) and pass every other option
(``scenario``, ``reward``, ``field``, ``team_size``, ``observation_mode``, ``rules``, ...)
through to ``teamenv.parallel_env``. Registered as ``teamenv/Player-v0`` and
``teamenv/Team-v0`` (``teamenv.registration``).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import gymnasium
import numpy as np
from gymnasium import spaces

from teamenv.env import SIDES, SoccerParallelEnv
from teamenv.errors import ConfigError

#: Options a view sets itself; passing them is an error rather than silently overridden.
_OWN_OPTIONS = ("left", "right", "left_config", "right_config", "caller_agents",
                "observation_format", "action_format")


def _check_options(view: str, options: Mapping[str, Any]) -> None:
    taken = sorted(set(options) & set(_OWN_OPTIONS))
    if taken:
        raise ConfigError(f"{view}: {taken} are set by the view itself (use agent/side, "
                          "teammates/opponents and their *_config options instead)")


def _episode_seed(env: gymnasium.Env, seed: int | None) -> int:
    """The seed of the wrapped env's episode: ``seed``, or the next draw of the view's own
    generator (so a run of resets after one seeded reset is deterministic too)."""
    if seed is not None:
        return int(seed)
    return int(env.np_random.integers(0, 2**63 - 1))


class PlayerEnv(gymnasium.Env):
    """One player controlled by the caller; its teammates and the opponents are teams.

    Args:
        agent: the caller's player, e.g. "left_1" (uniform 1: the keeper in the built-in
            teams' formations) or "right_3".
        teammates: the registered team (or ``module:Class``) driving the rest of its side;
            it sees the caller's player too, and its actions for it are ignored.
        opponents: the team driving the other side.
        teammates_config, opponents_config: keyword options of those teams.
        **env_options: any other ``teamenv.parallel_env`` option.

    Observation: the player's flat Box observation; action: its flat Box action in [-1, 1]^9
    (no ``say``); reward: its reward from the env (``reward=`` picks the terms). An episode
    terminates or truncates when the env's does (scenario end, GameOver, ``max_cycles``);
    ``info`` is the player's info (``end`` holds a scenario episode's reason).
    """

    metadata = {"render_modes": ["human", "rgb_array"], "render_fps": 50}

    def __init__(self, agent: str = "left_1", teammates: str = "full",
                 opponents: str = "chaser", teammates_config: Mapping[str, Any] | None = None,
                 opponents_config: Mapping[str, Any] | None = None,
                 render_mode: str | None = None, **env_options: Any) -> None:
        _check_options("PlayerEnv", env_options)
        side = agent.split("_")[0] if isinstance(agent, str) else None
        if side not in SIDES:
            raise ConfigError(f"PlayerEnv: agent must be 'left_<k>' or 'right_<k>', got "
                              f"{agent!r}")
        other = "right" if side == "left" else "left"
        self.agent = agent
        self.env = SoccerParallelEnv(
            **{side: teammates, f"{side}_config": teammates_config,
               other: opponents, f"{other}_config": opponents_config},
            caller_agents=[agent], observation_format="box", action_format="box",
            render_mode=render_mode, **env_options)
        if agent not in self.env.possible_agents:
            raise ConfigError(f"PlayerEnv: agent {agent!r} is not a player of this env; "
                              f"players are {self.env.player_names}")
        self.observation_space = self.env.observation_space(agent)
        self.action_space = self.env.action_space(agent)
        self.render_mode = render_mode

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        super().reset(seed=seed)
        observations, infos = self.env.reset(seed=_episode_seed(self, seed), options=options)
        return observations[self.agent], dict(infos[self.agent])

    def step(self, action: np.ndarray):
        if self.env.episode_over:
            raise ConfigError("PlayerEnv: step() on a finished episode; call reset() first")
        obs, rewards, terminations, truncations, infos = self.env.step({self.agent: action})
        return (obs[self.agent], float(rewards[self.agent]), bool(terminations[self.agent]),
                bool(truncations[self.agent]), dict(infos[self.agent]))

    def render(self):
        return self.env.render()

    def close(self) -> None:
        self.env.close()


class TeamEnv(gymnasium.Env):
    """A whole side as one agent; the other side is a team.

    Args:
        side: "left" (default) or "right": the caller's side.
        opponents, opponents_config: the team driving the other side and its options.
        **env_options: any other ``teamenv.parallel_env`` option.

    ``agents`` are the side's players on the pitch (a scenario's benched players left out),
    uniform-number order; with O = one player's flat observation length:
    observation = concatenation, ``obs[k*O:(k+1)*O]`` is ``agents[k]``'s observation;
    action = concatenation, ``action[9*k:9*(k+1)]`` is ``agents[k]``'s Box action.
    Reward: the mean of the agents' rewards (every built-in term is team-shared, so it is
    the team's reward). ``info``: ``{"agents": {agent: info}}`` plus ``end`` (a scenario
    episode's reason) when the episode ends.
    """

    metadata = {"render_modes": ["human", "rgb_array"], "render_fps": 50}

    def __init__(self, side: str = "left", opponents: str = "chaser",
                 opponents_config: Mapping[str, Any] | None = None,
                 render_mode: str | None = None, **env_options: Any) -> None:
        _check_options("TeamEnv", env_options)
        if side not in SIDES:
            raise ConfigError(f"TeamEnv: side must be 'left' or 'right', got {side!r}")
        other = "right" if side == "left" else "left"
        self.side = side
        self.env = SoccerParallelEnv(**{other: opponents, f"{other}_config": opponents_config},
                                     observation_format="box", action_format="box",
                                     render_mode=render_mode, **env_options)
        self.agents = [a for a in self.env.possible_agents if a.startswith(side + "_")]
        one_obs = self.env.observation_space(self.agents[0])
        one_act = self.env.action_space(self.agents[0])
        k = len(self.agents)
        self.observation_space = spaces.Box(np.tile(one_obs.low, k), np.tile(one_obs.high, k),
                                            dtype=one_obs.dtype)
        self.action_space = spaces.Box(np.tile(one_act.low, k), np.tile(one_act.high, k),
                                       dtype=one_act.dtype)
        self._act_size = one_act.shape[0]
        self.render_mode = render_mode

    def _joined(self, observations: Mapping[str, np.ndarray]) -> np.ndarray:
        return np.concatenate([observations[a] for a in self.agents])

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        super().reset(seed=seed)
        observations, infos = self.env.reset(seed=_episode_seed(self, seed), options=options)
        return self._joined(observations), {"agents": dict(infos)}

    def step(self, action: np.ndarray):
        if self.env.episode_over:
            raise ConfigError("TeamEnv: step() on a finished episode; call reset() first")
        action = np.asarray(action)
        if action.shape != self.action_space.shape:
            raise ConfigError(f"TeamEnv: action of shape {action.shape}, expected "
                              f"{self.action_space.shape} ({len(self.agents)} agents x "
                              f"{self._act_size})")
        rows = action.reshape(len(self.agents), self._act_size)
        obs, rewards, terminations, truncations, infos = self.env.step(
            dict(zip(self.agents, rows, strict=True)))
        first = self.agents[0]
        info: dict[str, Any] = {"agents": dict(infos)}
        if "end" in infos[first]:
            info["end"] = infos[first]["end"]
        reward = float(np.mean([rewards[a] for a in self.agents]))
        return (self._joined(obs), reward, bool(terminations[first]), bool(truncations[first]),
                info)

    def render(self):
        return self.env.render()

    def close(self) -> None:
        self.env.close()
