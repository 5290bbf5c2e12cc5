"""Rendering (pygame, behind the ``render`` extra): frames of a live env or of a replay."""

from __future__ import annotations

from teamenv.render.gif import render_replay_gif

__all__ = ["render_replay_gif"]
