"""What the learning team plays in training: field, team size, episode, observation, actions,
reward. One frozen, JSON-able description, shared by the training env, the snapshot writer and
the league's stored configuration (a resumed run must train on exactly the same setup)."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import asdict, dataclass
from dataclasses import field as dataclass_field
from typing import Any

import locomotion
import portable_math as pm
from teamenv.box_layout import ACTION_SIZE
from teamenv.capabilities import DEFAULT_LOCOMOTION_PROFILE
from teamenv.config import build_config
from teamenv.errors import ConfigError
from teamenv.field import field_preset
from teamenv.rewards import reward_weights
from teamenv.shaping import POTENTIALS

OBSERVATIONS = ("egocentric", "box")

#: A gated kick is asked for within this share of the body's kick reach (the chaser's 0.9:
#: the kick fires 0.5 s after it is asked for, and the ball must still be in reach then).
KICK_GATE_SHARE = 0.9


def kick_gate_m() -> float:
    """Where a gated kick is asked for (m): ``KICK_GATE_SHARE`` of the kick reach of the
    env's default locomotion profile (the one training and rating matches use)."""
    return KICK_GATE_SHARE * float(locomotion.load_profile(DEFAULT_LOCOMOTION_PROFILE).kick_reach)


@dataclass(frozen=True)
class ActionSetup:
    """How the network's outputs become the env's Box action ([-1, 1]^9: vx, vy, vturn,
    kick power, kick direction, beam request, beam x, y, rot).

    ``learned``: the Box entries the network sets; entry ``learned[k]`` is
    ``fixed[learned[k]] + scale[k] * output_k``, the others are ``fixed``; then clipped to
    [-1, 1]. ``kick_gate``: a kick is asked for only while the ball is within
    ``KICK_GATE_SHARE`` of the kick reach (a kick request starts the kick motion wherever the
    ball is, and a kicking player stands still; without the gate a network that asks for a
    kick every cycle never walks, docs/rl_training.md). ``walk_to_ball``: the walk entries are
    a reflex instead (walk at the ball, stand for the kick). ``action_repeat``: the network
    decides every that many cycles. All of it is written into the snapshot's policy file
    (``teamenv-mlp-v1``'s output layer, ``kick_gate_m``, ``walk_to_ball``,
    ``action_repeat``), so a snapshot plays as the learner did.
    """

    learned: tuple[int, ...] = (0, 1, 2, 3, 4)
    scale: tuple[float, ...] = (1.0, 1.0, 1.0, 0.5, 1.0)
    fixed: tuple[float, ...] = (0.0, 0.0, 0.0, 0.5, 0.0, 0.0, 0.0, 0.0, 0.0)
    kick_gate: bool = True
    walk_to_ball: bool = False
    action_repeat: int = 5

    def __post_init__(self) -> None:
        object.__setattr__(self, "learned", tuple(int(k) for k in self.learned))
        object.__setattr__(self, "scale", tuple(float(s) for s in self.scale))
        object.__setattr__(self, "fixed", tuple(float(f) for f in self.fixed))
        if not self.learned or len(set(self.learned)) != len(self.learned) or \
                not all(0 <= k < ACTION_SIZE for k in self.learned):
            raise ConfigError(f"actions: learned must be distinct Box entries in 0..{ACTION_SIZE - 1},"
                              f" got {list(self.learned)}")
        if len(self.scale) != len(self.learned) or \
                not all(math.isfinite(s) and s > 0 for s in self.scale):
            raise ConfigError(f"actions: scale needs one finite number > 0 per learned entry, got "
                              f"{list(self.scale)}")
        if len(self.fixed) != ACTION_SIZE or not all(-1.0 <= f <= 1.0 for f in self.fixed):
            raise ConfigError(f"actions: fixed needs {ACTION_SIZE} values in [-1, 1], got "
                              f"{list(self.fixed)}")
        if self.walk_to_ball and not self.kick_gate:
            raise ConfigError("actions: walk_to_ball needs kick_gate (where the walk stops)")
        if isinstance(self.action_repeat, bool) or not isinstance(self.action_repeat, int) or \
                self.action_repeat < 1:
            raise ConfigError(f"actions: action_repeat must be an int >= 1, got "
                              f"{self.action_repeat!r}")

    @property
    def size(self) -> int:
        """The network's output size."""
        return len(self.learned)

    def bounds(self) -> tuple[list[float], list[float]]:
        """The network output range whose image is [-1, 1] in each learned entry (a
        trainer that clips its actions to this range clips exactly as the env does)."""
        low, high = [], []
        for k, s in zip(self.learned, self.scale, strict=True):
            low.append((-1.0 - self.fixed[k]) / s)
            high.append((1.0 - self.fixed[k]) / s)
        return low, high


