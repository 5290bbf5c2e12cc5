"""One forward pass of the walking network per cycle for a whole team (``WalkBatch``).

A league match runs one ``NetworkWalkController`` per robot; each cycle each of them ran the
network on its own observation: 14 passes of a few dozen NumPy calls each for a 7 v 7, most
of their cost the calls, not the arithmetic. With a ``WalkBatch`` the controllers of a team
hand their observations in (``submit``: the controller's message is then a placeholder), and
the batch runs the network once on the stacked observations (``flush``) and puts each
robot's motor effectors in place of its placeholder (``resolve``, on the team's messages of
the cycle).

Each robot gets exactly the bits its own pass gives: ``WalkNetwork`` computes row by row
with the same sums (``portable_math.matmul`` is einsum, whose loops sum each row in the same
order whatever the number of rows; the LayerNorm's mean, the ELU and the clip are per row;
``tests/teamenv/league/test_league_network_batch.py`` checks every batch size of a 7 v 7 bit
for bit and a match's replay with and without batches).

A controller asked twice in one cycle (a second message needs the first's action as its
previous action) or reset while it waits makes the batch ``flush`` first, so the order of
events is that of the passes one by one.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from typing import Any

import numpy as np

from .errors import LeagueError

# the controllers and the network are network_walk's, which imports this module: typed Any
NetworkWalkController = WalkNetwork = Any

#: a placeholder: NUL never occurs in effector text (names are letters, digits, ``_-.``)
_TOKEN = re.compile("\x00([0-9]+)\x00")


class WalkBatch:
    """The pending passes of the controllers that share ``network`` (see the module doc)."""

    def __init__(self, network: WalkNetwork) -> None:
        self.network = network
        self._pending: list[tuple[NetworkWalkController, np.ndarray, int]] = []
        self._texts: dict[int, str] = {}
        self._next = 0

    def holds(self, controller: NetworkWalkController) -> bool:
        """Whether ``controller`` waits for this batch's pass."""
        return any(c is controller for c, _, _ in self._pending)

    def submit(self, controller: NetworkWalkController, observation: np.ndarray) -> str:
        """Queue ``controller``'s pass on ``observation``; its message's placeholder."""
        if controller.network is not self.network:
            raise LeagueError("walk batch: the controller's network is not the batch's")
        if self.holds(controller):
            self.flush()
        token = self._next
        self._next += 1
        self._pending.append((controller, observation, token))
        return f"\x00{token}\x00"

    def flush(self) -> None:
        """Run the pass of every pending controller (one network call) and keep their
        motor effectors for ``resolve``."""
        if not self._pending:
            return
        pending, self._pending = self._pending, []
        actions = self.network(np.stack([obs for _, obs, _ in pending]))
        for (controller, _, token), action in zip(pending, actions, strict=True):
            self._texts[token] = controller.finish(action.copy())

    def discard(self) -> None:
        """Forget the pending passes and computed messages (a cycle that raised: its
        messages are never sent, its controllers keep their previous actions)."""
        self._pending, self._texts, self._next = [], {}, 0

    def resolve(self, messages: Mapping[int, str]) -> dict[int, str]:
        """``messages`` with every placeholder replaced by its motor effectors (after a
        ``flush``); raises LeagueError if a computed message was not among them."""
        self.flush()
        out = {}
        for key, message in messages.items():
            if "\x00" in message:
                try:
                    message = _TOKEN.sub(lambda m: self._texts.pop(int(m.group(1))), message)
                except KeyError as exc:
                    raise LeagueError(f"walk batch: placeholder {exc.args[0]} of another "
                                      "cycle or batch in a message") from None
            out[key] = message
        if self._texts:
            lost = sorted(self._texts)
            self._texts.clear()
            raise LeagueError(f"walk batch: the messages of placeholders {lost} were computed "
                              "but are in none of the messages resolved")
        self._next = 0
        return out
