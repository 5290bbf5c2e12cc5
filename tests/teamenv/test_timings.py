"""The per-phase wall-clock accounting: env.timings() / Simulation.phase_s.

No assertion compares a duration with a speed threshold: the checks are about which keys
exist, that the phases add up to the total, that work lands in the right phase, that turning
it off gives zeros, and that it never changes a trajectory."""

import hashlib
import pickle

import numpy as np
import pytest

import teamenv
from teamenv.env import TIMING_PHASES
from teamenv.errors import ActionError
from teamenv.sim.simulation import SIM_PHASES

SLOW = "tests.teamenv.faulty_teams:SlowTeam"  # sleeps 50 ms in every act()


def _named_sum(t: dict) -> float:
    return sum(v for k, v in t.items() if k not in ("other", "total"))


def test_keys_and_sum_with_teams():
    env = teamenv.parallel_env(team_size=3, left="chaser", right="static")
    assert set(env.timings()) == set(TIMING_PHASES) | {"total"}
    assert all(v == 0.0 for v in env.timings().values())
    env.reset(seed=1)
    for _ in range(120):
        env.step({})
    t = env.timings()
    assert list(t) == [*TIMING_PHASES, "total"]
    assert all(v >= 0.0 for v in t.values())
    # Every phase is measured inside reset()/step(): the named phases never exceed the total,
    # and "other" is exactly the rest.
    assert _named_sum(t) <= t["total"] * (1 + 1e-12)
    assert sum(v for k, v in t.items() if k != "total") == pytest.approx(t["total"], rel=1e-9)
    for phase in ("actions", "team_left", "team_right", "locomotion", "physics", "referee",
                  "comms", "perception"):
        assert t[phase] > 0.0, phase
    # Team time includes act() (team_time_s) plus reset().
    assert t["team_left"] >= env.team_time_s["left"] > 0.0
    assert t["team_right"] >= env.team_time_s["right"] > 0.0


def test_caller_side_has_no_team_time():
    env = teamenv.parallel_env(team_size=2, right="static")
    env.reset(seed=0)
    for _ in range(20):
        env.step({a: {"walk": np.zeros(3)} for a in env.agents})
    t = env.timings()
    assert t["team_left"] == 0.0
    assert t["team_right"] > 0.0


def test_work_lands_in_its_phase():
    """A team that sleeps 50 ms per act() puts at least that much into its own phase and
    none of it anywhere else."""
    env = teamenv.parallel_env(team_size=2, left=SLOW, right="static")
    env.reset(seed=0)
    steps = 3
    for _ in range(steps):
        env.step({})
    t = env.timings()
    assert t["team_left"] >= 0.05 * steps
    assert t["total"] >= t["team_left"]
    assert t["total"] - t["team_left"] < 0.05  # the sleep was not counted twice or elsewhere
    assert t["team_right"] < 0.05


def test_disabled_gives_zeros_and_keeps_team_time():
    env = teamenv.parallel_env(team_size=2, left="chaser", right="static", profile_phases=False)
    env.reset(seed=0)
    for _ in range(30):
        env.step({})
    t = env.timings()
    assert set(t) == set(TIMING_PHASES) | {"total"}
    assert all(v == 0.0 for v in t.values())
    assert all(v == 0.0 for v in env.sim.phase_s.values())
    assert env.team_time_s["left"] > 0.0  # the cycle budget still needs it


def test_reset_timings():
    env = teamenv.parallel_env(team_size=2, left="chaser", right="static")
    env.reset(seed=0)
    for _ in range(10):
        env.step({})
    assert env.timings()["total"] > 0.0
    env.reset_timings()
    assert all(v == 0.0 for v in env.timings().values())
    env.step({})
    t = env.timings()
    assert t["total"] > 0.0 and t["physics"] > 0.0


def test_simulation_phase_keys():
    env = teamenv.parallel_env(team_size=2)
    assert tuple(env.sim.phase_s) == SIM_PHASES
    env.reset(seed=0)
    env.step({a: {} for a in env.agents})
    assert env.sim.phase_s["physics"] > 0.0 and env.sim.phase_s["perception"] > 0.0


def test_failed_step_still_adds_up():
    env = teamenv.parallel_env(team_size=2)
    env.reset(seed=0)
    with pytest.raises(ActionError):
        env.step({a: {"walk": [np.nan, 0, 0]} for a in env.agents})
    t = env.timings()
    assert _named_sum(t) <= t["total"] * (1 + 1e-12)
    # reset() plus the failed step: the step's time is in the total (under "other").
    before = t["total"]
    with pytest.raises(ActionError):
        env.step({a: {"walk": [np.nan, 0, 0]} for a in env.agents})
    assert env.timings()["total"] > before


def _digest(profile_phases: bool) -> str:
    env = teamenv.parallel_env(team_size=3, right="chaser", action_format="box",
                               profile_phases=profile_phases)
    obs, _ = env.reset(seed=4)
    rng = np.random.default_rng(9)
    h = hashlib.sha256(pickle.dumps(obs))
    for _ in range(200):
        out = env.step({a: rng.uniform(-1, 1, 9).astype(np.float32) for a in env.agents})
        h.update(pickle.dumps(out))
    return h.hexdigest()


def test_profiling_does_not_change_the_trajectory():
    assert _digest(True) == _digest(False)
