"""The learner's training env: ``copies`` matches at once, every player of the learning side a
slot of one batch, numpy in and out, opponents drawn per episode from an ``OpponentMix``.

Framework-neutral on purpose: a CleanRL-style loop steps it directly, and the SB3 adapter
(``teamenv.selfplay.sb3_learner``) wraps it in a ``VecEnv``. Slot ``c * team_size + k`` is
player ``left_{k+1}`` of copy ``c``; every copy ends its episode for all its slots at once.

Reproducible without a seeded reset from outside: episode ``e`` of copy ``c`` plays the
opponent ``opponents.draw(c, e)`` on the tuning seed ``training_seed(seed, c, e)``, so the same
(``seed``, ``opponents``) gives the same episodes whatever happened before.

When an episode ends, ``step`` returns the next episode's first observation for its slots and
puts the last one in the slot's info as ``terminal_observation`` (SB3's convention), with
``TimeLimit.truncated`` (True when the episode was cut at ``episode_s``: its value is
bootstrapped) and ``episode`` (``r``: the slot's return, ``l``: its decisions).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from teamenv.egocentric import EgocentricObservation
from teamenv.env import SoccerParallelEnv
from teamenv.errors import ConfigError
from teamenv.policy_team import apply_reflexes
from teamenv.seeds import TUNING_SEEDS, tuning_seeds
from teamenv.selfplay.pfsp import OpponentMix
from teamenv.selfplay.training_setup import TrainingSetup, kick_gate_m
from teamenv.shaping import PotentialShaping, WeightedPotentials
from teamenv.tournament.spec import parse_team_spec

#: The learner drives this side; the opponent the other.
LEARNER_SIDE = "left"
#: An option's label in the network's output space (``option_labels``): this for the option
#: the rule chose, minus this for the others (inside the output range [-1, 1], so that
#: PPO's clipped actions reach it).
OPTION_LABEL = 0.5


class _CallerActs:
    """An option team as the env hosts it: the env hands it observations and resets it, and
    the training env calls ``act`` itself, once a cycle, to play what the network chose (the
    env's own call would be a second decision in the same cycle)."""

    def __init__(self, team) -> None:
        self.team = team

    def reset(self, seed: int) -> None:
        self.team.reset(seed)

    def act(self, observations) -> dict:
        return {}


def training_seed(seed: int, copy: int, episode: int) -> int:
    """The tuning seed (``teamenv.seeds``) of episode ``episode`` of env copy ``copy``."""
    state = np.random.SeedSequence([seed, copy, episode]).generate_state(1)[0]
    (out,) = tuning_seeds(1, offset=int(state) % (TUNING_SEEDS.end - TUNING_SEEDS.first))
    return out


@dataclass(frozen=True)
class EpisodeRecord:
    """One finished training episode of one copy (``ret``: mean return of its slots)."""

    copy: int
    episode: int
    seed: int
    opponent: str
    ret: float
    decisions: int
    goals_for: int
    goals_against: int
    truncated: bool


class TeamBatchEnv:
    """``copies`` training matches, the learning side's players as slots of one batch."""

    def __init__(self, setup: TrainingSetup, opponents: OpponentMix, copies: int = 1,
                 seed: int = 0) -> None:
        if isinstance(copies, bool) or not isinstance(copies, int) or copies < 1:
            raise ConfigError(f"training env: copies must be an int >= 1, got {copies!r}")
        self.setup, self.copies = setup, copies
        self.team_size = setup.team_size
        self.n_slots = copies * self.team_size
        self.agents = [f"{LEARNER_SIDE}_{k + 1}" for k in range(self.team_size)]
        self.option_spec = parse_team_spec(setup.option_team) if setup.option_team else None
        self._teams: list[dict[str, Any]] = [{} for _ in range(copies)]
        probe = self._make_env(None)
        self.option_count = 0 if self.option_spec is None else setup.actions.size
        #: the options the option team gives to one player each by ranking the scores
        self.ranked_options: tuple[int, ...] = ()
        self.raw_size = int(probe.observation_space(self.agents[0]).shape[0])
        self.gate_m = kick_gate_m() if setup.actions.kick_gate else None
        self.transform = EgocentricObservation.for_env(
            probe, setup.teammate_slots, setup.opponent_slots, setup.ball_race,
            setup.game_state) \
            if setup.observation == "egocentric" else None
        self.observation_size = self.raw_size if self.transform is None else self.transform.size
        self.action_size = setup.actions.size
        self.action_low, self.action_high = (np.array(b, dtype=np.float32)
                                             for b in setup.actions.bounds())
        a = setup.actions
        self._learned = np.array(a.learned)
        self._scale = np.array(a.scale, dtype=np.float32)
        self._fixed = np.array(a.fixed, dtype=np.float32)
        self._cache: list[dict[str, SoccerParallelEnv]] = [{} for _ in range(copies)]
        self.episodes: list[EpisodeRecord] = []
        self.start(opponents, seed)

    # -- set-up ------------------------------------------------------------------------------
    def start(self, opponents: OpponentMix, seed: int) -> None:
        """New opponents and seed; the episode counts restart (call ``reset`` next)."""
        self.opponents, self.seed = opponents, int(seed)
        self._episode = [0] * self.copies
        self._env: list[SoccerParallelEnv | None] = [None] * self.copies
        self._raw = np.zeros((self.n_slots, self.raw_size), dtype=np.float32)
        self._returns = np.zeros(self.n_slots)
        self._decisions = [0] * self.copies
        self._goals = [[0, 0] for _ in range(self.copies)]
        self._opponent_label = [""] * self.copies
        self._seed_now = [0] * self.copies
        self._labels = np.zeros(self.n_slots, dtype=np.int64)
        self._played = np.zeros(self.n_slots, dtype=np.int64)
        self._eligible = np.zeros(self.n_slots, dtype=bool)
        self.episodes = []

    def _make_env(self, opponent) -> SoccerParallelEnv:
        s = self.setup
        shaping = PotentialShaping(WeightedPotentials(s.shaping, s.field), s.cycle_gamma) \
            if s.shaping else None
        cycles = max(1, round(s.episode_s / 0.02))
        right = {} if opponent is None else {"right": opponent.name,
                                             "right_config": opponent.config_dict,
                                             **self._learning_side_options()}
        # an option team's actions are Dict actions: its players talk (say) as they play
        actions = "box" if self.option_spec is None else "dict"
        return SoccerParallelEnv(field=s.field, team_size=s.team_size,
                                 observation_format="box", action_format=actions,
                                 reward=s.reward, reward_fn=shaping, max_cycles=cycles,
                                 profile_phases=False, **right)

    def _learning_side_options(self) -> dict:
        """More env options for a training match: the option team on the learning side,
        its players driven by the caller (a subclass names another team there:
        ``teamenv.selfplay.teacher_env``)."""
        if self.option_spec is None:
            return {}
        return {"left": self.option_spec.name, "left_config": self.option_spec.config_dict,
                "caller_agents": list(self.agents)}

    def _env_for(self, copy: int, opponent) -> SoccerParallelEnv:
        cache = self._cache[copy]
        env = cache.get(opponent.label)
        if env is None:
            env = cache[opponent.label] = self._make_env(opponent)
            if self.option_spec is not None:
                self._teams[copy][opponent.label] = self._take_option_team(env)
        return env

    def _take_option_team(self, env: SoccerParallelEnv):
        """The option team the env hosts on the learning side, which this env then plays
        itself (``_CallerActs``); a ``ConfigError`` if it cannot take options."""
        host = env.team_host
        team = host.teams[LEARNER_SIDE]
        names = getattr(team, "option_names", None)
        if any(not callable(getattr(team, m, None))
               for m in ("choose", "rule_options", "options_from_scores", "eligible")) or \
                names is None:
            raise ConfigError(f"training: option_team {self.setup.option_team!r} does not take "
                              f"options (it needs choose, eligible, options_from_scores, "
                              f"rule_options and option_names)")
        if len(names) != self.setup.actions.size:
            raise ConfigError(f"training: option_team {self.setup.option_team!r} has "
                              f"{len(names)} options {tuple(names)}, the network scores "
                              f"{self.setup.actions.size}")
        host.teams[LEARNER_SIDE] = _CallerActs(team)
        self.ranked_options = tuple(getattr(team, "ranked_options", ()))
        return team

    # -- stepping ----------------------------------------------------------------------------
    def observe(self, raw: np.ndarray) -> np.ndarray:
        """The learner's observation of raw Box rows (egocentric or as they are)."""
        return raw if self.transform is None else self.transform(raw)

    def reset(self) -> np.ndarray:
        """Start an episode in every copy; the observations (n_slots, observation_size)."""
        for copy in range(self.copies):
            self._begin(copy)
        return self.observe(self._raw)

    def _begin(self, copy: int) -> None:
        episode = self._episode[copy]
        opponent = self.opponents.draw(copy, episode)
        seed = training_seed(self.seed, copy, episode)
        env = self._env_for(copy, opponent)
        obs, _ = env.reset(seed=seed)
        rows = self._rows(copy)
        self._raw[rows] = np.stack([obs[a] for a in self.agents])
        self._env[copy] = env
        self._returns[rows] = 0.0
        self._decisions[copy] = 0
        self._goals[copy] = [0, 0]
        self._opponent_label[copy] = opponent.label
        self._seed_now[copy] = seed

    def _rows(self, copy: int) -> slice:
        return slice(copy * self.team_size, (copy + 1) * self.team_size)

    def box_actions(self, outputs: np.ndarray) -> np.ndarray:
        """The env's Box actions (before the reflexes) for network outputs (n, action_size):
        clipped to the output range, scaled, offset, clipped to [-1, 1]."""
        outputs = np.clip(np.asarray(outputs, dtype=np.float32), self.action_low,
                          self.action_high)
        full = np.tile(self._fixed, (len(outputs), 1))
        full[:, self._learned] += outputs * self._scale
        return np.clip(full, -1.0, 1.0)

    def eligible_slots(self) -> np.ndarray:
        """(n_slots,) which slots the option team could give an option to at the last
        decision (its upright field players)."""
        return self._eligible.copy()

    def played_options(self) -> np.ndarray:
        """(n_slots,) the option each slot played in the last decision (an option team's:
        ``options_from_scores`` of the network's outputs, or its rule's)."""
        return self._played.copy()

    def option_labels(self) -> np.ndarray:
        """(n_slots, k) what the option team's rule chose at the first cycle of the last
        decision, in the network's output space (``OPTION_LABEL`` for it, minus that for the
        others): the imitation labels of that decision's observations."""
        labels = np.full((self.n_slots, self.option_count), -OPTION_LABEL, dtype=np.float32)
        labels[np.arange(self.n_slots), self._labels] = OPTION_LABEL
        return labels

    def step(self, outputs: np.ndarray | None):
        """One decision of every slot: ``outputs`` (n_slots, action_size); None with an
        option team: its own rule chooses (the teacher's demonstration). Returns
        observations, rewards (n_slots,), dones (n_slots,) and one info dict per slot."""
        if outputs is None and self.option_spec is not None:
            full = None
        else:
            outputs = np.asarray(outputs, dtype=np.float32)
            if outputs.shape != (self.n_slots, self.action_size):
                raise ConfigError(f"training env: actions of shape {outputs.shape}, expected "
                                  f"({self.n_slots}, {self.action_size})")
            full = self.box_actions(outputs)
        rewards = np.zeros(self.n_slots)
        dones = np.zeros(self.n_slots, dtype=bool)
        infos: list[dict] = [{} for _ in range(self.n_slots)]
        for copy in range(self.copies):
            rows = self._rows(copy)
            if self.option_spec is not None:
                reward, ended, truncated = self._play_options(
                    copy, None if full is None else full[rows, :self.option_count])
            else:
                reward, ended, truncated = self._decide(copy, full[rows])
            rewards[rows] = reward
            self._returns[rows] += reward
            self._decisions[copy] += 1
            if ended:
                self._finish(copy, truncated, infos)
                dones[rows] = True
        return self.observe(self._raw), rewards.astype(np.float32), dones, infos

    def _decide(self, copy: int, full: np.ndarray) -> tuple[np.ndarray, bool, bool]:
        """Play one decision (``action_repeat`` cycles, reflexes each cycle) in ``copy``; the
        slots' discounted reward, whether the episode ended, and whether it was cut."""
        rows, a = self._rows(copy), self.setup.actions

        def actions(cycle: int) -> dict:
            act = apply_reflexes(self._raw[rows], full, self.gate_m, a.walk_to_ball)
            return dict(zip(self.agents, act, strict=True))

        return self._cycles(copy, actions)

    def _play_options(self, copy: int, scores: np.ndarray | None
                      ) -> tuple[np.ndarray, bool, bool]:
        """``_decide`` with an option team: it plays the options its ``options_from_scores``
        makes of the network's ``scores`` (clipped outputs; None: its rule's choices) for
        ``action_repeat`` cycles, deciding how every cycle itself."""
        env, rows = self._env[copy], self._rows(copy)
        team = self._teams[copy][self._opponent_label[copy]]
        self._eligible[rows] = team.eligible(self.agents, self._raw[rows])
        options = None if scores is None else \
            team.options_from_scores(self.agents, self._raw[rows], scores)
        team.choose(options)
        if options is not None:
            self._played[rows] = [options[a] for a in self.agents]

        def actions(cycle: int) -> dict:
            act = team.act(env.team_host.observations[LEARNER_SIDE])
            if cycle == 0:  # the rule chose in this call: the decision's label
                self._labels[rows] = team.rule_options(self.agents)
                if options is None:
                    self._played[rows] = self._labels[rows]
            return act

        return self._cycles(copy, actions)

    def _cycles(self, copy: int, actions) -> tuple[np.ndarray, bool, bool]:
        """Play ``action_repeat`` cycles in ``copy`` with ``actions(cycle)``; the slots'
        discounted reward, whether the episode ended, and whether it was cut."""
        env, rows = self._env[copy], self._rows(copy)
        gamma, discount = self.setup.cycle_gamma, 1.0
        total = np.zeros(self.team_size)
        for cycle in range(self.setup.actions.action_repeat):
            obs, rew, term, trunc, infos = env.step(actions(cycle))
            total += discount * np.array([rew[x] for x in self.agents])
            discount *= gamma
            self._raw[rows] = np.stack([obs[x] for x in self.agents])
            scorer = infos[self.agents[0]].get("goal")
            if scorer is not None:
                self._goals[copy][0 if scorer == LEARNER_SIDE else 1] += 1
            first = self.agents[0]
            if term[first] or trunc[first]:
                return total, True, bool(trunc[first] and not term[first])
        return total, False, False

    def _finish(self, copy: int, truncated: bool, infos: list[dict]) -> None:
        rows = self._rows(copy)
        last = self.observe(self._raw[rows])
        decisions = self._decisions[copy]
        for k, slot in enumerate(range(rows.start, rows.stop)):
            infos[slot]["terminal_observation"] = last[k]
            infos[slot]["TimeLimit.truncated"] = truncated
            infos[slot]["episode"] = {"r": float(self._returns[slot]), "l": decisions, "t": 0.0}
            infos[slot]["opponent"] = self._opponent_label[copy]
        goals = self._goals[copy]
        self.episodes.append(EpisodeRecord(
            copy=copy, episode=self._episode[copy], seed=self._seed_now[copy],
            opponent=self._opponent_label[copy], ret=float(self._returns[rows].mean()),
            decisions=decisions, goals_for=goals[0], goals_against=goals[1],
            truncated=truncated))
        self._episode[copy] += 1
        self._begin(copy)

    def close(self) -> None:
        for cache in self._cache:
            for env in cache.values():
                env.close()
            cache.clear()
