"""The league's training env with a scripted teacher looking over the learner's shoulder: the
teacher's action for every learning player at every decision, in the network's output space.

``TeacherBatchEnv`` is a ``TeamBatchEnv`` whose matches name a teacher team (any team spec,
e.g. ``chaser`` or ``chaser:all_chase=true``) for the learning side and leave its players to
the caller (the env's ``caller_agents``): the teacher sees every observation the learner sees
but its actions are not played. ``teacher_outputs()`` asks it what it would do now and maps
the answer (a Dict action: walk command, kick power and direction) onto the learner's
actions (``ActionSetup``): the walk scaled to the Box range as the env decodes it, the kick
power 0 when the teacher does not kick, then ``(box - fixed) / scale`` for each learned
entry, clipped to the output range. Those are the labels of behaviour cloning and DAgger
(``teamenv.selfplay.imitation``).

The teacher decides every cycle and the learner every ``action_repeat`` cycles: a label is the
teacher's action at the decision's first cycle, held as the learner holds its own, with the
learner's reflexes (the kick gate) applied on top, so a demonstration played from labels
(``step(teacher_outputs())``) is something the network can do exactly.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from teamenv.box_layout import ACTION_SIZE, KICK_DIRECTION, KICK_POWER, WALK
from teamenv.errors import ConfigError
from teamenv.match import MatchOptions
from teamenv.selfplay.batch_env import LEARNER_SIDE, TeamBatchEnv
from teamenv.selfplay.pfsp import OpponentMix
from teamenv.selfplay.training_setup import TrainingSetup
from teamenv.tournament.errors import TournamentError
from teamenv.tournament.spec import TeamSpec, parse_team_spec, validate_specs


def dict_to_box_action(action: Mapping[str, Any], walk_low: np.ndarray,
                       walk_high: np.ndarray) -> np.ndarray:
    """A Dict action (``walk``, optional ``kick`` = (power, direction in rad)) as the Box
    action (9 entries in [-1, 1]) the env decodes into the same walk and kick
    (``teamenv.box_layout.decode_box_actions`` inverted; no beam)."""
    box = np.zeros(ACTION_SIZE)
    walk = np.asarray(action.get("walk", np.zeros(3)), dtype=float)
    box[WALK] = np.where(walk >= 0.0, walk / walk_high, -walk / walk_low)
    kick = action.get("kick")
    if kick is not None:
        power, direction = (float(v) for v in np.asarray(kick, dtype=float)[:2])
        if power > 0.0:
            box[KICK_POWER] = power
            box[KICK_DIRECTION] = math.remainder(direction, 2.0 * math.pi) / math.pi
    return np.clip(box, -1.0, 1.0)


def parse_teacher(teacher: str | TeamSpec, setup: TrainingSetup | None = None) -> TeamSpec:
    """The teacher's team spec (``name`` or ``name:key=value,...``), built once on the
    training field when ``setup`` is given (as a match would build it: an unknown team or a
    config it rejects fails here); a ``ConfigError`` naming it else."""
    if not isinstance(teacher, TeamSpec) and (not isinstance(teacher, str) or not teacher):
        raise ConfigError(f"imitation: teacher must be a team spec string, got {teacher!r}")
    try:
        spec = parse_team_spec(teacher)
        if setup is not None:
            validate_specs([spec], MatchOptions(field=setup.field, team_size=setup.team_size))
    except TournamentError as exc:
        raise ConfigError(f"imitation: teacher {str(teacher)!r}: {exc}") from None
    return spec


class TeacherBatchEnv(TeamBatchEnv):
    """``TeamBatchEnv`` with ``teacher`` watching the learning side (module docstring)."""

    def __init__(self, setup: TrainingSetup, opponents: OpponentMix, teacher: str | TeamSpec,
                 copies: int = 1, seed: int = 0) -> None:
        self.teacher = parse_teacher(teacher, setup)
        super().__init__(setup, opponents, copies=copies, seed=seed)
        a = setup.actions
        self._learned_idx = np.array(a.learned)

    def _learning_side_options(self) -> dict[str, Any]:
        if self.option_spec is not None:  # the option team's own rule is the teacher
            return super()._learning_side_options()
        agents = [f"{LEARNER_SIDE}_{k + 1}" for k in range(self.setup.team_size)]
        return {"left": self.teacher.name, "left_config": self.teacher.config_dict,
                "caller_agents": agents}

    def teacher_outputs(self) -> np.ndarray:
        """The teacher's actions now, one row per slot, in the network's output space
        (n_slots, action_size): the labels for the current observations. (With an option
        team the labels come after the decision's first cycle: ``option_labels``.)"""
        if self.option_spec is not None:
            raise ConfigError("training env: an option team's labels are its rule's choices "
                              "at the decision (step, then option_labels)")
        out = np.zeros((self.n_slots, self.action_size), dtype=np.float32)
        for copy in range(self.copies):
            env = self._env[copy]
            host = env.team_host
            actions = host.teams[LEARNER_SIDE].act(host.observations[LEARNER_SIDE])
            low, high = env.parser.walk_low, env.parser.walk_high
            boxes = np.stack([dict_to_box_action(actions.get(agent, {}), low, high)
                              for agent in self.agents])
            out[self._rows(copy)] = self.box_to_outputs(boxes)
        return out

    def box_to_outputs(self, boxes: np.ndarray) -> np.ndarray:
        """Network outputs whose ``box_actions`` are ``boxes`` (n, 9) in the learned entries
        (clipped to the output range)."""
        raw = (boxes[:, self._learned_idx] - self._fixed[self._learned_idx]) / self._scale
        return np.clip(raw, self.action_low, self.action_high).astype(np.float32)
