"""Voting on role vectors: every agent tallies the vectors it heard and adopts the team's choice.

Each agent computes a *role vector* from its own world model (``position_of[i]`` = the position
player i should take; a permutation of 0..N-1) and says it. Each agent keeps the latest vector
heard from each teammate (its own counts too, always fresh), drops those older than an age
limit, and tallies them: ``votes[i, k]`` = how many vectors give player i position k.

The result is the permutation that agrees with the most votes (sum over players of
``votes[i, result[i]]``): when the per-player most-voted positions form a permutation, that is
it; otherwise it is their repair into one. **Tie-break** (documented and deterministic, the
same on every agent): among the permutations with the most votes, the lexicographically
smallest (player 0's position as small as possible, then player 1's, ...). Agents that tally
the same set of vectors therefore adopt the same assignment, whatever their own world model
says; since a speaker's vector is the same for every listener, the team converges once each
agent has heard the others within the age limit.

The maximum-vote, lexicographically smallest permutation is one ``linear_sum_assignment`` on
integer costs ``-votes * n**n + position * n**(n-1-player)`` (exact in float64 for n <= 12:
the tie-break term is a base-n number whose digits are the positions, smaller than the value
of one vote). Larger n fall back to fixing players one at a time (exact, slower).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import linear_sum_assignment

from teamenv.errors import TeamEnvError

DEFAULT_MAX_AGE_CYCLES = 60
"""Default age limit of a heard vector (cycles; 1.2 s at 20 ms). The simspark channel lets a
listener hear one teammate every 2 cycles, so 10 talking teammates are heard every ~20 cycles."""

_EXACT_MAX_N = 12
#: the cycle of something that never happened (far older than any age limit, no overflow)
_NEVER = np.iinfo(np.int64).min // 2
_WEIGHTS: dict[int, tuple[float, NDArray[np.float64]]] = {}


class VotingError(TeamEnvError, ValueError):
    """A role vector is not a permutation of 0..N-1, or a voter argument is out of range."""


def is_permutation(vector: ArrayLike, n: int) -> bool:
    """True if ``vector`` is a permutation of 0..n-1 (integers, shape (n,))."""
    v = np.asarray(vector)
    if v.shape != (n,) or v.dtype.kind not in "iu":
        return False
    return sorted(v.tolist()) == list(range(n))


def vote_matrix(vectors: ArrayLike, n: int) -> NDArray[np.int64]:
    """(n, n) counts: ``votes[i, k]`` = how many of the (K, n) ``vectors`` give player i position k."""
    v = np.asarray(vectors, dtype=np.intp).reshape(-1, n)
    offsets = _OFFSETS.get(n)
    if offsets is None:
        offsets = _OFFSETS[n] = np.arange(n, dtype=np.intp) * n
    return np.bincount((offsets + v).ravel(), minlength=n * n).reshape(n, n)


_OFFSETS: dict[int, NDArray[np.intp]] = {}


def tally_votes(vectors: ArrayLike | Sequence[ArrayLike], n: int | None = None) -> NDArray[np.intp]:
    """The permutation agreeing with the most of ``vectors`` (K, n); ties: lexicographically smallest.

    Args:
        vectors: K role vectors, each a permutation of 0..n-1 (validated).
        n: number of players (default: the vectors' length).

    Returns:
        (n,) int permutation.
    """
    arr = np.asarray(vectors)
    if arr.ndim == 1:
        arr = arr[None, :]
    if arr.ndim != 2 or arr.shape[0] == 0:
        raise VotingError(f"tally_votes: vectors must have shape (K >= 1, n), got shape {arr.shape}")
    n = arr.shape[1] if n is None else n
    for k, v in enumerate(arr):
        if not is_permutation(v, n):
            raise VotingError(f"tally_votes: vectors[{k}] = {v.tolist()} is not a permutation of "
                              f"0..{n - 1}")
    return _tally(vote_matrix(arr, n))


def _tally(votes: NDArray[np.int64]) -> NDArray[np.intp]:
    n = votes.shape[0]
    if n <= _EXACT_MAX_N:
        scale, tie = _weights(n)
        _, cols = linear_sum_assignment(tie - votes * scale)
        return cols
    return _tally_slow(votes)


def _weights(n: int) -> tuple[float, NDArray[np.float64]]:
    w = _WEIGHTS.get(n)
    if w is None:
        digit = np.array([float(n) ** (n - 1 - i) for i in range(n)])
        w = (float(n) ** n, digit[:, None] * np.arange(n, dtype=np.float64)[None, :])
        _WEIGHTS[n] = w
    return w


def _tally_slow(votes: NDArray[np.int64]) -> NDArray[np.intp]:
    """Same result as ``_tally`` for any n: maximise votes, then fix players in order."""
    n = votes.shape[0]
    cost = -votes.astype(np.float64)
    r, c = linear_sum_assignment(cost)
    best = cost[r, c].sum()
    result = np.full(n, -1, dtype=np.intp)
    for i in range(n):
        for k in range(n):
            if k in result[:i]:
                continue
            trial = cost.copy()
            for j in range(i + 1):
                col = result[j] if j < i else k
                trial[j, :] = np.inf
                trial[:, col] = np.inf
                trial[j, col] = cost[j, col]
            try:
                rr, cc = linear_sum_assignment(trial)
            except ValueError:
                continue
            if trial[rr, cc].sum() == best:
                result[i] = k
                break
    return result


class RoleVoters:
    """The ballot boxes of several agents (rows), as arrays over agents: each row is one
    agent's own box (``RoleVoter``) — the latest role vector it heard from each teammate,
    with its age — so a team counts every agent's vote in one pass (``vote``), each row
    from what that agent alone heard and said.

    Args:
        n_players: team size N (vectors are permutations of 0..N-1).
        agents: the player index (uniform number - 1) of each row.
        max_age_cycles: vectors heard more than this many cycles ago are not counted.
    """

    def __init__(self, n_players: int, agents: Sequence[int],
                 max_age_cycles: int = DEFAULT_MAX_AGE_CYCLES) -> None:
        if n_players < 1:
            raise VotingError(f"RoleVoter: n_players must be >= 1, got {n_players!r}")
        for me in agents:
            if not 0 <= me < n_players:
                raise VotingError(f"RoleVoter: me={me!r} must be in 0..{n_players - 1}")
        if max_age_cycles < 0:
            raise VotingError(f"RoleVoter: max_age_cycles must be >= 0, got {max_age_cycles!r}")
        self.n = int(n_players)
        self.me = np.array(agents, dtype=np.intp)
        self.max_age_cycles = int(max_age_cycles)
        rows = len(self.me)
        self._vectors = np.zeros((rows, self.n, self.n), dtype=np.intp)
        self._cycle = np.full((rows, self.n), _NEVER, dtype=np.int64)
        # the ballots each row counted last (uncounted rows -1; -2: none yet) and their result
        self._last_ballots = np.full((rows, self.n, self.n), -2, dtype=np.intp)
        self._last_result = np.tile(np.arange(self.n, dtype=np.intp), (rows, 1))
        self._own_changed = np.full(rows, _NEVER, dtype=np.int64)

    def voter(self, row: int) -> RoleVoter:
        """The ``RoleVoter`` of agent row ``row`` (a view of this row)."""
        return RoleVoter(self.n, int(self.me[row]), self.max_age_cycles, boxes=self, row=row)

    def reset(self, rows: Sequence[int] | None = None) -> None:
        """Forget everything the agents of ``rows`` (None: all) heard (new episode)."""
        picked = slice(None) if rows is None else list(rows)
        self._cycle[picked] = _NEVER
        self._own_changed[picked] = _NEVER
        self._last_ballots[picked] = -2

    def hear(self, row: int, speaker: int, vector: ArrayLike, cycle: int,
             validate: bool = True) -> None:
        """Row ``row``'s agent heard ``speaker``'s role vector at ``cycle`` (``RoleVoter.hear``)."""
        if not 0 <= speaker < self.n:
            raise VotingError(f"RoleVoter.hear: speaker={speaker!r} must be in 0..{self.n - 1}")
        if validate and not is_permutation(vector, self.n):
            raise VotingError(
                f"RoleVoter.hear: vector from speaker {speaker} = {np.asarray(vector).tolist()} "
                f"is not a permutation of 0..{self.n - 1}"
            )
        if speaker == self.me[row]:
            return
        self._vectors[row, speaker] = vector
        self._cycle[row, speaker] = cycle

    def fresh_speakers(self, row: int, cycle: int) -> NDArray[np.intp]:
        """``RoleVoter.fresh_speakers`` of row ``row``."""
        ok = cycle - self._cycle[row] <= self.max_age_cycles
        ok[self.me[row]] = False
        return np.flatnonzero(ok)

    def vote(self, rows: Sequence[int], own_vectors: ArrayLike, cycles: ArrayLike,
             since_own_change: bool = False) -> NDArray[np.intp]:
        """(R, N) ``RoleVoter.vote`` of each agent row ``rows[r]`` with its own vector
        ``own_vectors[r]`` at ``cycles[r]``: the bookkeeping of all rows in one pass, the
        tally per row (only when its counted ballots changed). Vectors are not validated."""
        picked = np.asarray(rows, dtype=np.intp)
        owns = np.asarray(own_vectors)
        now = np.asarray(cycles, dtype=np.int64)
        me = self.me[picked]
        changed = (self._vectors[picked, me] != owns).any(axis=1)
        self._own_changed[picked[changed]] = now[changed]
        self._vectors[picked, me] = owns
        self._cycle[picked, me] = now
        heard = self._cycle[picked]
        counted = now[:, None] - heard <= self.max_age_cycles
        if since_own_change:
            counted &= heard > self._own_changed[picked][:, None]
            counted[np.arange(len(picked)), me] = True
        # the same ballots as last cycle: the same result; else tally (rarely: per row)
        ballots = np.where(counted[:, :, None], self._vectors[picked], -1)
        new = (ballots != self._last_ballots[picked]).any(axis=(1, 2))
        for r in np.flatnonzero(new).tolist():
            row = int(picked[r])
            self._last_ballots[row] = ballots[r]
            self._last_result[row] = _tally(vote_matrix(self._vectors[row][counted[r]],
                                                        self.n))
        return self._last_result[picked]


class RoleVoter:
    """One agent's ballot box: the latest role vector from each teammate, with its age.

    Args:
        n_players: team size N (vectors are permutations of 0..N-1).
        me: this agent's player index (uniform number - 1).
        max_age_cycles: vectors heard more than this many cycles ago are not counted.
        boxes, row: the team's ``RoleVoters`` and this agent's row there (its votes are then
            counted with the team's in one pass); None: a box of its own.
    """

    def __init__(self, n_players: int, me: int, max_age_cycles: int = DEFAULT_MAX_AGE_CYCLES,
                 *, boxes: RoleVoters | None = None, row: int = 0):
        if boxes is None:
            boxes, row = RoleVoters(n_players, [me], max_age_cycles), 0
        self.boxes, self.row = boxes, row
        self.n, self.me, self.max_age_cycles = boxes.n, int(me), boxes.max_age_cycles

    def reset(self) -> None:
        """Forget everything heard (new episode)."""
        self.boxes.reset([self.row])

    def hear(self, speaker: int, vector: ArrayLike, cycle: int, validate: bool = True) -> None:
        """Record ``speaker``'s role vector, heard at ``cycle`` (it replaces an older one).

        A vector "heard" from oneself is ignored (the agent's own vote is always its latest).
        Raises ``VotingError`` if ``speaker`` is out of range or ``vector`` is not a permutation
        (``validate=False`` skips the permutation check, for vectors a decoder already checked).
        """
        self.boxes.hear(self.row, speaker, vector, cycle, validate)

    def fresh_speakers(self, cycle: int) -> NDArray[np.intp]:
        """Teammates whose latest vector is within the age limit at ``cycle`` (self excluded)."""
        return self.boxes.fresh_speakers(self.row, cycle)

    def vote(self, own_vector: ArrayLike, cycle: int, validate: bool = True,
             since_own_change: bool = False) -> NDArray[np.intp]:
        """Count ``own_vector`` and every fresh heard vector; return the team's assignment
        (``RoleVoters.vote`` with one row).

        ``validate=False`` skips checking that ``own_vector`` is a permutation (for vectors
        ``assign_roles`` just produced).

        ``since_own_change=True``: a heard vector counts only if it was heard after the cycle
        on which ``own_vector`` last changed. For an agent that votes with its fresh vector
        (``state`` mode), a vector heard before that was computed on a situation it has
        already seen change, so it would only hold the team in the old assignment; right
        after a change the own vector decides alone, and teammates' vectors count again as
        they are heard.
        """
        own = np.asarray(own_vector)
        if validate and not is_permutation(own, self.n):
            raise VotingError(
                f"RoleVoter.vote: own vector {own.tolist()} is not a permutation of 0..{self.n - 1}"
            )
        return self.boxes.vote([self.row], own[None], [cycle], since_own_change)[0]
