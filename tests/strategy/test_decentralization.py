"""Decentralization: each agent decides from its own observation and what it heard, nothing else.

Agent level: 11 ``PositioningAgent`` objects, each fed only its own noisy world view and the
texts the league's simspark channel (``comms``) delivered to it. Perturbing one agent's view
changes nobody else's decision in that cycle; afterwards, every other agent's decisions are
reproduced exactly by a fresh agent given only its own views and the texts it heard. Env
level: the same through ``teamenv.parallel_env`` observations.
"""

from __future__ import annotations

import numpy as np
import pytest

import comms
import teamenv
from strategy.positioning import PositioningAgent, WorldView, world_view
from strategy.positioning.formation import builtin_formation

N = 11
FORMATION = builtin_formation("11v11-defend")


def make_views(cycles: int, seed: int = 0) -> list[list[WorldView]]:
    """Per cycle, every agent's own noisy belief of one slowly moving true scene."""
    rng = np.random.default_rng(seed)
    ball = np.array([2.0, -1.0])
    players = FORMATION.home_positions(ball)[rng.permutation(N)] * 0.5
    players[0] = [-14.0, 0.0]
    opponents = rng.uniform([-15, -10], [15, 10], (N, 2))
    out = []
    for _ in range(cycles):
        ball = np.clip(ball + rng.normal(0, 0.15, 2), [-14, -9], [14, 9])
        players = players + rng.normal(0, 0.05, (N, 2))
        out.append([
            world_view(players + rng.normal(0, 0.4, (N, 2)), ball + rng.normal(0, 0.3, 2),
                       opponents + rng.normal(0, 0.4, (N, 2)))
            for _ in range(N)
        ])
    return out


def run(views, mute: int | None = None, seed: int = 1):
    """Run the team; the channel delivers this cycle's says next cycle. Returns per cycle
    the decisions and the texts each agent heard."""
    agents = [PositioningAgent(i, FORMATION, "simspark") for i in range(N)]
    channel = comms.make_channel("simspark", N, np.zeros(N, dtype=int))
    channel.reset()
    rng = np.random.default_rng(seed)
    heard: list[list[str]] = [[] for _ in range(N)]
    decisions, heard_log = [], []
    for cycle_views in views:
        ds = [a.step(v, heard[i]) for i, (a, v) in enumerate(zip(agents, cycle_views,
                                                                  strict=True))]
        decisions.append(ds)
        heard_log.append([list(h) for h in heard])
        says = [comms.Utterance(i, d.say) for i, d in enumerate(ds) if d.say and i != mute]
        positions = np.array([v.players[i] for i, v in enumerate(cycle_views)])
        delivery = channel.deliver(says, positions, np.zeros(N), rng)
        heard = [[h.text for h in delivery.heard[i]] for i in range(N)]
    return decisions, heard_log


def same(a, b) -> bool:
    return (a.say == b.say and np.array_equal(a.target, b.target)
            and np.array_equal(a.team_vector, b.team_vector)
            and np.array_equal(a.own_vector, b.own_vector))


def perturbed(views, k: int, t0: int, seed: int = 9):
    rng = np.random.default_rng(seed)
    out = [list(c) for c in views]
    for t in range(t0, len(views)):
        v = out[t][k]
        out[t][k] = world_view(rng.uniform([-15, -10], [15, 10], (N, 2)), -v.ball, v.opponents)
    return out


@pytest.fixture(scope="module")
def views():
    return make_views(90)


def test_team_agrees_on_one_assignment(views):
    decisions, _ = run(views)
    final = [d.team_vector.tolist() for d in decisions[-1]]
    assert all(v == final[0] for v in final)
    assert sorted(final[0]) == list(range(N))
    # while their own world models (and so their own vectors) still disagree
    owns = {tuple(d.own_vector.tolist()) for c in decisions[-20:] for d in c}
    assert len(owns) > 1


def test_perturbing_one_agent_changes_only_what_it_can_reach_through_messages(views):
    k, t0 = 4, 40
    base, _ = run(views)
    pert_views = perturbed(views, k, t0)
    pert, heard = run(pert_views)
    for t in range(t0):
        assert all(same(a, b) for a, b in zip(base[t], pert[t], strict=True))
    # the cycle of the perturbation: only agent k can differ (nobody reads its state)
    assert not same(base[t0][k], pert[t0][k])
    assert all(same(base[t0][j], pert[t0][j]) for j in range(N) if j != k)
    # later the others do react, through agent k's role votes
    assert any(not same(base[t][j], pert[t][j])
               for t in range(t0 + 1, len(views)) for j in range(N) if j != k)
    # afterwards every other agent is a function of its own views and what it heard only:
    # a fresh agent given exactly those reproduces its decisions
    for j in range(N):
        if j == k:
            continue
        fresh = PositioningAgent(j, FORMATION, "simspark")
        for t in range(len(views)):
            d = fresh.step(pert_views[t][j], heard[t][j])
            assert same(d, pert[t][j]), (j, t)


def test_a_silent_agent_cannot_influence_anyone(views):
    k, t0 = 7, 30
    quiet, _ = run(views, mute=k)
    quiet_pert, _ = run(perturbed(views, k, t0), mute=k)
    for t in range(len(views)):
        for j in range(N):
            if j != k:
                assert same(quiet[t][j], quiet_pert[t][j]), (j, t)


def test_env_level_agents_decide_from_their_own_observation():
    """Through ``teamenv.parallel_env``: perturbing left_5's observation at one cycle changes no
    other agent's action in that cycle; the team's messages are legal and it converges."""

    def play(perturb_at: int | None, cycles: int = 60):
        env = teamenv.parallel_env(field="simspark", team_size=N)
        obs, _ = env.reset(seed=3)
        agents = {f"left_{i + 1}": PositioningAgent(i, FORMATION, "simspark") for i in range(N)}
        log = []
        for t in range(cycles):
            actions, decided = {}, {}
            for name in env.agents:
                if name not in agents:
                    actions[name] = {}
                    continue
                o = obs[name]
                if t == perturb_at and name == "left_5":
                    o = dict(o)
                    mates = np.array(o["teammates"], copy=True)
                    mates[:, :2] = mates[::-1, :2]
                    o["teammates"] = mates
                    o["ball"] = -np.asarray(o["ball"])
                d = agents[name].step_observation(o)
                decided[name] = d
                walk = np.zeros(3, dtype=np.float32)
                actions[name] = {"walk": walk, "say": d.say}
            log.append(decided)
            obs, *_ = env.step(actions)
        env.close()
        # every agent heard role votes from teammates, not only its own
        assert all(len(a.voter.fresh_speakers(a.cycle - 1)) > 0 for a in agents.values())
        return log

    base = play(None)
    pert = play(25)
    for t in range(25):
        assert all(same(base[t][a], pert[t][a]) for a in base[t])
    assert not same(base[25]["left_5"], pert[25]["left_5"])
    assert all(same(base[25][a], pert[25][a]) for a in base[25] if a != "left_5")
    final = [d.team_vector.tolist() for d in base[-1].values()]
    assert all(v == final[0] for v in final)
