"""League client against the real server (rcsssmj 0.2.1, CPU): join, beam, say/hear, motors,
kick-off through the monitor, every perceptor parsed, and clean shutdown after success,
server death and Ctrl-C; bad server output through a fake server."""

from __future__ import annotations

import math
import os
import signal
import socket
import subprocess
import sys
import textwrap
import threading
import time
from pathlib import Path

import pytest

from teamenv.league import effectors
from teamenv.league.errors import ProtocolError, ServerDiedError, UnknownPerceptorError
from teamenv.league.framing import encode_frame, read_frame
from teamenv.league.server import LeagueServer
from teamenv.league.t1 import T1_MOTORS, joint_sensor
from teamenv.league.team_client import TeamClient, join_teams

pytestmark = pytest.mark.humanoid
pytest.importorskip("rcsssmj", reason="needs the humanoid extra: pip install -e '.[humanoid]'")

HOST = "127.0.0.1"
DATA = Path(__file__).resolve().parents[1] / "league_data"


def _gone(pid: int) -> bool:
    """True when ``pid`` no longer runs: absent, or a zombie nobody reaped yet with no thread
    left (a zombie leader whose other threads still run is a live process)."""
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
        threads = len(os.listdir(f"/proc/{pid}/task"))
    except (FileNotFoundError, ProcessLookupError):
        return True
    return state in ("Z", "X") and threads <= 1


def _port_closed(port: int) -> bool:
    try:
        with socket.create_connection((HOST, port), timeout=1):
            return False
    except OSError:
        return True


def _wait_gone(pid: int, *ports: int, timeout_s: float = 30.0) -> bool:
    """Wait (polling) until ``pid`` is gone and nothing listens on ``ports``."""
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        if _gone(pid) and all(_port_closed(p) for p in ports):
            return True
        time.sleep(0.2)
    return False


def test_protocol_with_the_real_server():
    with LeagueServer() as server:
        pid, aport, mport = server.pid, server.agent_port, server.monitor_port
        alpha = TeamClient(HOST, aport, "Alpha", (1, 2), check_alive=server.check_alive)
        beta = TeamClient(HOST, aport, "Beta", (1,), check_alive=server.check_alive)
        with alpha, beta:
            join_teams([alpha, beta])
            kinds: set[str] = set()
            vision_cycles, modes, heard, hj1 = [], [], {}, []
            for cycle in range(40):
                pa, pb = alpha.perceive(), beta.perceive()
                for p in (*pa.values(), *pb.values()):
                    assert p.unknown == []                      # strict: every kind known
                    kinds |= {k for k, v in (("time", p.time), ("GS", p.game),
                                             ("pos", p.positions), ("quat", p.orientations),
                                             ("GYR", p.gyros), ("ACC", p.accelerometers),
                                             ("HJ", p.joints), ("See", p.vision),
                                             ("MIC", p.heard)) if v}
                vision_cycles.append(pa[1].vision is not None)
                modes.append(pa[1].game.play_mode)
                for key, p in (("Alpha_1", pa[1]), ("Alpha_2", pa[2]), ("Beta_1", pb[1])):
                    for h in p.heard or ():
                        heard.setdefault(key, []).append(h.payload)
                hj1.append(pa[2].joints[joint_sensor("he1")].angle)
                if cycle == 10:
                    pos_a1 = pa[1].positions["torso_pos"]
                    pos_b1 = pb[1].positions["torso_pos"]
                acts_a, acts_b = {}, {}
                if cycle == 0:
                    acts_a = {1: effectors.beam(-3.0, 1.0, 0.0), 2: effectors.beam(-6.0, -2.0, 0.0)}
                    acts_b = {1: effectors.beam(-4.0, 0.5, 0.0)}
                if cycle == 12:
                    acts_a = {1: effectors.say(b"teamenv!")}
                if cycle >= 12:   # turn Alpha 2's head (joint hj1) to 0.5 rad under PD
                    # every robot commands every motor: rcsssmj 0.2.1 leaves garbage (~-5e303)
                    # in some velocity actuators' ctrl when a player joins, and MuJoCo then
                    # zeroes every control of the world each step until it is overwritten
                    limp = [effectors.motor(m, 0.0) for m in T1_MOTORS if m != "he1"]
                    head = effectors.motor("he1", 0.5, 0.0, 30.0, 1.0)
                    acts_a = {1: effectors.message(acts_a.get(1, ""), head, *limp),
                              2: effectors.message(head, *limp)}
                    acts_b = {1: effectors.message(head, *limp)}
                alpha.act(acts_a)
                beta.act(acts_b)
                if cycle == 20:
                    server.monitor.kick_off("Left")
        assert kinds == {"time", "GS", "pos", "quat", "GYR", "ACC", "HJ", "See", "MIC"}
        # beams: the left team where asked, the right team mirrored into its own half
        assert math.hypot(pos_a1[0] + 3.0, pos_a1[1] - 1.0) < 0.15
        assert pos_b1[0] > 3.5 and abs(pos_b1[1] - 0.5) < 0.6
        # vision every 2nd cycle
        assert all(a != b for a, b in zip(vision_cycles, vision_cycles[1:], strict=False))
        # say: teammate and opponent hear it, the speaker does not hear itself
        assert heard.get("Alpha_2") == [b"teamenv!"] and heard.get("Beta_1") == [b"teamenv!"]
        assert "Alpha_1" not in heard
        # motors: the head turned towards its target
        assert abs(hj1[11]) < 0.05 and abs(hj1[-1] - 0.5) < 0.1
        # kick-off through the monitor port changes the play mode
        assert modes[0] == "BeforeKickOff" and modes[20] == "BeforeKickOff"
        assert modes[-1] in ("KickOff_Left", "PlayOn")
    assert _wait_gone(pid, aport, mport)


