"""The ball reach of several beliefs in one compiled pass gives the NumPy expressions' bits, and
is looked up once per belief."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from strategy.decision.field_player import MOVING_BALL_M_S, FieldPlayerDecisionMaker
from strategy.geometry import BallRoll
from strategy.perception.worldmodel import WorldModel
from strategy.teams.full_config import FullTeamConfig
from tests.strategy.scenes import skills, world


def _reach_numpy(maker: FieldPlayerDecisionMaker, wm: WorldModel) -> np.ndarray:
    """The per-belief NumPy ball reach the kernel replaced (the test's oracle)."""
    d = wm.upright_ball_distances()
    if math.hypot(*wm.ball_velocity) < MOVING_BALL_M_S:
        return d
    times, _ = wm.intercepts(wm.teammates, maker.skills.run_speed)
    return np.where(np.isfinite(d), times * maker.skills.run_speed, np.inf)


def _random_world(rng: np.random.Generator, field: str, roll: BallRoll) -> WorldModel:
    n = 7 if field == "mj7v7" else 11
    half = (7.0, 4.5) if field == "mj7v7" else (15.0, 10.0)
    mates = [tuple(rng.uniform(-1.0, 1.0, 2) * half) for _ in range(n - 1)]
    speed = float(rng.choice([0.0, rng.uniform(0.0, 1.0), MOVING_BALL_M_S,
                              rng.uniform(1.0, 9.0)]))
    angle = rng.uniform(-np.pi, np.pi)
    wm = world(position=tuple(rng.uniform(-1.0, 1.0, 2) * half), ball=tuple(
        rng.uniform(-1.0, 1.0, 2) * half), teammates=mates, field=field, team_size=n,
        ball_velocity=(speed * np.cos(angle), speed * np.sin(angle)),
        fallen_mates=tuple(rng.choice(n, int(rng.integers(0, 3)), replace=False).tolist()))
    absent = rng.random(n) < 0.15
    wm.teammates_present[absent] = False
    return dataclasses.replace(wm, roll=roll)


@pytest.mark.parametrize("field", ["simspark", "mj7v7"])
def test_the_kernel_gives_the_numpy_reach_bit_for_bit(field: str) -> None:
    rng = np.random.default_rng(11_27)
    maker = FieldPlayerDecisionMaker(FullTeamConfig().decision_params(), skills(field),
                                     goalie=None)
    rolls = [BallRoll(), BallRoll(linear_drag=0.0, rolling_decel=0.6),
             BallRoll(linear_drag=0.4, rolling_decel=0.0)]
    rolling = 0
    for _ in range(60):
        wms = [_random_world(rng, field, rolls[int(rng.integers(0, 3))]) for _ in range(5)]
        got = maker.ball_reach_rows(wms)
        want = np.array([_reach_numpy(maker, wm) for wm in wms])
        assert got.tobytes() == want.tobytes()
        rolling += sum(np.hypot(*wm.ball_velocity) >= MOVING_BALL_M_S for wm in wms)
        assert np.isinf(got).any()  # absent or fallen teammates
    assert 60 < rolling < 240  # both kinds of ball were drawn


def test_one_computation_per_belief_and_the_goalie_only_when_alone() -> None:
    maker = FieldPlayerDecisionMaker(FullTeamConfig().decision_params(), skills("mj7v7"),
                                     goalie=0, memo={})
    wm = world(position=(-6.0, 0.0), ball=(2.0, 1.0), teammates=[(1.0, 1.0), (-2.0, 0.0)],
               field="mj7v7", team_size=7)
    keyed = dataclasses.replace(wm, belief_key=b"k")
    calls = []
    real = maker._ball_reach_many
    maker._ball_reach_many = lambda models: calls.append(len(models)) or real(models)
    rows = maker.ball_reach_rows([keyed, keyed, wm, keyed])
    assert calls == [2]  # the keyed belief once, the unkeyed one on its own
    assert rows.tobytes() == np.array([rows[0], rows[0], rows[2], rows[0]]).tobytes()
    maker.ball_reach_rows([keyed])
    assert calls == [2]  # held in the memo
    assert maker.choose_ball_players([keyed]).tolist() == [1]  # not the goalie, nearer
    down = dataclasses.replace(world(position=(-6.0, 0.0), ball=(2.0, 1.0),
                                     teammates=[(1.0, 1.0)], field="mj7v7", team_size=7,
                                     fallen_mates=(1,)), belief_key=b"down")
    assert maker.choose_ball_players([down]).tolist() == [0]  # nobody else upright
