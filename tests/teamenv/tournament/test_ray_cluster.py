"""Ray where other Ray clusters run or once ran: with no address teamenv starts a private local
instance; it joins a cluster only when told to, and names an address nobody answers on.

Each test runs in a Ray temp dir of its own (``RAY_TMPDIR``), so the cluster file it makes or
the head it starts is its own and is removed afterwards; the machine's /tmp/ray is left alone.
"""

from __future__ import annotations

import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pytest

from teamenv.match import MatchOptions
from teamenv.tournament import ResultStore, round_robin, run_tournament
from teamenv.tournament.backends import RayBackend, make_backend
from teamenv.tournament.ray_cluster import RayClusterError, init_ray

ray = pytest.importorskip("ray", reason="the ray extra is installed in CI")
pytestmark = pytest.mark.ray

OPTIONS = MatchOptions(team_size=1, half_time_s=5.0, halves=1)
#: CPUs of the foreign head: a private instance has as many as asked (1), a joined head 3
HEAD_CPUS = 3


@pytest.fixture
def ray_tmpdir(monkeypatch):
    """A Ray temp dir of this test's own (short: Ray's socket paths must stay < 108 bytes)."""
    root = tempfile.mkdtemp(prefix="rt", dir="/tmp")
    monkeypatch.setenv("RAY_TMPDIR", root)
    monkeypatch.setenv("RAY_DISABLE_USAGE_STATS", "1")
    yield Path(root)
    shutil.rmtree(root, ignore_errors=True)


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture
def foreign_head(ray_tmpdir):
    """A running ``ray start --head`` that has nothing to do with teamenv, stopped afterwards
    (only the processes it started: its own process group)."""
    ray_cli = Path(sys.executable).with_name("ray")
    port = _free_port()
    proc = subprocess.Popen(
        [str(ray_cli), "start", "--head", f"--port={port}", f"--num-cpus={HEAD_CPUS}",
         "--include-dashboard=false", "--block"],
        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True,
        env=os.environ.copy())
    cluster_file = ray_tmpdir / "ray" / "ray_current_cluster"
    deadline = time.monotonic() + 120
    while not cluster_file.exists() and time.monotonic() < deadline and proc.poll() is None:
        time.sleep(0.5)
    assert cluster_file.exists(), "the foreign Ray head did not start"
    time.sleep(2.0)  # the head writes the file before its raylet is fully up
    yield cluster_file.read_text().strip()
    os.killpg(proc.pid, signal.SIGTERM)
    try:
        # `ray start --block` takes its own ~30 s to shut down gracefully; the test's head
        # holds nothing worth a graceful stop
        proc.wait(timeout=5)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()


@pytest.fixture
def stale_cluster_file(ray_tmpdir):
    """The file a killed cluster leaves behind: an address where nothing answers."""
    path = ray_tmpdir / "ray" / "ray_current_cluster"
    path.parent.mkdir(parents=True)
    path.write_text(f"127.0.0.1:{_free_port()}")
    return path


def _tiny_tournament():
    return round_robin("ray", ["chaser", "static"], games_per_pairing=1, seed=5,
                       options=OPTIONS)


def _workers_seen(backend: RayBackend) -> int:
    """Run no match, only start/join Ray, and report the CPUs the backend saw."""
    list(backend.run([]))
    return backend.workers


def test_no_address_starts_a_private_instance_beside_a_running_head(foreign_head, tmp_path):
    backend = make_backend("ray", jobs=1)
    assert _workers_seen(backend) == 1  # joining the head would have shown its 3 CPUs
    assert not ray.is_initialized()
    run = run_tournament(_tiny_tournament(), tmp_path / "t.sqlite", backend="ray", jobs=1,
                         progress=False)
    assert run.complete
    with ResultStore(tmp_path / "t.sqlite") as store:
        assert len(store.matches(run.tournament_id)) == 2


def test_auto_joins_the_running_head(foreign_head):
    backend = make_backend("ray", ray_address="auto")
    assert _workers_seen(backend) == HEAD_CPUS
    assert not ray.is_initialized()  # the backend disconnects from what it joined


def test_no_address_starts_a_private_instance_despite_a_stale_cluster_file(stale_cluster_file):
    assert _workers_seen(make_backend("ray", jobs=1)) == 1
    assert stale_cluster_file.exists()  # not ours to remove: left as found


def test_auto_with_a_stale_cluster_file_names_the_dead_address(stale_cluster_file):
    dead = stale_cluster_file.read_text()
    started = time.monotonic()
    with pytest.raises(RayClusterError, match=f"'auto -> {dead}'.*nothing answers"):
        init_ray("auto")
    assert time.monotonic() - started < 60  # ray.init alone retries a dead GCS for minutes


def test_unreachable_addresses_are_one_line_errors(ray_tmpdir):
    port = _free_port()
    for address in (f"127.0.0.1:{port}", f"ray://127.0.0.1:{port}"):
        with pytest.raises(RayClusterError, match="nothing answers") as info:
            init_ray(address)
        assert "\n" not in str(info.value) and f"127.0.0.1:{port}" in str(info.value)
    with pytest.raises(RayClusterError, match="num_cpus"):
        init_ray("auto", num_cpus=2)
    assert not ray.is_initialized()


def test_cli_names_the_unreachable_cluster_in_one_line(ray_tmpdir, tmp_path):
    port = _free_port()
    teamenv_cli = Path(sys.executable).with_name("teamenv")
    done = subprocess.run(
        [str(teamenv_cli), "tournament", "run", "chaser", "static", "--games", "1",
         "--team-size", "1", "--half-time", "5", "--backend", "ray",
         "--ray-address", f"127.0.0.1:{port}", "--db", str(tmp_path / "t.sqlite")],
        capture_output=True, text=True, timeout=120)
    assert done.returncode != 0
    assert "Traceback" not in done.stderr
    assert f"127.0.0.1:{port}" in done.stderr and "nothing answers" in done.stderr


def test_a_ray_worker_killed_mid_tournament_loses_and_duplicates_nothing(ray_tmpdir, tmp_path,
                                                                         monkeypatch):
    """A worker dies in its first match (os._exit, as a segfault would): Ray retries the task,
    every match of the schedule is stored exactly once, and the retried match is the same
    match the process pool plays."""
    marker = tmp_path / "crashed"
    monkeypatch.setenv("TEAMENV_TEST_CRASH_MARKER", str(marker))
    crash = "tests.teamenv.tournament_faulty_teams:CrashOnceTeam"
    t = round_robin("crash", [crash, "chaser"], games_per_pairing=2, seed=7, options=OPTIONS)
    on_ray = run_tournament(t, tmp_path / "ray.sqlite", backend="ray", jobs=1, progress=False)
    assert marker.exists()                       # a worker did die
    assert on_ray.complete and on_ray.stored == 4
    with ResultStore(tmp_path / "ray.sqlite") as store:
        rows = store.matches(on_ray.tournament_id)
    rows = sorted(rows, key=lambda r: r.idx)
    assert [r.idx for r in rows] == [0, 1, 2, 3]             # each once
    pool = run_tournament(t, tmp_path / "pool.sqlite", jobs=1, progress=False)  # marker set
    with ResultStore(tmp_path / "pool.sqlite") as store:
        want = [r.comparable() for r in sorted(store.matches(pool.tournament_id),
                                               key=lambda r: r.idx)]
    assert [r.comparable() for r in rows] == want
