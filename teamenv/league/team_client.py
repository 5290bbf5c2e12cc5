"""The sync-mode loop for all agents of a team: connect, join, then perceive/act each cycle.

In sync mode the server, every cycle, first waits for one answer from each active agent and
then sends each a perception; an agent that does not answer within 5 s is dropped. So after
the join every agent alternates perception -> answer, and reading all perceptions before
sending all answers cannot deadlock. During the join it can (an agent activated a cycle later
than another gets no perception this cycle), so ``join`` answers every perception at once with
``(syn)`` until every agent has been activated."""

from __future__ import annotations

import selectors
import time
from collections.abc import Callable, Mapping, Sequence

from . import effectors
from .connection import READ_TIMEOUT_S, Connection
from .errors import LeagueError, ServerDiedError
from .perception import Perception, parse_perception

#: how long a failed connection waits for the server's process to be seen exiting
DEATH_GRACE_S = 2.0


class TeamClient:
    """All agents of one team on one server: ``join()``, then ``perceive()`` / ``act()``.

    Args:
        host, port: the server's agent port.
        team: team name (letters, digits, ``_-.``).
        unums: uniform numbers to connect (1-99, distinct).
        model: robot model (``T1``).
        strict: unknown perceptors are an error (else kept in ``Perception.unknown``).
        check_alive: called while waiting (e.g. ``LeagueServer.check_alive``) so a dead server
            is reported as such and not as a timeout.
    """

    def __init__(self, host: str, port: int, team: str, unums: Sequence[int], model: str = "T1",
                 strict: bool = True, check_alive=None, timeout_s: float = READ_TIMEOUT_S) -> None:
        if len(set(unums)) != len(unums) or not unums:
            raise LeagueError(f"team {team}: uniform numbers must be distinct and non-empty: "
                              f"{list(unums)}")
        self.team = team
        self.unums = tuple(unums)
        self.strict = strict
        self.timeout_s = timeout_s
        self._check_alive = check_alive or (lambda: None)
        self._inits = {u: effectors.init(team, u, model) for u in self.unums}
        self._conns: dict[int, Connection] = {}
        self._host, self._port = host, port
        self.last: dict[int, Perception] = {}
        self.cycles = 0
        #: called with (unum, raw message) for every message received (recording, debugging)
        self.on_message: Callable[[int, str], None] | None = None

    def who(self, unum: int) -> str:
        return f"agent {self.team}_{unum}"

    # -- lifecycle ---------------------------------------------------------------------------
    def join(self) -> dict[int, Perception]:
        """Wait until every agent has had a perception (answering each with ``(syn)``); the
        next call is ``perceive()`` (``last`` has been answered)."""
        join_teams([self])
        return dict(self.last)

    def _read(self, unum: int) -> Perception:
        try:
            text = self._conns[unum].receive()
        except ServerDiedError:
            self._name_the_death()
            raise
        if self.on_message is not None:
            self.on_message(unum, text)
        return parse_perception(text, strict=self.strict, who=self.who(unum))

    def perceive(self) -> dict[int, Perception]:
        """One perception per agent (blocks until each has arrived)."""
        self.last = {u: self._read(u) for u in self.unums}
        return dict(self.last)

    def act(self, actions: Mapping[int, str] | None = None) -> None:
        """Answer this cycle: ``actions[unum]`` is the agent's message (``(syn)`` if absent)."""
        try:
            for u, message in answers(self.team, self.unums, actions).items():
                self._conns[u].send(message)
        except ServerDiedError:
            self._name_the_death()
            raise
        self.cycles += 1

    def _name_the_death(self) -> None:
        """After a connection failed: raise ``check_alive``'s error (the exit code, the log)
        if the server has exited. A killed server's sockets are reset before its process can
        be reaped, so an exit is awaited for up to ``DEATH_GRACE_S``; a server that is alive
        after that closed the connection itself, and the caller's error stands."""
        deadline = time.monotonic() + DEATH_GRACE_S
        while True:
            self._check_alive()
            if time.monotonic() >= deadline:
                return
            time.sleep(0.02)

    def close(self) -> None:
        for conn in self._conns.values():
            conn.close()
        self._conns.clear()

    def __enter__(self) -> TeamClient:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def answers(team: str, unums: Sequence[int], actions: Mapping[int, str] | None) -> dict[int, str]:
    """Every agent's message of this cycle (``(syn)`` where ``actions`` has none); an action
    for an agent the team does not have is an error naming it."""
    actions = actions or {}
    unknown = set(actions) - set(unums)
    if unknown:
        raise LeagueError(f"team {team}: actions for unknown agents {sorted(unknown)}")
    return {u: actions.get(u) or effectors.SYN for u in unums}


def join_teams(clients: Sequence[TeamClient]) -> None:
    """Connect every team's agents, one at a time, and wait until all are active, answering
    each perception with ``(syn)`` as it comes; it returns when every agent's newest
    perception (``last``) is of the same cycle and answered, so the next call is
    ``perceive()``.

    Teams sharing a server join together (an active agent that is not answered while another
    team joins is dropped after 5 s). One agent at a time, because the server (rcsssmj 0.2.1)
    sometimes hangs when two players are added in the same cycle."""
    order = [(i, u) for i, c in enumerate(clients) for u in c.unums]
    timeout_s = max(c.timeout_s for c in clients)
    with selectors.DefaultSelector() as sel:
        for i, u in order:
            c = clients[i]
            conn = c._conns.get(u)
            if conn is None:
                conn = Connection(c._host, c._port, c.who(u), c.timeout_s)
                c._conns[u] = conn
                conn.send(c._inits[u])
            sel.register(conn, selectors.EVENT_READ, (i, u))
            deadline = time.monotonic() + timeout_s
            while u not in c.last:
                _answer_ready(sel, clients, deadline, f"{c.who(u)} got no perception in "
                                                      f"{timeout_s:.0f} s after init")
        # end with every agent's newest perception read and answered, all of the same cycle:
        # the caller's next step is perceive(). (Answering ``last`` again would queue a second
        # answer at the server, which applies one per cycle: every later action would then
        # take effect a cycle late, for good.)
        deadline = time.monotonic() + timeout_s
        while True:
            times = [p.time or 0.0 for cl in clients for p in cl.last.values()]
            if min(times) >= max(times):
                break
            _answer_ready(sel, clients, deadline, "agents did not reach the same cycle in "
                                                  f"{timeout_s:.0f} s after joining")


def _answer_ready(sel: selectors.BaseSelector, clients: Sequence[TeamClient], deadline: float,
                  timeout_message: str) -> None:
    """Read the perceptions that have arrived and answer each with ``(syn)``."""
    ready = sel.select(timeout=0.5)
    if not ready:
        for other in clients:
            other._check_alive()
        if time.monotonic() > deadline:
            raise ServerDiedError(timeout_message)
    for key, _ in ready:
        ki, ku = key.data
        kc = clients[ki]
        kc.last[ku] = kc._read(ku)
        kc._conns[ku].send(effectors.SYN)
