"""The league server (``rcssservermj``) as a child process that is always stopped.

The server runs in its own process group (``start_new_session``) so that stopping it reaches
every process it started; it is stopped on leaving the ``with`` block (success, error or
Ctrl-C), at interpreter exit (``atexit``), and — on Linux — when our process dies without
running either (``PR_SET_PDEATHSIG``)."""

from __future__ import annotations

import atexit
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

from teamenv.errors import MissingExtraError

from .errors import LeagueError, ServerDiedError
from .monitor import MonitorConnection

#: how long the server may take to listen (it needs ~1 s idle; a loaded 2-core box is slower)
START_TIMEOUT_S = 60.0
#: SIGINT (the server's own clean shutdown) first, then SIGKILL after this long
STOP_GRACE_S = 3.0


@dataclass(frozen=True)
class ServerOptions:
    """How to run the server: rules book (``ssim``: 7 v 7 on ``fifa7vs7``), optional field
    version, sync mode (the server waits for every agent's answer each cycle) and real time."""

    rules: str = "ssim"
    field: str | None = None
    sync: bool = True
    realtime: bool = False
    host: str = "127.0.0.1"


def server_executable() -> str:
    """The ``rcssservermj`` script next to this interpreter, else on PATH."""
    beside = Path(sys.executable).with_name("rcssservermj")
    if beside.exists():
        return str(beside)
    found = shutil.which("rcssservermj")
    if found is None:
        raise MissingExtraError("humanoid", "rcsssmj", "the league server (rcssservermj)")
    return found


def free_port(host: str = "127.0.0.1") -> int:
    """A TCP port nobody listens on right now (the kernel's choice)."""
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind((host, 0))
        return s.getsockname()[1]


def _die_with_parent() -> None:  # pragma: no cover - runs in the child before exec
    if sys.platform.startswith("linux"):
        import ctypes

        libc = ctypes.CDLL("libc.so.6", use_errno=True)
        libc.prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG


class LeagueServer:
    """A running ``rcssservermj``: ``agent_port``, ``monitor_port``, ``pid``, ``log_path``.

    Use as a context manager; ``stop()`` is idempotent and also runs at interpreter exit."""

    def __init__(self, options: ServerOptions = ServerOptions(), log_dir: str | Path | None = None,
                 start_timeout_s: float = START_TIMEOUT_S) -> None:
        self.options = options
        self.start_timeout_s = start_timeout_s
        self._log_dir = Path(log_dir) if log_dir is not None else None
        self._process: subprocess.Popen[bytes] | None = None
        self.agent_port = 0
        self.monitor_port = 0
        self.log_path: Path | None = None
        self.monitor: MonitorConnection | None = None

    # -- lifecycle ---------------------------------------------------------------------------
    def start(self) -> LeagueServer:
        """Start the server and wait until its agent port accepts connections."""
        if self._process is not None:
            raise LeagueError("league server: already started")
        o = self.options
        self.agent_port, self.monitor_port = free_port(o.host), free_port(o.host)
        while self.monitor_port == self.agent_port:
            self.monitor_port = free_port(o.host)
        cmd = [server_executable(), "--host", o.host, "--aport", str(self.agent_port),
               "--mport", str(self.monitor_port), "--no-render", "--rules", o.rules,
               "--realtime" if o.realtime else "--no-realtime"]
        if o.sync:
            cmd.append("--sync")
        if o.field is not None:
            cmd += ["--field", o.field]
        log_dir = self._log_dir or Path(tempfile.gettempdir())
        log_dir.mkdir(parents=True, exist_ok=True)
        # The server writes console.log and MuJoCo's MUJOCO_LOG.TXT into its working directory:
        # give each server its own, beside its log, instead of the caller's checkout.
        run_dir = Path(tempfile.mkdtemp(prefix=f"rcssservermj-{self.agent_port}-", dir=log_dir))
        self.log_path = run_dir / "server.log"
        with open(self.log_path, "wb") as log:
            self._process = subprocess.Popen(  # noqa: S603 - our own argv, no shell
                cmd, stdin=subprocess.DEVNULL, stdout=log, stderr=subprocess.STDOUT,
                cwd=run_dir, start_new_session=True, preexec_fn=_die_with_parent)
        atexit.register(self.stop)
        try:
            self._wait_listening()
        except BaseException:
            self.stop()
            raise
        return self

    def _wait_listening(self) -> None:
        """Connect the monitor, then wait for its first state message.

        Both listeners are up before the simulation loop starts, so an open monitor port means
        the agent port is open too. Agents must not join before the first simulation step:
        rcsssmj 0.2.1 crashes its simulation thread (audio engine, ``a_forward``) when a player
        is added before the first step."""
        deadline = time.monotonic() + self.start_timeout_s
        while self.monitor is None:
            self.check_alive()
            try:
                self.monitor = MonitorConnection(self.options.host, self.monitor_port)
            except ServerDiedError:
                if time.monotonic() > deadline:
                    raise LeagueError(
                        f"league server: not listening on port {self.monitor_port} after "
                        f"{self.start_timeout_s:.0f} s; log: {self.log_path}") from None
                time.sleep(0.1)
        self.monitor.wait_frames(1, max(1.0, deadline - time.monotonic()))

    @property
    def pid(self) -> int | None:
        return None if self._process is None else self._process.pid

    def is_running(self) -> bool:
        return self._process is not None and self._process.poll() is None

    def log_tail(self, n_bytes: int = 2000) -> str:
        """The end of the server's output (for error messages)."""
        if self.log_path is None or not self.log_path.exists():
            return ""
        data = self.log_path.read_bytes()[-n_bytes:]
        return data.decode("utf-8", "replace")

    def check_alive(self) -> None:
        """Raise ServerDiedError (with the end of its log) if the server has exited."""
        if self._process is None:
            raise ServerDiedError("league server: not started")
        if self.monitor is not None and self.monitor.error is not None:
            # a monitor that stopped reading stalls the server: report why it stopped
            raise ServerDiedError(f"league server: monitor connection failed: {self.monitor.error}")
        code = self._process.poll()
        if code is not None:
            raise ServerDiedError(
                f"league server (pid {self._process.pid}) exited with code {code}; "
                f"last output:\n{self.log_tail()}")

    def stop(self) -> None:
        """Stop the server and everything in its process group; safe to call twice."""
        proc = self._process
        if proc is None:
            return
        atexit.unregister(self.stop)
        if self.monitor is not None:
            self.monitor.close()
            self.monitor = None
        if proc.poll() is None:
            for sig, grace in ((signal.SIGINT, STOP_GRACE_S), (signal.SIGKILL, 10.0)):
                try:
                    os.killpg(proc.pid, sig)
                except ProcessLookupError:
                    break
                try:
                    proc.wait(grace)
                    break
                except subprocess.TimeoutExpired:
                    continue
        # whatever the server started and left in its group goes too
        try:
            os.killpg(proc.pid, signal.SIGKILL)
        except (ProcessLookupError, PermissionError):
            pass
        proc.wait()
        self._process = None

    def __enter__(self) -> LeagueServer:
        return self if self._process is not None else self.start()

    def __exit__(self, *exc: object) -> None:
        self.stop()
