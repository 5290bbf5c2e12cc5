"""The monitor port: commands to the referee (kick-off, play mode) and a drained state stream.

The server writes a state message to every monitor each 2nd step from its simulation thread,
so a monitor that stops reading stalls the whole server; a daemon thread reads (and counts)
every frame for as long as the connection is open."""

from __future__ import annotations

import threading

from .connection import Connection
from .errors import LeagueError, ProtocolError, ServerDiedError
from .framing import MAX_MONITOR_FRAME_BYTES

#: the kick-off sides the server's ``kickOff`` command understands
KICK_OFF_SIDES = ("Left", "Right")


class MonitorConnection:
    """A monitor client: ``kick_off(side)``, ``set_play_mode(mode)``; ``frames`` counts the
    state messages received (the first means the simulation has stepped)."""

    def __init__(self, host: str, port: int) -> None:
        # no read timeout: the server sends nothing while it waits for slow agents
        self._conn = Connection(host, port, "monitor", timeout_s=None,
                                max_frame_bytes=MAX_MONITOR_FRAME_BYTES)
        self._cond = threading.Condition()
        self.frames = 0
        self.error: Exception | None = None
        self._reader = threading.Thread(target=self._drain, name="league-monitor", daemon=True)
        self._reader.start()

    def _drain(self) -> None:
        while True:
            try:
                self._conn.receive_bytes()
            except (ServerDiedError, ProtocolError, OSError) as exc:
                with self._cond:
                    if not self._conn.closed:
                        self.error = exc
                    self._cond.notify_all()
                return
            with self._cond:
                self.frames += 1
                self._cond.notify_all()

    def wait_frames(self, n: int, timeout_s: float) -> None:
        """Block until ``n`` state messages have arrived (the server is stepping)."""
        with self._cond:
            ok = self._cond.wait_for(lambda: self.frames >= n or self.error is not None,
                                     timeout_s)
        if self.error is not None:
            raise ServerDiedError(f"monitor: {self.error}")
        if not ok:
            raise LeagueError(f"monitor: {self.frames} of {n} state messages in {timeout_s:.0f} s")

    def send(self, command: str) -> None:
        self._conn.send(command)

    def kick_off(self, side: str = "Left") -> None:
        """Start the match (``(kickOff Left|Right)``): the referee leaves BeforeKickOff."""
        if side not in KICK_OFF_SIDES:
            raise LeagueError(f"monitor: kick-off side must be one of {KICK_OFF_SIDES}, not {side!r}")
        self.send(f"(kickOff {side})")

    def set_play_mode(self, mode: str) -> None:
        """Force a play mode by its league name (e.g. ``PlayOn``)."""
        self.send(f"(playMode {mode})")

    def close(self) -> None:
        self._conn.close()
        self._reader.join(timeout=5)
