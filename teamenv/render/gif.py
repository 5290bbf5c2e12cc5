"""Render a replay to an animated GIF (or MP4 when imageio's ffmpeg plugin is installed)."""

from __future__ import annotations

import math
from pathlib import Path

from teamenv.errors import ConfigError, MissingExtraError, value_repr
from teamenv.field import field_preset
from teamenv.replay import Replay, load_replay


def gif_frame_ms(fps: float) -> int:
    """The delay of one GIF frame at ``fps`` frames per second, in milliseconds (what
    imageio's pillow writer takes as ``duration``; GIF itself stores whole centiseconds, so
    e.g. 30 fps is written as 30 ms and plays at 33 fps)."""
    if isinstance(fps, bool) or not isinstance(fps, (int, float)) or not math.isfinite(fps) \
            or fps <= 0:
        raise ConfigError(f"render: fps must be a number > 0, got {value_repr(fps)}")
    return max(1, round(1000.0 / fps))


def render_replay_gif(replay: Replay | str | Path, out_path: str | Path, fps: int = 10,
                      every: int = 5, start: int = 0, stop: int | None = None,
                      width_px: int = 480) -> Path:
    """Write every ``every``-th cycle of ``replay`` between ``start`` and ``stop`` to
    ``out_path`` at ``fps`` frames per second; returns the path."""
    frame_ms = gif_frame_ms(fps)
    if isinstance(every, bool) or not isinstance(every, int) or every < 1:
        raise ConfigError(f"render: every must be an integer >= 1, got {value_repr(every)}")
    from teamenv.pygame_renderer import PygameRenderer

    try:
        import imageio.v2 as imageio
    except ImportError as exc:
        raise MissingExtraError("render", "imageio", "writing GIF/video") from exc
    if not isinstance(replay, Replay):
        replay = load_replay(replay)
    renderer = PygameRenderer(field_preset(replay.metadata["field"]), replay.team_size,
                              "rgb_array", width_px=width_px)
    frames = [
        renderer.draw_frame(replay.ball[t], replay.players[t], int(replay.play_mode[t]),
                            replay.score[t], float(replay.time_s[t]))
        for t in range(start, len(replay) if stop is None else min(stop, len(replay)), every)
    ]
    out_path = Path(out_path)
    out_path.parent.mkdir(parents=True, exist_ok=True)
    if out_path.suffix.lower() == ".gif":
        # imageio's pillow writer takes the frame delay in milliseconds (seconds would round
        # to a 0 ms delay, which viewers play as fast as they can)
        imageio.mimsave(out_path, frames, duration=frame_ms, loop=0)
    else:
        imageio.mimsave(out_path, frames, fps=fps)
    renderer.close()
    return out_path
