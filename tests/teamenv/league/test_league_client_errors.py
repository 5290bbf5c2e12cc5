"""A team client names a dead server's exit even when its socket is reset before the process
can be reaped (a race seen in CI: the client said "connection reset" instead of the exit)."""

from __future__ import annotations

import socket
import struct
import threading

import pytest

from teamenv.league.connection import Connection
from teamenv.league.errors import ServerDiedError
from teamenv.league.team_client import TeamClient


def _resetting_server() -> tuple[socket.socket, threading.Thread]:
    """A listener whose first connection is reset (RST, as a killed process's socket is)."""
    listener = socket.create_server(("127.0.0.1", 0))

    def serve() -> None:
        conn, _ = listener.accept()
        conn.recv(64)  # wait for the client's first message, then die
        conn.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 0))
        conn.close()

    thread = threading.Thread(target=serve, daemon=True)
    thread.start()
    return listener, thread


class _LateReapedServer:
    """check_alive of a process that is seen exiting only after a few polls."""

    def __init__(self, polls_alive: int) -> None:
        self.polls = 0
        self.polls_alive = polls_alive

    def __call__(self) -> None:
        self.polls += 1
        if self.polls > self.polls_alive:
            raise ServerDiedError("league server (pid 1) exited with code -9; last output:")


def _client_on(listener: socket.socket, check_alive) -> TeamClient:
    client = TeamClient("127.0.0.1", listener.getsockname()[1], "Alpha", (1,),
                        check_alive=check_alive, timeout_s=5)
    client._conns[1] = Connection("127.0.0.1", listener.getsockname()[1], client.who(1), 5)
    return client


def test_a_reset_connection_waits_for_the_exit_to_be_seen():
    listener, thread = _resetting_server()
    check_alive = _LateReapedServer(polls_alive=3)
    with listener, _client_on(listener, check_alive) as client:
        client.act()
        thread.join(5)
        with pytest.raises(ServerDiedError, match="exited with code -9"):
            client.perceive()
    assert check_alive.polls == 4


def test_a_live_server_that_closed_the_connection_keeps_the_connection_error():
    listener, thread = _resetting_server()
    check_alive = _LateReapedServer(polls_alive=10**9)
    with listener, _client_on(listener, check_alive) as client:
        client.act()
        thread.join(5)
        with pytest.raises(ServerDiedError, match="agent Alpha_1: connection reset|closed the"):
            client.perceive()
    assert check_alive.polls > 1  # it waited for an exit before giving the connection's error
