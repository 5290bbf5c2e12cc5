"""Length-prefixed framing of the league's TCP protocol: 4-byte big-endian length, then payload."""

from __future__ import annotations

import socket
import struct

from .errors import ProtocolError, ServerDiedError

PREFIX = struct.Struct(">I")
#: the largest agent frame accepted from the server (a perception is ~2 kB; a length above
#: this means the stream is out of step, not a big message)
MAX_FRAME_BYTES = 1 << 20
#: the monitor's full scene-graph messages after a player joins are several MB
MAX_MONITOR_FRAME_BYTES = 1 << 28


def encode_frame(payload: bytes) -> bytes:
    """``payload`` with its 4-byte big-endian length in front."""
    if len(payload) > MAX_FRAME_BYTES:
        raise ProtocolError(f"frame of {len(payload)} bytes exceeds {MAX_FRAME_BYTES}")
    return PREFIX.pack(len(payload)) + payload


def _recv_exact(sock: socket.socket, n: int, who: str, what: str) -> bytes:
    buf = bytearray(n)
    view = memoryview(buf)
    got = 0
    while got < n:
        try:
            k = sock.recv_into(view[got:], n - got)
        except (ConnectionResetError, BrokenPipeError) as exc:
            raise ServerDiedError(f"{who}: connection reset while reading the {what}") from exc
        if k == 0:
            if got == 0 and what == "length prefix":
                raise ServerDiedError(f"{who}: the server closed the connection")
            raise ProtocolError(
                f"{who}: truncated frame: the {what} ended after {got} of {n} bytes "
                "(the server closed the connection mid-frame)")
        got += k
    return bytes(buf)


def read_frame(sock: socket.socket, who: str = "agent",
               max_bytes: int = MAX_FRAME_BYTES) -> bytes:
    """Read one frame's payload; ``who`` names the reader in errors.

    Raises ServerDiedError when the connection closes between frames, ProtocolError when it
    closes inside a frame or the length is absurd."""
    (length,) = PREFIX.unpack(_recv_exact(sock, PREFIX.size, who, "length prefix"))
    if length > max_bytes:
        raise ProtocolError(f"{who}: frame length {length} exceeds {max_bytes} bytes")
    return _recv_exact(sock, length, who, "payload")


def split_frames(data: bytes) -> tuple[list[bytes], bytes]:
    """Split a byte buffer into whole frames' payloads and the incomplete rest."""
    frames: list[bytes] = []
    pos = 0
    while len(data) - pos >= PREFIX.size:
        (length,) = PREFIX.unpack_from(data, pos)
        if length > MAX_FRAME_BYTES:
            raise ProtocolError(f"frame length {length} exceeds {MAX_FRAME_BYTES} bytes")
        if len(data) - pos - PREFIX.size < length:
            break
        frames.append(data[pos + PREFIX.size:pos + PREFIX.size + length])
        pos += PREFIX.size + length
    return frames, data[pos:]
