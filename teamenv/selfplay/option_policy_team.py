"""The team that plays a policy file scoring an option team's options.

A league run with an option team (``TrainingSetup.option_team``, e.g. ``full_options``:
``strategy.teams.full_options``) writes snapshots whose network scores that team's options
(``teamenv.policy_team.mlp_file``'s ``option_team`` entries name it). ``OptionPolicyTeam``
builds the named team (a plugin, looked up like any team) and, every ``action_repeat``-th
cycle, hands it the network's scores for all its agents (one call on their egocentric rows);
the team makes them its choice (``options_from_scores``) and plays it (``choose``, ``act``)
— exactly as the league's training env drove it. As a team spec (it is not a registered
name)::

    teamenv.selfplay.option_policy_team:OptionPolicyTeam:path=snapshots/gen-0003.npz

It lives here, not beside the option team, because reading a policy file is the league's
business: a team plugin imports only teamenv's core.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from teamenv.box_layout import flatten_observation
from teamenv.policy_team import PolicyFileError
from teamenv.policy_team.mlp_file import option_team
from teamenv.selfplay.egocentric_team import egocentric_policy
from teamenv.team_config import team_config
from teamenv.teams import TeamContext, resolve_team_class
from teamenv.tournament.spec import parse_team_spec

#: The team spec name of ``OptionPolicyTeam`` (``module:Class``).
OPTION_POLICY_SPEC_NAME = "teamenv.selfplay.option_policy_team:OptionPolicyTeam"
#: The methods an option team offers (``strategy.teams.full_options.FullOptionsTeam``).
OPTION_TEAM_METHODS = ("choose", "eligible", "options_from_scores", "rule_options")


@dataclass(frozen=True)
class OptionPolicyTeamConfig:
    """``path``: a ``teamenv-mlp-v1`` file with egocentric slots and an ``option_team``."""

    path: str | Path | None = None


class OptionPolicyTeam:
    """The option team a policy file names, its options chosen by the file's network
    (module docstring)."""

    def __init__(self, context: TeamContext, **config: Any) -> None:
        options = team_config("option policy", OptionPolicyTeamConfig, config,
                              error=PolicyFileError)
        path = options.path
        if path is None:
            raise PolicyFileError(f"option policy team ({context.side}): 'path' (a policy "
                                  f"file that scores an option team's options) is required")
        chooser = option_team(path)
        if chooser is None:
            raise PolicyFileError(f"policy file {str(path)!r}: its outputs are Box actions, "
                                  f"not an option team's scores (no 'option_team' entry); "
                                  f"play it with the policy team")
        spec_text, count = chooser
        spec = parse_team_spec(spec_text)
        self.team = resolve_team_class(spec.name)(context, **spec.config_dict)
        missing = [m for m in OPTION_TEAM_METHODS if not callable(getattr(self.team, m, None))]
        names = tuple(getattr(self.team, "option_names", ()))
        if missing or not names:
            raise PolicyFileError(f"policy file {str(path)!r}: team {spec_text!r} takes no "
                                  f"options (it lacks {missing or ['option_names']})")
        if count != len(names):
            raise PolicyFileError(f"policy file {str(path)!r} scores {count} options; team "
                                  f"{spec_text!r} has {len(names)} {names}")
        self.policy = egocentric_policy(path, context, option_team=spec_text)
        self.action_repeat = int(self.policy.action_repeat)
        self.count = count
        self._cycle = 0

    def reset(self, seed: int) -> None:
        self.team.reset(seed)
        self._cycle = 0

    def act(self, observations: Mapping[str, Mapping[str, Any]]) -> dict[str, dict[str, Any]]:
        if observations:
            if self._cycle % self.action_repeat == 0:
                agents = list(observations)
                rows = np.stack([flatten_observation(observations[a]) for a in agents])
                scores = self.policy.network_actions(rows)[:, :self.count]
                self.team.choose(self.team.options_from_scores(agents, rows, scores))
            self._cycle += 1
        return self.team.act(observations)