def test_server_death_gives_a_clear_error_and_no_process():
    with LeagueServer() as server:
        pid = server.pid
        with TeamClient(HOST, server.agent_port, "Alpha", (1,), check_alive=server.check_alive,
                        timeout_s=20) as team:
            team.join()
            team.act()
            team.perceive()
            os.kill(pid, signal.SIGKILL)
            with pytest.raises(ServerDiedError, match=r"exited with code -9|closed the connection"):
                for _ in range(50):
                    team.act()
                    team.perceive()
    assert _wait_gone(pid)


# A process started in the background by a non-interactive shell (as CI may start pytest)
# inherits SIGINT ignored, and Python then installs no KeyboardInterrupt handler: the child
# restores it, as a terminal's Ctrl-C would find it.
_CHILD = textwrap.dedent("""
    import signal, sys, time
    signal.signal(signal.SIGINT, signal.default_int_handler)
    from teamenv.league.server import LeagueServer
    with LeagueServer() as server:
        print(server.pid, server.agent_port, flush=True)
        time.sleep(120)
""")


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGKILL], ids=["ctrl-c", "kill -9"])
def test_no_server_left_after_ctrl_c_or_kill_of_our_process(sig):
    child = subprocess.Popen([sys.executable, "-c", _CHILD], stdout=subprocess.PIPE, text=True)
    try:
        pid, port = map(int, child.stdout.readline().split())
        assert not _gone(pid)
        child.send_signal(sig)
        child.wait(60)  # stop() may take ~20 s: 5 s monitor join, 3 s SIGINT grace, 10 s SIGKILL
        assert _wait_gone(pid, port), f"server {pid} still runs after {sig.name} to its parent"
    finally:
        if child.poll() is None:
            child.kill()
            child.wait()


# -- bad server output, through a fake server ---------------------------------------------
def _fake_server(frames: list[bytes]) -> tuple[int, threading.Thread]:
    """A one-connection TCP server: reads the init, sends ``frames`` raw, closes."""
    listener = socket.create_server((HOST, 0))
    port = listener.getsockname()[1]

    def serve() -> None:
        conn, _ = listener.accept()
        with conn, listener:
            assert read_frame(conn).startswith(b"(init T1 Alpha 1)")
            for f in frames:
                conn.sendall(f)

    thread = threading.Thread(target=serve, daemon=True)
    thread.start()
    return port, thread


GOOD = (DATA / "first.txt").read_text().strip().encode()


@pytest.mark.parametrize("frames, error, needle", [
    ([encode_frame(GOOD + b"(XYZ (n a) (v 1))")], UnknownPerceptorError,
     "agent Alpha_1: unknown perceptor 'XYZ'"),
    ([encode_frame(GOOD)[:100]], ProtocolError, "agent Alpha_1: truncated frame"),
    ([encode_frame(b"(time (now 1)(GS")], ProtocolError, "agent Alpha_1: unclosed"),
    ([], ServerDiedError, "agent Alpha_1: the server closed the connection"),
], ids=["unknown-perceptor", "truncated-frame", "bad-sexp", "server-gone"])
def test_bad_server_output_gives_a_clear_error_and_closes(frames, error, needle):
    port, thread = _fake_server(frames)
    team = TeamClient(HOST, port, "Alpha", (1,), timeout_s=20)
    with pytest.raises(error, match=needle), team:
        team.join()
    assert all(c.closed for c in team._conns.values()) and not team._conns
    thread.join(10)
