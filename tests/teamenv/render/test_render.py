"""rgb_array rendering and replay GIFs (the render extra is installed in CI)."""

import numpy as np

import teamenv
from teamenv.errors import ConfigError


def test_rgb_array_frame():
    env = teamenv.parallel_env(team_size=3, render_mode="rgb_array")
    env.reset(seed=0)
    frame = env.render()
    assert frame.ndim == 3 and frame.shape[2] == 3 and frame.dtype == np.uint8
    # The pitch is green and the two teams' colours appear.
    assert (frame[..., 1] > frame[..., 0]).mean() > 0.5
    assert ((frame[..., 2] > 200) & (frame[..., 0] < 80)).any()
    assert ((frame[..., 0] > 200) & (frame[..., 2] < 80)).any()
    env.close()


def test_human_mode_runs_headless():
    env = teamenv.parallel_env(team_size=1, render_mode="human")
    env.reset(seed=0)
    env.step({a: {} for a in env.agents})
    env.close()


def test_bad_render_mode():
    import pytest

    with pytest.raises(ConfigError, match="render_mode"):
        teamenv.parallel_env(render_mode="ascii")
