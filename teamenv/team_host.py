"""Hosting the team plugins of one env: the scripted teams that drive whole sides.

``TeamHost`` builds each named team (``teamenv.teams.make_team``) with its ``TeamContext``,
seeds it every episode, hands it its agents' observations, turns its answer into rows of the
cycle's ``Commands``, times it and reports what goes wrong as a ``TeamFault`` naming the side
(a plugin's bug must not look like the env's). The env (``teamenv.env``) stays the PettingZoo
shell around it: it asks the host for the teams' actions once per cycle.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Mapping, Sequence
from typing import Any

from teamenv.actions import ActionParser
from teamenv.errors import ActionError, ConfigError, TeamFault
from teamenv.lazy import LazyObservations
from teamenv.sim.perception import ObservationRows
from teamenv.sim.simulation import Commands
from teamenv.teams import TeamContext, make_team

#: Keys of ``TeamHost.phase_s``: the parts of the env's ``timings()`` the teams take.
TEAM_PHASES = ("actions", "team_left", "team_right", "perception")


class TeamHost:
    """The team plugins of one env and everything the env does with them.

    ``specs``: side -> (team spec or None, its config); a side with no spec is the caller's.
    ``context``: side -> the ``TeamContext`` its team is built with. ``row``: agent name ->
    player index. ``parser``: the strict Dict-form parser the teams' actions go through.
    ``cycle_budget_s``: a team whose ``act()`` takes longer faults as "too_slow".

    ``teams`` holds the plugins, left before right; ``agents[side]`` the agents of that side;
    ``time_s[side]`` the seconds its ``act()`` calls took (always measured: the cycle budget
    needs them); ``acting_side`` the side whose ``act()`` runs now (None between calls), for
    a caller that must name a team that stalls; ``observations[side]`` what it was handed last.
    ``phase_s`` (keys ``TEAM_PHASES``) adds up, when ``profile_phases``, the time of the
    teams' ``act()`` and ``reset()``, of turning their actions into commands ("actions") and of
    handing them their observations ("perception").
    """

    def __init__(self, specs: Mapping[str, tuple[str | None, Mapping[str, Any] | None]],
                 context: Callable[[str], TeamContext], row: Mapping[str, int],
                 parser: ActionParser, cycle_budget_s: float | None = None,
                 profile_phases: bool = True) -> None:
        self.teams: dict[str, Any] = {}
        self.agents: dict[str, list[str]] = {}
        for side, (spec, config) in specs.items():
            if spec is None:
                if config:
                    raise ConfigError(f"{side}_config given but no {side} team is named")
                continue
            side_context = context(side)
            self.teams[side] = make_team(spec, side_context, config)
            self.agents[side] = list(side_context.agents)
        self._agent_sets = {side: set(a) for side, a in self.agents.items()}
        self._row = row
        self._rows = {side: [row[x] for x in a] for side, a in self.agents.items()}
        # The agents whose actions each team gives: the same list object as ``agents[side]``
        # while the team drives all of them (``leave_to_caller`` narrows it).
        self._fill: dict[str, list[str]] = dict(self.agents)
        self._parser = parser
        self.cycle_budget_s = cycle_budget_s
        self.time_s = {side: 0.0 for side in self.teams}
        self.acting_side: str | None = None
        self.observations: dict[str, dict[str, Any]] = {}
        self.profile_phases = bool(profile_phases)
        # float() returns 0.0: with profiling off the clock is never read.
        self._clock = time.perf_counter if self.profile_phases else float
        self.reset_timings()

    def reset_timings(self) -> None:
        """Zero ``phase_s`` (``time_s`` is kept)."""
        self.phase_s = dict.fromkeys(TEAM_PHASES, 0.0)

    def leave_to_caller(self, caller_agents: Sequence[str]) -> None:
        """The caller drives ``caller_agents`` (of team sides): their teams still see their
        observations, and the teams' actions for them are ignored."""
        if caller_agents:
            self._fill = {side: [x for x in a if x not in caller_agents]
                          for side, a in self.agents.items()}

    def reset(self, seeds: Sequence[int]) -> None:
        """Start an episode: the k-th team (left before right) is reset with ``seeds[k]``."""
        for (side, team), seed in zip(self.teams.items(), seeds, strict=True):
            t0 = self._clock()
            self._call(side, team.reset, seed)
            self.phase_s["team_" + side] += self._clock() - t0

    def observe(self, observations: Sequence[Any]) -> None:
        """Hand each team its agents' observations (``observations``: every player's, in
        player order, Dict form) for the next ``act``."""
        t0 = self._clock()
        rows = self._rows
        if isinstance(observations, ObservationRows):  # dicts built on first use
            self.observations = {side: LazyObservations(agents, observations, self._row)
                                 for side, agents in self.agents.items()}
        else:
            self.observations = {
                side: dict(zip(agents, [observations[r] for r in rows[side]], strict=True))
                for side, agents in self.agents.items()
            }
        self.phase_s["perception"] += self._clock() - t0

    def act(self, cmd: Commands) -> None:
        """Ask every team for its actions on the last observations and write them into its
        agents' rows of ``cmd``."""
        for side, team in self.teams.items():
            self._act(side, team, cmd)

    def _call(self, side: str, fn: Callable, *args: Any) -> Any:
        try:
            return fn(*args)
        except Exception as exc:  # a plugin's bug must not look like ours
            raise TeamFault(side, "raised", f"{type(exc).__name__}: {exc}") from exc

    def _act(self, side: str, team: Any, cmd: Commands) -> None:
        agents = self.agents[side]
        self.acting_side = side
        start = time.perf_counter()
        actions = self._call(side, team.act, self.observations[side])
        elapsed = time.perf_counter() - start
        self.acting_side = None
        self.time_s[side] += elapsed
        if self.profile_phases:
            self.phase_s["team_" + side] += elapsed
        start = self._clock()
        if self.cycle_budget_s is not None and elapsed > self.cycle_budget_s:
            raise TeamFault(side, "too_slow", f"act() took {elapsed * 1e3:.1f} ms, budget "
                            f"{self.cycle_budget_s * 1e3:.1f} ms")
        if not isinstance(actions, Mapping):
            raise TeamFault(side, "invalid_action", f"act() returned {type(actions).__name__}, "
                            "expected a dict keyed by agent name")
        driven = self._agent_sets[side]
        extra = [a for a in actions if a not in driven]
        if extra:
            raise TeamFault(side, "invalid_action", f"act() returned actions for {extra}, which "
                            f"it does not drive")
        fill = self._fill[side]
        if len(actions) == len(agents) and fill is agents:  # every agent (the usual case)
            given, rows = agents, self._rows[side]
        else:  # some agents missing, or the caller drives some of this side
            given = [a for a in fill if a in actions]
            rows = [self._row[a] for a in given]
        try:
            self._parser.fill(cmd, rows, given, [actions[a] for a in given], {})
        except ActionError as exc:
            raise TeamFault(side, "invalid_action", str(exc)) from exc
        self.phase_s["actions"] += self._clock() - start
