"""Rendering a replay to a GIF or video (pygame and imageio, behind the ``render`` extra).

An application: its frames come from ``teamenv.pygame_renderer``, which is in the core because
the env's own ``render()`` draws with it."""

from __future__ import annotations

from teamenv.render.gif import render_replay_gif

__all__ = ["render_replay_gif"]
