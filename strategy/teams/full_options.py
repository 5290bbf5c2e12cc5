"""The full team with a learned choice of who plays the ball: ``full_options``.

Why it exists. PPO could not learn a 3 v 3 team that beats ``chaser`` from walk and kick
commands, from scratch or from a clone of ``chaser`` (docs/selfplay.md), and no scripted
3 v 3 team beats it either; at 5 v 5 ``full`` does, by its positioning and kick choice. So
the learned team here decides what the team-play layer of a RoboCup team decides — in open
play, which field player plays the ball, which one covers goal-side of it and which ones hold
their formation positions (``strategy.decision.field_player.OPTIONS``) — and plays the chosen
option with ``full``'s skills: its positioning, kicks, set plays, goalie and talk. That is
the usual split of a hierarchical team (options over scripted skills, as in Google Research
Football's or agent2d's action sets), and it keeps what is learned small enough for this
project's CPU budget.

One team, three uses:

- ``full_options`` alone is ``full`` exactly: the team's own rule chooses (the teacher of
  imitation learning, and a test that the hook changes nothing);
- a policy file that scores its options (a league snapshot, played by
  ``teamenv.selfplay.option_policy_team``): every ``action_repeat``-th cycle one network call
  for all agents scores the options from each agent's egocentric row
  (``teamenv.egocentric``) and the scores are made a team's choice
  (``options_from_scores``: the upright field player with the highest ``play_ball`` score
  plays the ball, the one with the highest ``cover`` score of the others covers, the rest
  hold; who had the ball keeps it unless beaten by ``SWITCH_MARGIN``), held until the next
  decision. Ranking, not a threshold per player, because a team
  needs exactly one ball player: the first clone, deciding each player's option by its own
  highest score, left the ball to nobody in 21 % of its open-play cycles and lost to
  ``chaser`` 1-22 over 8 tuning matches;
- the self-play league's training env drives it from outside (``choose``), and reads what
  the rule would have chosen (``rule_options``) as the imitation label.

The goalie's decisions and everything outside open play (kick-offs, set plays, beaming,
getting up) stay ``full``'s: an option only applies to a field player in play on.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from strategy.decision.field_player import COVER, HOLD, OPTIONS, PLAY_BALL
from strategy.teams.full import FullTeam
from strategy.teams.full_config import FullTeamConfig
from teamenv.box_layout import SELF_COLUMNS
from teamenv.errors import ConfigError
from teamenv.team_config import team_config
from teamenv.teams import TeamContext

#: The team's registered name: what a policy file's ``option_team`` entry names.
TEAM_NAME = "full_options"
#: A player keeps the ball (or the cover) it was given at the last decision unless another
#: player's score for it is higher by this much (scores are taught as +-0.5): without it the
#: first ranked clone switched its ball player 88 times in 4 750 open-play cycles where the
#: rule switched 12 times, and each switch restarts an approach to the ball.
SWITCH_MARGIN = 0.25
#: The column of a state-mode Box row that says the player is down.
_FALLEN = SELF_COLUMNS.index("fallen")


class FullOptionsTeam(FullTeam):
    """``FullTeam`` whose open-play options come from the caller (``choose``,
    ``options_from_scores``); config keys: the fields of ``FullTeamConfig``."""

    name = TEAM_NAME
    option_names = OPTIONS
    #: the options the team gives to one player each, in this order, by ranking the scores
    ranked_options = (PLAY_BALL, COVER)

    def __init__(self, context: TeamContext, **config: Any) -> None:
        team_config(self.name, FullTeamConfig, config)
        super().__init__(context, **config)
        self.agent_index = {agent: k for k, agent in enumerate(context.agents)}
        self._holders: dict[int, str] = {}  # option -> the agent given it last

    def reset(self, seed: int) -> None:
        super().reset(seed)
        self.choose(None)
        self._holders = {}

    def choose(self, options: Mapping[str, int] | None) -> None:
        """Play ``options`` (agent -> index into ``OPTIONS``) from the next ``act`` on, until
        changed; None: the team's own rule chooses."""
        if options is None:
            self.field_maker.option_override = None
            return
        override = {}
        for agent, option in options.items():
            if agent not in self.agent_index:
                raise ConfigError(f"{self.name} team: no agent {agent!r} on this side "
                                  f"({list(self.agent_index)})")
            if isinstance(option, bool) or not isinstance(option, (int, np.integer)) or \
                    not 0 <= option < len(OPTIONS):
                raise ConfigError(f"{self.name} team: {agent}: option must be an int in "
                                  f"0..{len(OPTIONS) - 1} {OPTIONS}, got {option!r}")
            override[self.agent_index[agent]] = int(option)
        self.field_maker.option_override = override

    def eligible(self, agents: Sequence[str], rows: np.ndarray) -> np.ndarray:
        """(len(agents),) which agents an option can be given to: the upright field players
        (their state-mode Box ``rows`` say who is down)."""
        goalie = self.field_maker.goalie
        return np.array([self.agent_index[a] != goalie for a in agents]) & \
            (np.asarray(rows)[:, _FALLEN] < 0.5)

    def options_from_scores(self, agents: Sequence[str], rows: np.ndarray,
                            scores: np.ndarray) -> dict[str, int]:
        """The team's options for network ``scores`` (len(agents), len(OPTIONS)) given the
        agents' state-mode Box ``rows``: the upright field player with the highest
        ``play_ball`` score plays the ball, the upright field player with the highest
        ``cover`` score of the others covers, everyone else holds (ties: the first agent);
        the player that had the ball (the cover) at the last call keeps it while it is
        upright and within ``SWITCH_MARGIN`` of the best score."""
        free = self.eligible(agents, rows)
        scores = np.asarray(scores, dtype=np.float64)
        options = np.full(len(agents), HOLD, dtype=np.int64)
        for option in self.ranked_options:
            if not free.any():
                self._holders.pop(option, None)
                continue
            pick = int(np.flatnonzero(free)[np.argmax(scores[free, option])])
            held = self._holders.get(option)
            if held in agents:
                k = agents.index(held)
                if free[k] and scores[k, option] >= scores[pick, option] - SWITCH_MARGIN:
                    pick = k
            options[pick] = option
            free[pick] = False
            self._holders[option] = agents[pick]
        return dict(zip(agents, options.tolist(), strict=True))

    def rule_options(self, agents: Sequence[str]) -> np.ndarray:
        """(len(agents),) the option the team's own rule chose for each agent at its last
        open-play decision (``HOLD`` for one that has made none: the goalie, or before play
        on)."""
        chosen = self.field_maker.chosen_options
        return np.array([chosen.get(self.agent_index[a], HOLD) for a in agents], dtype=np.int64)
