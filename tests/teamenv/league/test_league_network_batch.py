"""One walking-network pass per team and cycle (``WalkBatch``) gives every robot the bits of
its own pass, and a match replays the same with batches and without."""

from __future__ import annotations

import numpy as np
import pytest

from teamenv.league.errors import LeagueError
from teamenv.league.network_batch import WalkBatch
from teamenv.league.network_walk import NetworkWalkController, WalkNetwork, shipped_network
from teamenv.league.perception import JointState, Perception
from teamenv.league.t1 import T1_MOTORS, joint_sensor


def test_a_batched_pass_is_each_rows_own_pass_bit_for_bit() -> None:
    net = shipped_network()
    rng = np.random.default_rng(2)
    for n in range(1, 15):                               # every team size, both teams
        for _ in range(10):
            x = np.clip(rng.standard_normal((n, 78)) * 10.0 ** rng.integers(-3, 2, (n, 78)),
                        -10, 10)
            x[0, :5] = [0.0, -0.0, 1e-300, -1e-300, 10.0]
            rows = net(x)
            for i in range(n):
                assert net(x[i]).tobytes() == rows[i].tobytes(), (n, i)


def _perception(rng) -> Perception:
    return Perception(
        joints={joint_sensor(m): JointState(*rng.normal(0, 0.3, 2)) for m in T1_MOTORS},
        gyros={"torso_gyro": tuple(rng.normal(0, 0.5, 3))},
        orientations={"torso_quat": (1.0, *rng.normal(0, 0.05, 3))})


def test_controllers_in_a_batch_send_what_they_send_alone() -> None:
    """Several cycles of 7 robots, standing and walking, one asked twice in a cycle and one
    reset while it waits: the batch's messages are the one-by-one messages."""
    rng = np.random.default_rng(5)
    batch = WalkBatch(shipped_network())
    alone = [NetworkWalkController() for _ in range(7)]
    batched = [NetworkWalkController(batch=batch) for _ in range(7)]
    assert all(c.network is batch.network for c in alone)          # one shared network
    for cycle in range(6):
        ps = [_perception(rng) for _ in range(7)]
        commands = [tuple(rng.normal(0, 0.5, 3)) for _ in range(7)]
        expected, tokens = {}, {}
        for k, (a, b) in enumerate(zip(alone, batched, strict=True)):
            if k == 3:                                       # asked twice: stand, then walk
                expected[k] = a.stand(ps[k]) + a.step(commands[k], ps[k])
                tokens[k] = b.stand(ps[k]) + b.step(commands[k], ps[k])
            elif k == 5 and cycle % 2:                       # reset after its request
                expected[k] = a.step(commands[k], ps[k])
                a.reset()
                tokens[k] = b.step(commands[k], ps[k])
                b.reset()
            else:
                expected[k] = a.step(commands[k], ps[k]) if k % 2 else a.stand(ps[k])
                tokens[k] = b.step(commands[k], ps[k]) if k % 2 else b.stand(ps[k])
        assert all("\x00" in t for t in tokens.values())
        assert batch.resolve(tokens) == expected, cycle


def test_a_batch_names_what_goes_wrong() -> None:
    batch = WalkBatch(shipped_network())
    stranger = NetworkWalkController(network=WalkNetwork.load())
    with pytest.raises(LeagueError, match="network is not the batch's"):
        batch.submit(stranger, np.zeros(78))
    rng = np.random.default_rng(0)
    c = NetworkWalkController(batch=batch)
    token = c.stand(_perception(rng))
    with pytest.raises(LeagueError, match=r"placeholders \[0\] were computed but are in none"):
        batch.resolve({1: "(syn)"})
    with pytest.raises(LeagueError, match="placeholder 0 of another cycle"):
        batch.resolve({1: token})
    with pytest.raises(ValueError, match="read-only"):
        shipped_network().w1[0, 0] = 0.0


@pytest.mark.humanoid
def test_a_match_replays_the_same_with_batched_walks_and_without(tmp_path, monkeypatch) -> None:
    pytest.importorskip("rcsssmj")
    from teamenv.league import match
    from teamenv.replay import load_replay

    options = match.LeagueMatchOptions(team_size=2, game_s=1.5, server="local")
    calls = []
    original = match.LeagueSide.batch_walks

    def counted(self):
        original(self)
        calls.append(len(self.walk_batches))

    monkeypatch.setattr(match.LeagueSide, "batch_walks", counted)
    batched = match.play_league_match("full", "chaser", options, seed=4,
                                      replay_path=tmp_path / "batched.npz")
    assert calls == [1, 1]                             # one batch per side
    monkeypatch.setattr(match.LeagueSide, "batch_walks", lambda self: None)
    alone = match.play_league_match("full", "chaser", options, seed=4,
                                    replay_path=tmp_path / "alone.npz")
    assert batched.score == alone.score
    a, b = load_replay(tmp_path / "batched.npz"), load_replay(tmp_path / "alone.npz")
    for name in ("ball", "players", "fallen", "play_mode", "touch_cycle", "kick_cycle"):
        assert getattr(a, name).tobytes() == getattr(b, name).tobytes(), name
    assert np.ptp(a.players[:, :, 0]) > 0


def test_a_cycle_that_raises_leaves_no_pass_pending() -> None:
    from teamenv.league.match import LeagueSide

    rng = np.random.default_rng(3)
    batch = WalkBatch(shipped_network())
    c = NetworkWalkController(batch=batch)
    c.stand(_perception(rng))
    batch.discard()
    assert not batch.holds(c) and batch.resolve({1: "(syn)"}) == {1: "(syn)"}

    class Broken(LeagueSide):
        def _act(self, perceptions, on_act):
            c.stand(_perception(rng))
            raise RuntimeError("a team's bug")

    side = Broken.__new__(Broken)
    side.walk_batches = [batch]
    with pytest.raises(RuntimeError, match="a team's bug"):
        side.act({}, None)
    assert not batch.holds(c) and batch.resolve({}) == {}
