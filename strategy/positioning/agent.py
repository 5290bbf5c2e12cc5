"""One agent's positioning: formation lookup, marking, role assignment, role-vote say and tally.

Decentralized by construction: a ``PositioningAgent`` decides from *its own* world view (built
from its own observation) and the texts it heard; it holds no reference to any other agent.
Each cycle it

1. looks up the formation's home positions for the ball it believes in;
2. optionally replaces some by marking positions (``strategy.positioning.marking``);
3. assigns positions to players by MMD+MSD² (``strategy.positioning.roles.assignment``) from the player
   positions it believes in: its own *role vector*;
4. says that vector (``strategy.positioning.roles.message``, with its uniform number);
5. tallies its own vector with the fresh vectors heard from teammates
   (``strategy.positioning.roles.voting``) and takes the position the team voted for it.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

from strategy.memo import remember
from strategy.perception.worldmodel import WorldModel, WorldView
from strategy.positioning.formation.model import Formation, FormationError
from strategy.positioning.marking import MarkingParams, apply_marking
from strategy.positioning.roles.assignment import FALLEN_PENALTY_M, assign_roles_all
from strategy.positioning.roles.message import decode_role_vote, encode_role_vote
from strategy.positioning.roles.voting import DEFAULT_MAX_AGE_CYCLES, RoleVoter, RoleVoters
from teamenv.field import FieldSpec, field_preset


class PositioningDecision(NamedTuple):
    """One agent's positioning output for one cycle.

    Attributes:
        target: (2,) where this agent should stand, metres, team frame.
        position_index: the formation position the team voted for this agent.
        own_vector: (N,) the role vector this agent computed from its own world view.
        team_vector: (N,) the team's role vector after voting.
        positions: (N, 2) the positions (formation after marking) this agent used, metres.
        say: the role-vote text to say this cycle ("" when silent).
        max_distance: the longest walk of this agent's own assignment, metres.
    """

    target: NDArray[np.float64]
    position_index: int
    own_vector: NDArray[np.intp]
    team_vector: NDArray[np.intp]
    positions: NDArray[np.float64]
    say: str
    max_distance: float


class PositioningAgent:
    """The positioning brain of player ``me`` (index = uniform number - 1).

    Args:
        me: this agent's player index.
        formation: the formation to use (its size must be the team size), already on the
            match's pitch (``Formation.scaled_to`` / ``builtin_formation(name, field)``).
        field: the pitch (for marking: our goal centre).
        marking: marking thresholds, or None for no marking.
        channel: the say channel profile name, "simspark" or "mj".
        max_age_cycles: age limit of heard role vectors, cycles.
        fallen_penalty_m: extra distance charged to fallen players in role assignment, metres.
        say_every: say the role vector every this many cycles (offset by ``me``), 1 = always.
        memo: a dict that caches the pure part of ``step`` (formation lookup, marking, role
            assignment) by its exact inputs (``strategy.memo``); agents of one process may
            share one, so identical world views are computed once (a cache of a pure
            function: no agent sees another's view). None: no caching.
        voter: this agent's ballot box, a row of the team's ``RoleVoters`` (so that
            ``step_all`` counts the team's votes in one pass); None: one of its own with
            ``max_age_cycles``.
    """

    def __init__(
        self,
        me: int,
        formation: Formation,
        field: str | FieldSpec = "simspark",
        *,
        marking: MarkingParams | None = None,
        channel: str = "simspark",
        max_age_cycles: int = DEFAULT_MAX_AGE_CYCLES,
        fallen_penalty_m: float = FALLEN_PENALTY_M,
        say_every: int = 1,
        memo: dict | None = None,
        voter: RoleVoter | None = None,
    ) -> None:
        self.n = formation.n_players
        if not 0 <= me < self.n:
            raise FormationError(f"PositioningAgent: me={me!r} must be in 0..{self.n - 1}")
        if say_every < 1:
            raise FormationError(f"PositioningAgent: say_every must be >= 1, got {say_every!r}")
        self.me = int(me)
        self.formation = formation
        self.field = field_preset(field)
        self.marking = marking
        self.channel = channel
        self.fallen_penalty_m = float(fallen_penalty_m)
        self.say_every = int(say_every)
        self.memo = memo
        if voter is not None and (voter.n, voter.me) != (self.n, self.me):
            raise FormationError(f"PositioningAgent {self.me}: its voter is player "
                                 f"{voter.me} of {voter.n}")
        self.voter = voter if voter is not None else RoleVoter(self.n, self.me, max_age_cycles)
        self.cycle = 0
        # agents of equal marking, penalty and pitch assign alike: they share one object for
        # the three (equal objects are one object; a copy from another process is its own)
        kind = (self.marking, self.fallen_penalty_m, self.field)
        self._assign_kind = _ASSIGN_KINDS.setdefault(kind, kind)

    def reset(self) -> None:
        """Start a new episode: forget heard vectors, restart the cycle count."""
        self.voter.reset()
        self.cycle = 0

    def step_observation(self, obs: Mapping[str, Any],
                         formation: Formation | None = None) -> PositioningDecision:
        """``step`` on a Dict-form ``state`` observation (its own, and the texts it heard),
        through the agent's belief (``WorldModel``)."""
        wm = WorldModel.from_observation(obs, self.me, self.field)
        return self.step(wm.positioning_view(), wm.heard, formation)

    def step(self, view: WorldView, heard: Sequence[str] = (),
             formation: Formation | None = None,
             view_key: bytes | None = None, *,
             votes: Sequence[tuple[int, NDArray[np.intp]]] | None = None,
             own_ballot: NDArray[np.intp] | None = None,
             vote: bool = True, since_own_change: bool = False) -> PositioningDecision:
        """Decide this cycle's position from ``view`` and the ``heard`` texts; advance a cycle.

        Args:
            view: this agent's world view.
            heard: texts heard this cycle from teammates (or itself); non-votes are ignored.
            formation: use this formation this cycle instead of the default one (same size).
            view_key: bytes that identify ``view`` exactly (views with equal keys are equal),
                used for the memo instead of the view's arrays; None: key on the arrays.
            votes: (sender, role vector) pairs heard this cycle, already decoded from another
                message type (then ``heard`` is not decoded).
            own_ballot: the vector to count as this agent's own vote (e.g. the one it last
                said, which is what its teammates hold); None: its fresh vector.
            vote: False: take the position of its own vector (voting switched off).
            since_own_change: count only the vectors heard after this agent's own vector
                last changed (``RoleVoter.vote``): for agents whose beliefs are exact and
                shared (``state`` mode), where a vector heard before the change is only stale;
                with noisy beliefs keep it False, or the vote never gathers.
        """
        if votes is None:
            votes = self.heard_votes(heard)
        return PositioningAgent.step_all([self], [view], [formation], [view_key], [votes],
                                         [own_ballot], vote=vote,
                                         since_own_change=since_own_change)[0]

    @staticmethod
    def step_all(agents: Sequence[PositioningAgent], views: Sequence[WorldView],
                 formations: Sequence[Formation | None], view_keys: Sequence[bytes | None],
                 votes: Sequence[Sequence[tuple[int, NDArray[np.intp]]]],
                 own_ballots: Sequence[NDArray[np.intp] | None], *, vote: bool = True,
                 since_own_change: bool = False) -> list[PositioningDecision]:
        """``step`` of every agent ``agents[i]`` on its own ``views[i]``, formation, key,
        heard ``votes[i]`` and ballot (see ``step``); agents whose voters are rows of one
        ``RoleVoters`` count their votes in one pass."""
        proposed = PositioningAgent._propose_all(agents, views, formations, view_keys, votes)
        ballots = [own.position_of if ballot is None else ballot
                   for (_, _, own), ballot in zip(proposed, own_ballots, strict=True)]
        if vote:
            teams: list = [None] * len(agents)
            boxes: dict[int, tuple[RoleVoters, list[int]]] = {}
            for i, agent in enumerate(agents):
                boxes.setdefault(id(agent.voter.boxes), (agent.voter.boxes, []))[1].append(i)
            for box, members in boxes.values():
                counted = box.vote([agents[i].voter.row for i in members],
                                   [ballots[i] for i in members],
                                   [proposed[i][0] for i in members], since_own_change)
                for i, team in zip(members, counted, strict=True):
                    teams[i] = team
        else:
            teams = [own.position_of for _, _, own in proposed]
        return [agent._decided(cycle, positions, own, team)
                for agent, (cycle, positions, own), team in zip(agents, proposed, teams,
                                                               strict=True)]

    @staticmethod
    def _propose_all(agents: Sequence[PositioningAgent], views: Sequence[WorldView],
                     formations: Sequence[Formation | None],
                     view_keys: Sequence[bytes | None],
                     votes: Sequence[Sequence[tuple[int, NDArray[np.intp]]]]) -> list[tuple]:
        """Advance each agent a cycle, hear its ``votes``, and look up the positions and its
        own role vector for its view: (cycle, positions, own assignment) per agent. What no
        memo holds is computed once per distinct view, the views of agents that assign alike
        (formation, marking, penalty, pitch) together (``_assign_all``)."""
        cycles, keys, fs = [], [], []
        for agent, view, formation, view_key, heard in zip(agents, views, formations,
                                                           view_keys, votes, strict=True):
            f = agent.formation if formation is None else formation
            if f.n_players != agent.n:
                raise FormationError(
                    f"PositioningAgent {agent.me}: formation {f.name!r} has {f.n_players} "
                    f"players, expected {agent.n}"
                )
            cycle = agent.cycle
            agent.cycle += 1
            for sender, vector in heard:
                if 0 <= sender < agent.n:
                    agent.voter.hear(sender, vector, cycle, validate=False)  # decoder checked
            cycles.append(cycle)
            fs.append(f)
            keys.append(None if agent.memo is None else agent._memo_key(f, view, view_key))
        found: list[Any] = [None] * len(agents)
        # agents that assign alike (one formation object, one ``_assign_kind`` object: equal
        # marking, penalty and pitch) -> memo key -> agents
        todo: dict[tuple, dict[Any, list[int]]] = {}
        for i, (agent, key) in enumerate(zip(agents, keys, strict=True)):
            hit = None if key is None else agent.memo.get(key)  # type: ignore[union-attr]
            if hit is not None:
                found[i] = hit
                continue
            alike = (id(fs[i]), id(agent._assign_kind))
            # agents without a memo (key None) compute their own
            todo.setdefault(alike, {}).setdefault(key if key is not None else ("own", i),
                                                  []).append(i)
        for by_key in todo.values():
            first = [members[0] for members in by_key.values()]
            results = agents[first[0]]._assign_all(fs[first[0]], [views[i] for i in first])
            for members, result in zip(by_key.values(), results, strict=True):
                i = members[0]
                if keys[i] is not None:
                    remember(agents[i].memo, keys[i], result)  # type: ignore[arg-type]
                for j in members:
                    found[j] = result
        return [(cycle, positions, own) for cycle, (positions, own) in zip(cycles, found,
                                                                           strict=True)]

    def _memo_key(self, f: Formation, view: WorldView, view_key: bytes | None) -> tuple:
        """What the pure part of a step depends on: its memo key."""
        if view_key is not None:
            return (f, self.marking, self.fallen_penalty_m, view_key)
        return (f, self.marking, self.fallen_penalty_m, view.ball.tobytes(),
                view.players.tobytes(), view.present.tobytes(), view.fallen.tobytes(),
                view.opponents.tobytes(), view.opponents_present.tobytes())

    def _decided(self, cycle: int, positions: NDArray[np.float64], own: Any,
                 team: NDArray[np.intp]) -> PositioningDecision:
        k = int(team[self.me])
        say = ""
        if (cycle + self.me) % self.say_every == 0:
            say = encode_role_vote(self.me, own.position_of, self.n, self.channel)
        return PositioningDecision(positions[k].copy(), k, own.position_of, team, positions, say,
                                   own.max_distance)

    def heard_votes(self, heard: Sequence[str]) -> list[tuple[int, NDArray[np.intp]]]:
        """The (sender, role vector) votes among the ``heard`` texts (others are ignored)."""
        return [v for v in (decode_role_vote(t, self.n, self.channel) for t in heard)
                if v is not None]

    def _assign_all(self, f: Formation, views: Sequence[WorldView]) -> list[tuple]:
        """Formation lookup, marking and role assignment for each of ``views`` (a pure
        function of each view, with this agent's marking, penalty and pitch): (positions,
        own assignment) per view, the role assignments solved together
        (``assign_roles_all``: each the bits of its own)."""
        positions = list(f.home_positions_many(np.array([view.ball for view in views])))
        if self.marking is not None:
            positions = [apply_marking(pos, view.ball, view.opponents, self.field, self.marking,
                                       view.opponents_present, protected=_protected(f)).positions
                         for pos, view in zip(positions, views, strict=True)]
        gi = f.goalie_index
        own = assign_roles_all(np.array([view.players for view in views]), np.array(positions),
                               available=np.array([view.present for view in views]),
                               fallen=np.array([view.fallen for view in views]),
                               goalie=0 if gi is not None else None,
                               goalie_position=gi if gi is not None else 0,
                               fallen_penalty_m=self.fallen_penalty_m)
        for pos in positions:
            pos.flags.writeable = False
        return list(zip(positions, own, strict=True))


#: (marking, fallen penalty, pitch), one object per distinct value, so that ``step_all`` groups
#: agents that assign alike by identity instead of hashing the three every cycle (a handful of
#: entries per process)
_ASSIGN_KINDS: dict[tuple, tuple] = {}


def _protected(f: Formation) -> tuple[int, ...]:
    gi = f.goalie_index
    return () if gi is None else (gi,)
