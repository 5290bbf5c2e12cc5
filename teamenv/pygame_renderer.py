"""Draws the pitch, players and ball with pygame; returns RGB frames or shows a window.

In the core because the env's ``render()`` (PettingZoo's ``render_mode``) draws with it; the
render application (``teamenv.render``: a replay to GIF/MP4) draws its frames with it too.
pygame is imported on first use only (the ``render`` extra)."""

from __future__ import annotations

import os
from typing import Any

import numpy as np

from teamenv.errors import MissingExtraError
from teamenv.field import FieldSpec
from teamenv.sim.playmode import PlayMode

TEAM_COLOURS = ((40, 90, 220), (220, 50, 50))


def _pygame(headless: bool) -> Any:
    if headless:
        os.environ.setdefault("SDL_VIDEODRIVER", "dummy")
    os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")
    try:
        import pygame
    except ImportError as exc:
        raise MissingExtraError("render", "pygame", "rendering") from exc
    return pygame


class PygameRenderer:
    """Renders frames of ``field`` at ``pixels_per_metre``; mode "rgb_array" or "human"."""

    def __init__(self, field: FieldSpec, team_size: int, mode: str = "rgb_array",
                 width_px: int = 720) -> None:
        self.pg = _pygame(headless=(mode != "human"))
        self.field, self.team_size, self.mode = field, team_size, mode
        margin = 1.0
        self.scale = width_px / (field.length + 2 * margin)
        self.size = (width_px, int(round((field.width + 2 * margin) * self.scale)) + 24)
        self.origin = (width_px / 2, 24 + (self.size[1] - 24) / 2)
        self.pg.init()
        self.pg.font.init()
        self.font = self.pg.font.SysFont(None, 20)
        if mode == "human":
            self.screen = self.pg.display.set_mode(self.size)
            self.clock = self.pg.time.Clock()
        else:
            self.screen = self.pg.Surface(self.size)

    def _px(self, x: float, y: float) -> tuple[int, int]:
        return (int(round(self.origin[0] + x * self.scale)),
                int(round(self.origin[1] - y * self.scale)))

    def draw_frame(self, ball: np.ndarray, players: np.ndarray, mode: int, score: Any,
                   time_s: float, player_radius: float = 0.2) -> np.ndarray | None:
        """Draw one frame from world-frame arrays (ball (≥2,), players (2N, 3))."""
        pg, f, s = self.pg, self.field, self.screen
        s.fill((30, 120, 40))
        white = (235, 235, 235)
        hl, hw = f.half_length, f.half_width
        corners = [self._px(-hl, hw), self._px(hl, hw), self._px(hl, -hw), self._px(-hl, -hw)]
        pg.draw.lines(s, white, True, corners, 2)
        pg.draw.line(s, white, self._px(0, hw), self._px(0, -hw), 2)
        pg.draw.circle(s, white, self._px(0, 0), int(f.center_circle_radius * self.scale), 2)
        for sign in (-1, 1):
            x0, x1 = sign * hl, sign * (hl - f.penalty_length)
            pw = f.penalty_width / 2
            pg.draw.lines(s, white, False, [self._px(x0, pw), self._px(x1, pw),
                                             self._px(x1, -pw), self._px(x0, -pw)], 2)
            gx = sign * (hl + f.goal_depth)
            gw = f.half_goal_width
            pg.draw.lines(s, (250, 250, 120), False, [self._px(x0, gw), self._px(gx, gw),
                                                       self._px(gx, -gw), self._px(x0, -gw)], 3)
        radius = max(7, int(player_radius * self.scale))
        for i, (x, y, h) in enumerate(np.asarray(players, dtype=float)):
            colour = TEAM_COLOURS[i // self.team_size]
            centre = self._px(x, y)
            pg.draw.circle(s, colour, centre, radius)
            tip = (centre[0] + int(np.cos(h) * radius * 1.5), centre[1] - int(np.sin(h) * radius * 1.5))
            pg.draw.line(s, white, centre, tip, 2)
            label = self.font.render(str(i % self.team_size + 1), True, white)
            s.blit(label, (centre[0] + radius, centre[1] - radius - 8))
        pg.draw.circle(s, white, self._px(float(ball[0]), float(ball[1])),
                       max(3, int(0.11 * self.scale)))
        text = f"{int(score[0])} - {int(score[1])}   {time_s:6.1f} s   {PlayMode(int(mode)).name}"
        s.blit(self.font.render(text, True, white), (8, 4))
        if self.mode == "human":
            pg.event.pump()
            pg.display.flip()
            self.clock.tick(50)
            return None
        return np.transpose(pg.surfarray.array3d(s), (1, 0, 2)).copy()

    def draw(self, sim: Any) -> np.ndarray | None:
        """Draw the current state of a Simulation."""
        ref = sim.referee
        return self.draw_frame(sim.world.ball_state(), sim.world.player_poses(), int(ref.mode),
                               ref.score, ref.time_s, sim.profile.body_radius)

    def close(self) -> None:
        if self.mode == "human":
            self.pg.display.quit()
