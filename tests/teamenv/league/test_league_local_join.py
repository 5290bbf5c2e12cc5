"""LocalServer joins a whole match's robots with one MuJoCo recompile (join_many), and the world
is the same as when they join one by one."""

import numpy as np
import pytest

pytest.importorskip("rcsssmj", reason="the humanoid extra is installed in CI")

from teamenv.league.errors import LeagueError  # noqa: E402
from teamenv.league.local_server import LocalServer  # noqa: E402

KEYS = [("A", 1), ("A", 2), ("B", 1), ("B", 2)]


def _play(batch: bool):
    server = LocalServer(seed=3)
    first = server.join_many(KEYS) if batch else {k: server.join(*k) for k in KEYS}
    torso = []
    for _ in range(10):
        p = server.cycle({})
        torso.append([p[k].positions["torso_pos"] for k in KEYS])
    return first, np.array(torso), server.sim.mj_data.qpos.copy()


def test_joining_at_once_gives_the_world_of_joining_one_by_one():
    first_a, torso_a, qpos_a = _play(batch=True)
    first_b, torso_b, qpos_b = _play(batch=False)
    assert list(first_a) == KEYS
    for k in KEYS:
        assert first_a[k].positions == first_b[k].positions
    assert np.array_equal(torso_a, torso_b) and np.array_equal(qpos_a, qpos_b)


def test_join_many_refuses_a_player_twice():
    server = LocalServer(seed=0)
    with pytest.raises(LeagueError, match="A 1 has already joined"):
        server.join_many([("A", 1), ("A", 1)])
    server.join("A", 1)
    with pytest.raises(LeagueError, match="A 1 has already joined"):
        server.join_many([("A", 1)])