def option_actions(options: int, action_repeat: int = 5) -> ActionSetup:
    """The action setup of a network that scores ``options`` options (``TrainingSetup``'s
    ``option_team``): one output per option in the first Box entries, no reflexes."""
    return ActionSetup(learned=tuple(range(options)), scale=(1.0,) * options,
                       fixed=(0.0,) * ACTION_SIZE, kick_gate=False, walk_to_ball=False,
                       action_repeat=action_repeat)


@dataclass(frozen=True)
class TrainingSetup:
    """The learning side's training episodes.

    Args:
        field: field preset of the training episodes (and of the rating matches).
        team_size: players per side; the learner drives the whole left side, one network
            shared by every player (each player is one sample of the batch).
        episode_s: a training episode starts at kick-off and is cut (truncated, not
            terminated: its value is bootstrapped) after this many seconds of game time.
        observation: "egocentric" (``teamenv.egocentric``: nearest ``teammate_slots``
            teammates and ``opponent_slots`` opponents, any team size) or "box" (the env's
            state-mode Box row, players by uniform number).
        actions: ``ActionSetup``.
        reward: the env's ``reward=`` weights (``teamenv.rewards``); default the goal, +1/-1.
        shaping: potential-based shaping (``teamenv.shaping``) added on top:
            ``{potential: weight}`` over ``teamenv.shaping.POTENTIALS`` (empty: none). The
            default pays the team for the ball's approach to the goal it attacks
            (``ball_to_goal``) and, half as much, for getting its nearest player to the
            ball (``team_to_ball``); goals stay what the optimal policy is about.
        gamma: the learner's discount per decision (``actions.action_repeat`` cycles); the
            shaping uses ``gamma ** (1 / action_repeat)`` per cycle, and a decision's reward is
            its cycles' rewards discounted by that, so the shaping is exact per decision.
        ball_race: egocentric rows end with the ball-race columns (``teamenv.egocentric``:
            the agent's distance to the ball, and how much farther the nearest upright
            teammate and opponent are), which a team choosing its ball player needs.
        game_state: egocentric rows keep the ``game.*`` columns (clock, half, score); False
            leaves them out (a rule being cloned never reads them, and episodes shorter than
            a match would leave the network clock values it never saw).
        option_team: "" (the network's outputs are Box actions), or the team spec of a team
            that plays options the network chooses (e.g. ``full_options``,
            ``strategy.teams.full_options``): the learning side is that team, the network
            scores its options for every player (``actions`` = ``option_actions(k)``, the
            highest score wins) and the team plays them with its own skills.
    """

    field: str = "simspark"
    team_size: int = 3
    episode_s: float = 60.0
    observation: str = "egocentric"
    teammate_slots: int = 2
    opponent_slots: int = 3
    actions: ActionSetup = dataclass_field(default_factory=ActionSetup)
    reward: Mapping[str, float] = dataclass_field(default_factory=lambda: {"goal": 1.0})
    shaping: Mapping[str, float] = dataclass_field(
        default_factory=lambda: {"ball_to_goal": 1.0, "team_to_ball": 0.5})
    gamma: float = 0.99
    option_team: str = ""
    ball_race: bool = False
    game_state: bool = True

    def __post_init__(self) -> None:
        field_preset(self.field)
        if isinstance(self.team_size, bool) or not isinstance(self.team_size, int) or \
                not 1 <= self.team_size <= 11:
            raise ConfigError(f"training: team_size must be an int in 1..11, got "
                              f"{self.team_size!r}")
        if not (isinstance(self.episode_s, (int, float)) and math.isfinite(self.episode_s)
                and self.episode_s > 0):
            raise ConfigError(f"training: episode_s must be a number of seconds > 0, got "
                              f"{self.episode_s!r}")
        if self.observation not in OBSERVATIONS:
            raise ConfigError(f"training: observation {self.observation!r} is not one of "
                              f"{list(OBSERVATIONS)}")
        for name in ("teammate_slots", "opponent_slots"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int) or value < 0:
                raise ConfigError(f"training: {name} must be an int >= 0, got {value!r}")
        if not isinstance(self.actions, ActionSetup):
            object.__setattr__(self, "actions", ActionSetup(**dict(self.actions)))
        object.__setattr__(self, "reward", dict(reward_weights(dict(self.reward)) or {}))
        if not isinstance(self.shaping, Mapping):
            raise ConfigError(f"training: shaping must be a dict {{potential: weight}}, got "
                              f"{self.shaping!r}")
        for name, weight in self.shaping.items():
            if name not in POTENTIALS:
                raise ConfigError(f"training: shaping: unknown potential {name!r}; potentials "
                                  f"are {sorted(POTENTIALS)}")
            if isinstance(weight, bool) or not isinstance(weight, (int, float)) or \
                    not math.isfinite(weight):
                raise ConfigError(f"training: shaping[{name!r}]: weight must be a finite "
                                  f"number, got {weight!r}")
        object.__setattr__(self, "shaping", {k: float(v) for k, v in self.shaping.items()})
        if not (isinstance(self.gamma, (int, float)) and 0.0 < self.gamma <= 1.0):
            raise ConfigError(f"training: gamma must be in (0, 1], got {self.gamma!r}")
        if not isinstance(self.ball_race, bool):
            raise ConfigError(f"training: ball_race must be true or false, got "
                              f"{self.ball_race!r}")
        if not isinstance(self.game_state, bool):
            raise ConfigError(f"training: game_state must be true or false, got "
                              f"{self.game_state!r}")
        if not self.game_state and self.observation != "egocentric":
            raise ConfigError("training: game_state=false leaves columns out of egocentric "
                              "observations; observation is 'box'")
        if self.ball_race and self.observation != "egocentric":
            raise ConfigError("training: ball_race columns are part of egocentric "
                              "observations; observation is 'box'")
        if not isinstance(self.option_team, str):
            raise ConfigError(f"training: option_team must be a team spec string ('' for "
                              f"none), got {self.option_team!r}")
        if self.option_team:
            a = self.actions
            if a.kick_gate or a.walk_to_ball or a.learned != tuple(range(a.size)) or \
                    any(f != 0.0 for f in a.fixed) or any(x != 1.0 for x in a.scale):
                raise ConfigError(f"training: option_team {self.option_team!r}: the network "
                                  f"scores options; use actions=option_actions(k) (got "
                                  f"{asdict(a)})")
            if self.observation != "egocentric":
                raise ConfigError(f"training: option_team {self.option_team!r} reads "
                                  f"egocentric observations, got {self.observation!r}")

    @property
    def cycle_gamma(self) -> float:
        """The discount per env cycle: ``gamma ** (1 / action_repeat)``."""
        return float(pm.power(float(self.gamma), 1.0 / self.actions.action_repeat))

    def to_json(self) -> dict[str, Any]:
        data = asdict(self)
        data["actions"] = asdict(self.actions)
        data["reward"] = dict(self.reward)
        data["shaping"] = dict(self.shaping)
        for key in ("learned", "scale", "fixed"):
            data["actions"][key] = list(data["actions"][key])
        return data

    @classmethod
    def from_json(cls, data: Mapping[str, Any]) -> TrainingSetup:
        values = dict(data)
        if "actions" in values:
            values["actions"] = build_config(ActionSetup, values["actions"], section="actions")
        return build_config(cls, values, section="training")
