"""PFSP: the weightings are AlphaStar's formulas, and opponents drawn per (copy, episode) come
up as often as their probabilities say (binomial tolerance over a seeded draw), the hard
ones most."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.stats import binomtest, chisquare

from teamenv.errors import ConfigError
from teamenv.selfplay.pfsp import OpponentMix, pfsp_probabilities, pfsp_weights

P_WIN = [0.1, 0.5, 0.8, 0.97]
TEAMS = ("chaser", "static", "full", "chaser:all_chase=true")


def test_weightings_are_the_published_formulas():
    p = np.array(P_WIN)
    assert pfsp_weights(p, "hard") == pytest.approx((1 - p) ** 2)
    assert pfsp_weights(p, "hard", exponent=3) == pytest.approx((1 - p) ** 3)
    assert pfsp_weights(p, "variance") == pytest.approx(p * (1 - p))
    assert pfsp_weights(p, "linear") == pytest.approx(1 - p)
    assert pfsp_weights(p, "uniform") == pytest.approx(np.ones(4))
    probs = pfsp_probabilities(p, "hard")
    assert probs == pytest.approx((1 - p) ** 2 / np.sum((1 - p) ** 2))
    # the variance weighting prefers opponents of the learner's level
    assert np.argmax(pfsp_probabilities(p, "variance")) == 1


def test_a_pool_beaten_with_certainty_is_drawn_uniformly_and_latest_share_mixes_in():
    assert pfsp_probabilities([1.0, 1.0, 1.0], "hard") == pytest.approx([1 / 3] * 3)
    probs = pfsp_probabilities(P_WIN, "hard", latest_share=0.35, latest=3)
    base = pfsp_probabilities(P_WIN, "hard")
    assert probs == pytest.approx(0.65 * base + 0.35 * np.eye(4)[3])
    assert probs.sum() == pytest.approx(1.0)


@pytest.mark.parametrize("call,match", [
    (lambda: pfsp_weights(P_WIN, "greedy"), "weighting 'greedy' is not one of"),
    (lambda: pfsp_weights(P_WIN, "hard", exponent=0), "exponent must be"),
    (lambda: pfsp_weights([0.5, 1.2], "hard"), "probabilities in"),
    (lambda: pfsp_probabilities([], "hard"), "no opponents"),
    (lambda: pfsp_probabilities(P_WIN, "hard", latest_share=0.5), "needs the latest"),
    (lambda: OpponentMix(TEAMS, (0.5, 0.5, 0.5, 0.5), 0), "summing to 1"),
    (lambda: OpponentMix(TEAMS[:2], (1.0,), 0), "as many"),
])
def test_bad_input_is_clear(call, match):
    with pytest.raises(ConfigError, match=match):
        call()


def test_sampled_frequencies_match_the_weights_and_hard_opponents_come_first():
    probs = pfsp_probabilities(P_WIN, "hard")
    mix = OpponentMix(TEAMS, tuple(probs), seed=2026)
    copies, episodes = 8, 2500
    drawn = [mix.draw(c, e).label for c in range(copies) for e in range(episodes)]
    n = len(drawn)
    counts = np.array([drawn.count(t) for t in TEAMS])
    for team, count, p in zip(TEAMS, counts, probs, strict=True):
        # within 4.5 binomial standard deviations (a seeded draw: fixed, not flaky) ...
        assert abs(count - n * p) <= 4.5 * np.sqrt(n * p * (1 - p)), (team, count, n * p)
        # ... and an exact binomial test does not reject it
        assert binomtest(int(count), n, p).pvalue > 1e-3, (team, count, n * p)
    assert chisquare(counts, n * probs).pvalue > 1e-3
    # the lower the learner's chance against an opponent, the more often it is drawn
    assert list(counts) == sorted(counts, reverse=True)
    assert counts[0] > 10 * counts[3]


def test_a_draw_depends_on_the_seed_copy_and_episode_only():
    mix = OpponentMix(TEAMS, (0.25,) * 4, seed=7)
    forward = [mix.draw(c, e) for c in range(3) for e in range(50)]
    backward = [mix.draw(c, e) for c in reversed(range(3)) for e in reversed(range(50))]
    assert forward == list(reversed(backward))
    other = OpponentMix(TEAMS, (0.25,) * 4, seed=8)
    assert forward != [other.draw(c, e) for c in range(3) for e in range(50)]
    assert OpponentMix.single("static").draw(5, 9).label == "static"
