"""``best_kick``'s compiled loops give the bits of the NumPy expressions they replaced, on
random scenes: both fields, three bodies, crowds near the ball, fallen players, excluded
teammates, balls near and past the goal line."""

from __future__ import annotations

import numpy as np
import pytest

from locomotion import load_profile
from strategy.behaviours.kick_choice import best_kick
from teamenv.capabilities import body_capabilities

from . import scenes
from .kick_choice_numpy import best_kick_numpy

BODIES = [scenes.BODY] + [body_capabilities(load_profile(p)) for p in ("t1_league", "t1_mj")]


def _bits(choice) -> tuple:
    return (choice.target.tobytes(), choice.power, np.float64(choice.value).tobytes(),
            np.float64(choice.margin_s).tobytes(), choice.shot,
            np.float64(choice.goal_chance).tobytes())


def _scene(rng: np.random.Generator, t: int):
    field = ("simspark", "mj7v7")[t % 2]
    hl = 15.0 if field == "simspark" else 7.5

    def point():
        return rng.uniform(-1.1 * hl, 1.1 * hl), rng.uniform(-0.8 * hl, 0.8 * hl)

    ball = point() if t % 5 else (rng.uniform(hl - 1.0, hl + 0.3), rng.uniform(-1.0, 1.0))
    crowd = (1.0, 1.0, 0.1)[t % 3]  # every third scene: the opponents near the ball
    mates = [point() for _ in range(rng.integers(0, 8))]
    opponents = [(ball[0] + crowd * (x - ball[0]), ball[1] + crowd * (y - ball[1]))
                 for x, y in (point() for _ in range(rng.integers(0, 8)))]
    wm = scenes.world(position=point(), ball=ball, teammates=mates, opponents=opponents,
                      field=field, fallen_mates=[k for k in range(len(mates) + 1)
                                                 if rng.random() < 0.2])
    wm.opponents_fallen[:] = rng.random(len(wm.opponents_fallen)) < 0.2
    exclude = tuple(int(k) for k in rng.choice(len(mates) + 1, rng.integers(0, 2)))
    return wm, exclude


@pytest.mark.parametrize("seed", range(4))
def test_the_compiled_kick_choice_equals_the_numpy_expressions_bit_for_bit(seed):
    rng = np.random.default_rng(seed)
    shots = 0
    for t in range(400):
        wm, exclude = _scene(rng, t)
        args = (wm, BODIES[t % 3], float(rng.uniform(0.3, 1.5)), 2.0,
                float(rng.uniform(0.0, 0.3)), 25.0, float(rng.uniform(0.0, 1.0)))
        expected = best_kick_numpy(*args, exclude=exclude)
        assert _bits(best_kick(*args, exclude=exclude)) == _bits(expected), (seed, t)
        shots += expected.shot
    assert 0 < shots < 400  # the scenes choose shots and other kicks
