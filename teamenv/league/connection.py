"""One TCP connection to the league server: an agent's, or the monitor port's."""

from __future__ import annotations

import socket

from .errors import ProtocolError, ServerDiedError
from .framing import MAX_FRAME_BYTES, encode_frame, read_frame

#: a read that waits longer than this means the server hangs (in sync mode it answers every
#: agent within one step; a 7 v 7 step on a loaded 2-core machine takes well under a second)
READ_TIMEOUT_S = 30.0


class Connection:
    """A framed TCP connection; ``who`` names it in errors (e.g. ``"agent left_3"``)."""

    def __init__(self, host: str, port: int, who: str, timeout_s: float | None = READ_TIMEOUT_S,
                 max_frame_bytes: int = MAX_FRAME_BYTES) -> None:
        self.who = who
        self.max_frame_bytes = max_frame_bytes
        try:
            self._sock = socket.create_connection((host, port), timeout=timeout_s)
        except OSError as exc:
            raise ServerDiedError(f"{who}: cannot connect to {host}:{port}: {exc}") from exc
        self._sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        self._sock.settimeout(timeout_s)
        self.closed = False

    def send(self, text: str) -> None:
        """Send one message (one frame)."""
        try:
            self._sock.sendall(encode_frame(text.encode("ascii")))
        except (BrokenPipeError, ConnectionResetError) as exc:
            raise ServerDiedError(f"{self.who}: the server closed the connection") from exc
        except UnicodeEncodeError as exc:
            raise ProtocolError(f"{self.who}: message is not ASCII: {text[:80]!r}") from exc

    def receive_bytes(self) -> bytes:
        """Read one message's raw payload (blocks up to the timeout)."""
        try:
            return read_frame(self._sock, self.who, self.max_frame_bytes)
        except TimeoutError as exc:
            raise ServerDiedError(f"{self.who}: no message from the server in "
                                  f"{self._sock.gettimeout():.0f} s (hung?)") from exc

    def receive(self) -> str:
        """Read one message (blocks up to the timeout)."""
        try:
            payload = read_frame(self._sock, self.who, self.max_frame_bytes)
        except TimeoutError as exc:
            raise ServerDiedError(f"{self.who}: no message from the server in "
                                  f"{self._sock.gettimeout():.0f} s (hung?)") from exc
        try:
            return payload.decode("ascii")
        except UnicodeDecodeError as exc:
            raise ProtocolError(f"{self.who}: message is not ASCII: {payload[:80]!r}") from exc

    def fileno(self) -> int:
        return self._sock.fileno()

    def close(self) -> None:
        if not self.closed:
            self.closed = True
            try:
                self._sock.shutdown(socket.SHUT_RDWR)
            except OSError:
                pass
            self._sock.close()

    def __enter__(self) -> Connection:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
