"""The Ray backend on a local Ray instance gives the same results as the process pool and as
the serial (in-process) backend."""

from __future__ import annotations

import sys

import pytest

from teamenv.errors import MissingExtraError
from teamenv.match import MatchOptions
from teamenv.tournament import ResultStore, round_robin, run_tournament
from teamenv.tournament.backends import make_backend

OPTIONS = MatchOptions(team_size=2, half_time_s=25.0, halves=1)


def test_missing_ray_names_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "ray", None)  # makes `import ray` fail
    with pytest.raises(MissingExtraError, match=r"pip install -e '\.\[ray\]'"):
        make_backend("ray")


@pytest.mark.ray
def test_ray_backend_equals_process_pool(tmp_path):
    ray = pytest.importorskip("ray", reason="the ray extra is installed in CI")
    t = round_robin("ray", ["chaser", "static"], games_per_pairing=2, seed=3, options=OPTIONS)
    pool = run_tournament(t, tmp_path / "pool.sqlite", jobs=2, progress=False)
    # the backend starts a private local instance: ray.init(address="local", num_cpus=2)
    on_ray = run_tournament(t, tmp_path / "ray.sqlite", backend="ray", jobs=2, progress=False)
    assert not ray.is_initialized()  # and shuts down what it started
    serial = run_tournament(t, tmp_path / "serial.sqlite", backend="serial", progress=False)
    assert pool.complete and on_ray.complete and on_ray.backend == "ray" and serial.complete
    with ResultStore(tmp_path / "pool.sqlite") as a, ResultStore(tmp_path / "ray.sqlite") as b, \
            ResultStore(tmp_path / "serial.sqlite") as c:
        got = [r.comparable() for r in b.matches(on_ray.tournament_id)]
        want = [r.comparable() for r in a.matches(pool.tournament_id)]
        in_process = [r.comparable() for r in c.matches(serial.tournament_id)]
    assert len(got) == 4 and got == want == in_process
    assert sum(len(r["goals"]) for r in got) >= 1  # seed 3 has a goal: events compared too


def test_local_ray_workers_are_not_niced(monkeypatch):
    # Ray nices its workers to 15 by default: on a busy machine the matches then ran several
    # times slower than in a plain process. A local instance the backend starts uses 0.
    ray = pytest.importorskip("ray", reason="the ray extra is installed in CI")
    seen = {}

    class StopHere(Exception):
        pass

    def fake_init(**kwargs):
        seen.update(kwargs)
        raise StopHere("stop here")

    monkeypatch.setattr(ray, "is_initialized", lambda: False)
    monkeypatch.setattr(ray, "init", fake_init)
    monkeypatch.setattr("teamenv.tournament.ray_cluster._check_reachable", lambda a: None)
    with pytest.raises(StopHere):
        list(make_backend("ray", jobs=2).run([]))
    assert seen["num_cpus"] == 2 and seen["_system_config"] == {"worker_niceness": 0}
    assert seen["address"] == "local"  # a private instance, never someone else's cluster
    seen.clear()
    with pytest.raises(StopHere):
        list(make_backend("ray", ray_address="auto").run([]))
    assert seen["address"] == "auto" and "_system_config" not in seen
    assert "num_cpus" not in seen  # a cluster's resources are its own
