"""Hand-built replays with known answers for the analytics tests (2 v 2 on a 30 x 20 m pitch).

The story (rows = cycles, 0.02 s each; the left side attacks +x throughout):

- rows 0-9: BeforeKickOff then KickOff_Left from row 1; play on from row 5;
- row 10: left_1 (player 0) kicks from the centre spot towards +y (a pass: not on frame);
- row 20: left_2 (player 1) touches the ball: the pass is completed (1 -> 2);
- row 30: right_1 (player 2) touches the ball: possession changes, the left side lost it in
  the middle third in open play;
- row 40: right_2 (player 3) kicks from (-10, 0) towards the left goal (direction pi, 8 m): on
  frame and in reach, a shot, with nobody in its cone; the ball rolls 0.5 m a row to -12.5;
- row 45: the ball crosses the line: Goal_Right, goal by right_2; row 50 on: KickOff_Left;
- rows 50-59: left_1 is fallen (one fall);
- row 60: KickIn_Right (the right side's set play), play on again at row 70 where right_1
  kicks it (a pass nobody receives: it stops at row 90);
- row 5: left_1 says a 10-byte message that left_2 hears and right_1 hears; one drop record;
- left_2 walks 0.01 m per row from row 1 to row 80 (0.79 m) and is beamed 5 m at row 81
  (not walking).
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from teamenv.replay import Replay, load_replay
from teamenv.sim.playmode import PlayMode

T = 100
N = 2  # players per side
HALF_LENGTH, HALF_WIDTH, HALF_GOAL_WIDTH = 15.0, 10.0, 1.05


def story_arrays() -> dict[str, np.ndarray]:
    mode = np.full(T, int(PlayMode.PlayOn), np.int8)
    mode[0] = int(PlayMode.BeforeKickOff)
    mode[1:5] = int(PlayMode.KickOff_Left)
    mode[45:50] = int(PlayMode.Goal_Right)
    mode[50:55] = int(PlayMode.KickOff_Left)
    mode[60:70] = int(PlayMode.KickIn_Right)
    ball = np.zeros((T, 4), np.float32)
    ball[11:20, 0:2] = (0.0, 1.0)  # the pass rolls to y = 1 (x stays 0)
    ball[11:20, 3] = 1.0
    ball[20:30, 0:2] = (0.0, 2.0)
    ball[30:40, 0:2] = (-10.0, 0.0)  # right_1 carried it (placed: a teleport in the story)
    ball[40:45, 0] = -10.5 - 0.5 * np.arange(5)  # the shot rolls 0.5 m a row: 2.5 m ahead
    ball[40:45, 2] = -25.0
    ball[45:60, 0:2] = (0.0, 0.0)
    ball[60:70, 0:2] = (5.0, -10.0)
    ball[70:90, 0:2] = (5.0, -9.0)
    ball[70:90, 3] = 0.5  # rolling, comes to rest at row 90
    ball[90:, 0:2] = (5.0, -8.5)
    players = np.zeros((T, 2 * N, 3), np.float32)
    players[:, 0, :2] = (-1.0, 0.0)
    players[:, 1, :2] = (-5.0, 5.0)
    players[1:81, 1, 0] = -5.0 + 0.01 * np.arange(80)
    players[81:, 1, :2] = (0.0, 0.0)
    players[:, 2, :2] = (5.0, 5.0)
    players[:, 3, :2] = (6.0, -6.0)
    score = np.zeros((T, 2), np.int16)
    score[45:, 1] = 1
    fallen = np.zeros((T, 2 * N), bool)
    fallen[50:60, 0] = True
    say_bytes = np.zeros((T, 2 * N), np.uint8)
    say_drops = np.zeros((T, 2 * N), np.uint16)
    heard_from = np.zeros((T, 2 * N), np.uint32)
    say_bytes[5, 0] = 10
    say_drops[5, 0] = 1
    heard_from[5, 0] = 1  # left_1 hears itself
    heard_from[5, 1] = 1  # left_2 hears left_1
    heard_from[5, 2] = 1  # right_1 hears left_1
    return {
        "ball": ball, "players": players, "play_mode": mode, "score": score,
        "time_s": np.arange(T) * 0.02, "attack_sign": np.ones(T, np.int8), "fallen": fallen,
        "kick_cycle": np.array([10, 40, 70], np.int32),
        "kick_player": np.array([0, 3, 2], np.int16),
        "kick_distance": np.array([5.0, 8.0, 3.0], np.float32),
        "kick_direction": np.array([math.pi / 2, math.pi, math.pi / 2], np.float32),
        "touch_cycle": np.array([20, 30], np.int32), "touch_player": np.array([1, 2], np.int16),
        "goal_cycle": np.array([45], np.int32), "goal_team": np.array([1], np.int8),
        "goal_player": np.array([3], np.int16),
        "say_bytes": say_bytes, "say_drops": say_drops, "heard_from": heard_from,
    }


def story_metadata(extras: bool = False) -> dict:
    return {"format": 2, "left": "lefty", "right": "righty", "seed": 7, "field": "hand",
            "team_size": N, "cycle_s": 0.02, "half_length": HALF_LENGTH,
            "half_width": HALF_WIDTH, "half_goal_width": HALF_GOAL_WIDTH, "extras": extras}


def save_replay(path: Path, arrays: dict[str, np.ndarray], metadata: dict) -> Path:
    with open(path, "wb") as fh:
        np.savez_compressed(fh, **arrays,
                            metadata=np.frombuffer(json.dumps(metadata).encode(), np.uint8))
    return path


def story_replay(tmp_path: Path, extras: dict[str, np.ndarray] | None = None) -> Replay:
    """The story, written to a file and loaded back (the loader is part of what is tested)."""
    arrays = story_arrays()
    if extras:
        arrays.update(extras)
    path = save_replay(tmp_path / "story.npz", arrays, story_metadata(extras is not None))
    return load_replay(path)
