"""The GIF writer's frame delays follow ``fps`` (read back from the written file)."""

from __future__ import annotations

import pytest

import teamenv
from teamenv.errors import ConfigError
from teamenv.replay import ReplayRecorder, load_replay

pytest.importorskip("imageio")
PIL_Image = pytest.importorskip("PIL.Image")


@pytest.fixture(scope="module")
def replay_path(tmp_path_factory):
    env = teamenv.parallel_env(team_size=1)
    env.reset(seed=0)
    recorder = ReplayRecorder(env)
    recorder.record()
    for _ in range(120):  # play starts after the kick-off pause; the players then walk
        env.step({a: {"walk": [1.0, 0.0, 1.0]} for a in env.agents})
        recorder.record()
    path = tmp_path_factory.mktemp("gif") / "short.npz"
    recorder.save(path, {"seed": 0})
    env.close()
    return path


def _frame_delays_ms(path) -> list[int]:
    with PIL_Image.open(path) as image:
        delays = []
        for k in range(image.n_frames):
            image.seek(k)
            delays.append(image.info.get("duration"))
    return delays


@pytest.mark.parametrize(("fps", "expected_ms"), [(10, 100), (4, 250), (25, 40)])
def test_gif_frame_delay_follows_fps(replay_path, tmp_path, fps, expected_ms):
    from teamenv.render import render_replay_gif

    out = render_replay_gif(replay_path, tmp_path / f"m{fps}.gif", fps=fps, every=30,
                            width_px=240)
    delays = _frame_delays_ms(out)
    assert len(delays) == len(range(0, len(load_replay(replay_path)), 30))
    assert delays == [expected_ms] * len(delays)


@pytest.mark.parametrize("fps", [0, -5, float("nan"), "10", True])
def test_gif_bad_fps_is_a_config_error(replay_path, tmp_path, fps):
    from teamenv.render import render_replay_gif

    with pytest.raises(ConfigError, match="fps"):
        render_replay_gif(replay_path, tmp_path / "bad.gif", fps=fps)


def test_gif_bad_every_is_a_config_error(replay_path, tmp_path):
    from teamenv.render import render_replay_gif

    with pytest.raises(ConfigError, match="every"):
        render_replay_gif(replay_path, tmp_path / "bad.gif", every=0)
