"""Replays: per-cycle positions, play mode and score of a match, saved as a compressed .npz."""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from teamenv.errors import ConfigError

REPLAY_FORMAT = 1


@dataclass(frozen=True)
class Replay:
    """A recorded match: ``ball`` (T, 4) x, y, vx, vy; ``players`` (T, 2N, 3) x, y, heading;
    ``play_mode`` (T,); ``score`` (T, 2); ``time_s`` (T,); world frame, metres/radians."""

    ball: np.ndarray
    players: np.ndarray
    play_mode: np.ndarray
    score: np.ndarray
    time_s: np.ndarray
    metadata: dict[str, Any]

    @property
    def team_size(self) -> int:
        return self.players.shape[1] // 2

    def __len__(self) -> int:
        return len(self.time_s)


class ReplayRecorder:
    """Records a SoccerParallelEnv cycle by cycle (call ``record()`` after reset and each step)."""

    def __init__(self, env: Any) -> None:
        self.env = env
        self._ball: list[np.ndarray] = []
        self._players: list[np.ndarray] = []
        self._mode: list[int] = []
        self._score: list[tuple[int, int]] = []
        self._time: list[float] = []

    def record(self) -> None:
        sim = self.env.sim
        self._ball.append(sim.world.ball_state().astype(np.float32))
        self._players.append(sim.world.player_poses().astype(np.float32))
        self._mode.append(int(sim.referee.mode))
        self._score.append(tuple(sim.referee.score))
        self._time.append(sim.referee.time_s)

    def save(self, path: str | Path, metadata: dict[str, Any]) -> Path:
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        meta = dict(metadata, format=REPLAY_FORMAT, field=self.env.field.name,
                    team_size=self.env.team_size, cycle_s=self.env.physics.cycle_s)
        with open(path, "wb") as fh:
            np.savez_compressed(
                fh, ball=np.stack(self._ball), players=np.stack(self._players),
                play_mode=np.asarray(self._mode, np.int8), score=np.asarray(self._score, np.int16),
                time_s=np.asarray(self._time, np.float64),
                metadata=np.frombuffer(json.dumps(meta).encode(), dtype=np.uint8))
        return path


def load_replay(path: str | Path) -> Replay:
    """Load a replay written by ReplayRecorder; a malformed file raises ConfigError."""
    try:
        with np.load(Path(path), allow_pickle=False) as data:
            meta = json.loads(bytes(data["metadata"]).decode())
            replay = Replay(data["ball"], data["players"], data["play_mode"], data["score"],
                            data["time_s"], meta)
    except (OSError, KeyError, ValueError) as exc:
        raise ConfigError(f"replay {str(path)!r}: not a teamenv replay file ({exc})") from exc
    if meta.get("format") != REPLAY_FORMAT:
        raise ConfigError(f"replay {str(path)!r}: format {meta.get('format')!r}, "
                          f"expected {REPLAY_FORMAT}")
    return replay
