"""Replays: per-cycle positions, play mode, score, kicks, touches, falls and messages of a match
(and, optionally, each agent's belief and roles), saved as a compressed .npz.

Format 3 (written today) is format 2 with a checksum: the metadata's ``sha256`` is the SHA-256
of the file's content (``replay_checksum``: every array's name, dtype, shape and bytes, and the
rest of the metadata), and ``load_replay`` refuses a file whose content does not match it, so a
damaged replay that still parses is an error rather than a different match. Formats 1 and 2
(written before checksums) still load; their only guard is the zip's CRC-32 of each member.

Format 2 adds to format 1 (which still loads; its new fields are None):

- ``attack_sign`` (T,) int8: +1 when the left side attacks +x in that row (sides change at half
  time);
- ``fallen`` (T, 2N) bool;
- kicks ``kick_cycle`` (K,) int32 (the row the kick happened in), ``kick_player`` (K,) int16,
  ``kick_distance`` (K,) float32 metres, ``kick_direction`` (K,) float32 world radians;
- physics touches ``touch_cycle``/``touch_player`` (M,): a player's body touched the ball;
- goals ``goal_cycle``/``goal_team`` (0 left, 1 right)/``goal_player`` (-1: nobody touched);
- messages, per row and agent: ``say_bytes`` (T, 2N) uint8, the length of what the agent said
  that cycle as the listeners got it (0: silent, or a message dropped whole as illegal);
  ``say_drops`` (T, 2N) uint16, the channel's drop records of the agent's message (one per
  listener that lost it; one for a message dropped whole); ``heard_from`` (T, 2N) uint32, a
  bit mask of the speakers (bit k = player k) each agent heard that cycle (itself included).

Extras (``ReplayRecorder(env, extras=True)``; empty otherwise): what each agent believed, from
the optional team hook ``annotations()`` (see ``ANNOTATION_KEYS``), in the world frame:
``belief_pose`` (T, 2N, 3) x, y, heading (NaN: not given), ``belief_ball`` (T, 2N, 2),
``role`` (T, 2N) int8 (the agent's own role index, -1: not given) and ``role_vector``
(T, 2N, N) int8 (the team's role assignment as the agent holds it, -1: not given). The file
keeps the beliefs as their errors from the true pose and ball, quantised to int16
(``belief_pose_error``, ``belief_ball_error``: 1 cm and 1 mrad steps, -32768 = unknown): a
state-mode belief is the truth (errors 0) and vision-mode errors are small numbers, so they
compress well; ``load_replay`` adds the truth back. Row t holds what each agent believed
when it acted on the observation of row t (in step t + 1); the last row is unknown.
"""

from __future__ import annotations

import hashlib
import json
import math
from collections.abc import Mapping
from dataclasses import dataclass, fields
from pathlib import Path
from typing import Any

import numpy as np

from teamenv.errors import ConfigError, value_repr
from teamenv.input_files import read_npz

REPLAY_FORMAT = 3
READABLE_FORMATS = (1, 2, 3)
#: The metadata key of a format-3 replay's checksum (``replay_checksum``).
CHECKSUM_KEY = "sha256"
#: What a team's optional ``annotations()`` may give per agent name, in the team's own frame
#: (attacking +x, as its observations): ``pose`` (x, y, heading) m/rad, ``ball`` (x, y) m,
#: ``role`` int, ``role_vector`` sequence of N ints (the team's assignment as the agent holds
#: it). Every key is optional; an agent left out is recorded as unknown.
ANNOTATION_KEYS = ("pose", "ball", "role", "role_vector")
_FORMAT_2_ARRAYS = ("attack_sign", "fallen", "kick_cycle", "kick_player", "kick_distance",
                    "kick_direction", "touch_cycle", "touch_player", "goal_cycle", "goal_team",
                    "goal_player", "say_bytes", "say_drops", "heard_from")
#: belief errors are stored in these steps (x, y metres; heading radians), as int16
POSE_ERROR_STEPS = (0.01, 0.01, 0.001)
UNKNOWN_Q = -32768
_EXTRA_ARRAYS = ("belief_pose", "belief_ball", "belief_pose_error", "belief_ball_error", "role",
                 "role_vector")


@dataclass(frozen=True)
class Replay:
    """A recorded match: ``ball`` (T, 4) x, y, vx, vy; ``players`` (T, 2N, 3) x, y, heading;
    ``play_mode`` (T,); ``score`` (T, 2); ``time_s`` (T,); world frame, metres/radians.

    Row 0 is the state after ``reset``, row t the state after step t. The other fields are
    described in the module docstring; they are None in a format-1 replay (and the extras
    also when the match was recorded without them)."""

    ball: np.ndarray
    players: np.ndarray
    play_mode: np.ndarray
    score: np.ndarray
    time_s: np.ndarray
    metadata: dict[str, Any]
    attack_sign: np.ndarray | None = None
    fallen: np.ndarray | None = None
    kick_cycle: np.ndarray | None = None
    kick_player: np.ndarray | None = None
    kick_distance: np.ndarray | None = None
    kick_direction: np.ndarray | None = None
    touch_cycle: np.ndarray | None = None
    touch_player: np.ndarray | None = None
    goal_cycle: np.ndarray | None = None
    goal_team: np.ndarray | None = None
    goal_player: np.ndarray | None = None
    say_bytes: np.ndarray | None = None
    say_drops: np.ndarray | None = None
    heard_from: np.ndarray | None = None
    belief_pose: np.ndarray | None = None
    belief_ball: np.ndarray | None = None
    role: np.ndarray | None = None
    role_vector: np.ndarray | None = None

    @property
    def team_size(self) -> int:
        return self.players.shape[1] // 2

    @property
    def has_events(self) -> bool:
        """True when kicks, touches, falls and messages were recorded (format 2)."""
        return self.kick_cycle is not None

    @property
    def has_extras(self) -> bool:
        """True when the agents' beliefs and roles were recorded."""
        return self.role is not None

    def __len__(self) -> int:
        return len(self.time_s)


class ReplayRecorder:
    """Records a SoccerParallelEnv cycle by cycle (call ``record()`` after reset and each step).

    ``extras``: also record each agent's belief and roles from the teams' optional
    ``annotations()`` hook (a team without it is recorded as unknown). Recording reads the env
    and never changes it: a match plays the same with or without a recorder.
    """

    def __init__(self, env: Any, extras: bool = False) -> None:
        self.env = env
        self.extras = bool(extras)
        self.n = 2 * env.team_size
        if self.n > 32:
            raise ConfigError(f"replay: {self.n} players do not fit the 32-bit heard_from mask")
        self._ball: list[np.ndarray] = []
        self._players: list[np.ndarray] = []
        self._mode: list[int] = []
        self._score: list[tuple[int, int]] = []
        self._time: list[float] = []
        self._sign: list[int] = []
        self._fallen: list[np.ndarray] = []
        self._kicks: list[tuple[int, int, float, float]] = []
        self._touches: list[tuple[int, int]] = []
        self._goals: list[tuple[int, int, int]] = []
        self._talk: list[tuple[int, np.ndarray, np.ndarray, np.ndarray]] = []
        self._pose: list[np.ndarray] = []
        self._belief_ball: list[np.ndarray] = []
        self._role: list[np.ndarray] = []
        self._role_vector: list[np.ndarray] = []
        self._bits = np.left_shift(np.uint32(1), np.arange(self.n, dtype=np.uint32))

    def record(self) -> None:
        sim = self.env.sim
        row = len(self._time)
        self._ball.append(sim.world.ball_state().astype(np.float32))
        self._players.append(sim.world.player_poses().astype(np.float32))
        ref = sim.referee
        self._mode.append(int(ref.mode))
        self._score.append(tuple(ref.score))
        self._time.append(ref.time_s)
        self._sign.append(int(ref.attack_sign[0]))
        self._fallen.append(np.asarray(sim.bodies.fallen, dtype=bool).copy())
        if row > 0:  # row 0 is the state after reset: nothing happened before it
            report = self.env.last_report
            self._kicks.extend((row, int(p), float(d), float(a)) for p, d, a in report.kicks)
            self._touches.extend((row, int(p)) for p in sim.world.touches)
            for event in report.referee:
                if event.kind == "goal":
                    player = -1 if event.player is None else int(event.player)
                    self._goals.append((row, int(event.team), player))
            if report.delivery is not None:
                self._talk.append((row, *self._messages(report.delivery)))
        if self.extras and row > 0:
            # what the teams acted on in this step: their beliefs about the previous row
            previous = float(self._sign[row - 1])
            self._annotate([previous, -previous])

    def _messages(self, delivery: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(say_bytes, say_drops, heard_from) of one delivery, each (2N,)."""
        n = self.n
        said = np.zeros(n, np.uint8)
        drops = np.zeros(n, np.uint16)
        heard = np.zeros(n, np.uint32)
        if delivery.pairs is not None:
            listener, speaker, texts, *_ = delivery.pairs
        else:
            flat = [(i, h.speaker, h.text) for i, got in enumerate(delivery.heard) for h in got]
            listener = np.array([f[0] for f in flat], dtype=np.intp)
            speaker = np.array([f[1] for f in flat], dtype=np.intp)
            texts = np.array([f[2] for f in flat], dtype=object)
        if len(listener):
            np.bitwise_or.at(heard, listener, self._bits[speaker])
            first = np.unique(speaker, return_index=True)[1]
            said[speaker[first]] = [min(len(t), 255) for t in texts[first]]
        drop_speaker = delivery.drop_arrays()[0]
        if len(drop_speaker):
            np.add.at(drops, drop_speaker, 1)
        return said, drops, heard

    def _annotate_unknown(self) -> tuple[np.ndarray, ...]:
        n, size = self.n, self.env.team_size
        rows = (np.full((n, 3), np.nan, np.float32), np.full((n, 2), np.nan, np.float32),
                np.full(n, -1, np.int8), np.full((n, size), -1, np.int8))
        for store, values in zip((self._pose, self._belief_ball, self._role, self._role_vector),
                                 rows, strict=True):
            store.append(values)
        return rows

    def _annotate(self, attack_sign: list[float]) -> None:
        size = self.env.team_size
        pose, ball, role, vector = self._annotate_unknown()
        for side_index, side in enumerate(("left", "right")):
            team = getattr(self.env, "teams", {}).get(side)
            hook = getattr(team, "annotations", None)
            if hook is None:
                continue
            sign = float(attack_sign[side_index])
            for agent, values in (hook() or {}).items():
                i = _player_index(agent, side, size)
                _fill_annotation(values, i, sign, pose, ball, role, vector, agent)

    def arrays(self) -> dict[str, np.ndarray]:
        """Everything recorded so far, as the arrays a replay file holds (no metadata)."""
        t, n = len(self._time), self.n
        say_bytes = np.zeros((t, n), np.uint8)
        say_drops = np.zeros((t, n), np.uint16)
        heard_from = np.zeros((t, n), np.uint32)
        for row, said, drops, heard in self._talk:
            say_bytes[row], say_drops[row], heard_from[row] = said, drops, heard
        kicks = np.asarray(self._kicks, dtype=np.float64).reshape(-1, 4)
        touches = np.asarray(self._touches, dtype=np.int64).reshape(-1, 2)
        goals = np.asarray(self._goals, dtype=np.int64).reshape(-1, 3)
        out = {
            "ball": np.stack(self._ball), "players": np.stack(self._players),
            "play_mode": np.asarray(self._mode, np.int8),
            "score": np.asarray(self._score, np.int16),
            "time_s": np.asarray(self._time, np.float64),
            "attack_sign": np.asarray(self._sign, np.int8),
            "fallen": np.stack(self._fallen) if self._fallen else np.zeros((0, n), bool),
            **event_arrays(kicks, touches, goals),
            "say_bytes": say_bytes, "say_drops": say_drops, "heard_from": heard_from,
        }
        if self.extras and t:
            self._annotate_unknown()  # the last row: nobody acted on it
            error = np.stack(self._pose) - out["players"]
            error[..., 2] = np.remainder(error[..., 2] + np.pi, 2.0 * np.pi) - np.pi
            out["belief_pose_error"] = _quantise(error, POSE_ERROR_STEPS)
            out["belief_ball_error"] = _quantise(np.stack(self._belief_ball)
                                                 - out["ball"][:, None, :2], POSE_ERROR_STEPS[:2])
            out["role"] = np.stack(self._role)
            out["role_vector"] = np.stack(self._role_vector)
            for rows in (self._pose, self._belief_ball, self._role, self._role_vector):
                rows.pop()  # recording may go on
        return out

    def save(self, path: str | Path, metadata: dict[str, Any]) -> Path:
        meta = dict(metadata, field=self.env.field.name,
                    team_size=self.env.team_size, cycle_s=self.env.physics.cycle_s,
                    half_length=float(self.env.field.half_length),
                    half_width=float(self.env.field.half_width),
                    half_goal_width=float(self.env.field.half_goal_width),
                    extras=self.extras)
        return write_replay(path, self.arrays(), meta)


def replay_checksum(arrays: Mapping[str, np.ndarray], metadata: Mapping[str, Any]) -> str:
    """SHA-256 (hex) of a replay's content: each array's name, dtype, shape and C-order bytes
    (in name order), then the metadata without its checksum as sorted JSON."""
    digest = hashlib.sha256()
    for name in sorted(arrays):
        array = np.ascontiguousarray(arrays[name])
        digest.update(f"{name}|{array.dtype.str}|{array.shape}|".encode())
        digest.update(array.tobytes())
    rest = {k: v for k, v in metadata.items() if k != CHECKSUM_KEY}
    digest.update(json.dumps(rest, sort_keys=True).encode())
    return digest.hexdigest()


def write_replay(path: str | Path, arrays: Mapping[str, np.ndarray],
                 metadata: Mapping[str, Any]) -> Path:
    """Write a replay file (format ``REPLAY_FORMAT``): ``arrays`` and ``metadata`` (JSON-able;
    its format is set here) with their checksum. Returns the path."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    meta = {k: v for k, v in metadata.items() if k != CHECKSUM_KEY}
    meta["format"] = REPLAY_FORMAT
    meta = json.loads(json.dumps(meta))  # what a reader gets back (tuples as lists, ...)
    meta[CHECKSUM_KEY] = replay_checksum(arrays, meta)
    with open(path, "wb") as fh:  # a file object: numpy would append .npz to a bare name
        np.savez_compressed(fh, **arrays,
                            metadata=np.frombuffer(json.dumps(meta).encode(), dtype=np.uint8))
    return path


def event_arrays(kicks: np.ndarray, touches: np.ndarray, goals: np.ndarray
                 ) -> dict[str, np.ndarray]:
    """The kick, touch and goal arrays of a replay file from rows (cycle, player, distance,
    direction), (cycle, player) and (cycle, team, player), in the file's dtypes."""
    kicks = np.asarray(kicks, np.float64).reshape(-1, 4)
    touches = np.asarray(touches, np.int64).reshape(-1, 2)
    goals = np.asarray(goals, np.int64).reshape(-1, 3)
    return {
        "kick_cycle": kicks[:, 0].astype(np.int32), "kick_player": kicks[:, 1].astype(np.int16),
        "kick_distance": kicks[:, 2].astype(np.float32),
        "kick_direction": kicks[:, 3].astype(np.float32),
        "touch_cycle": touches[:, 0].astype(np.int32),
        "touch_player": touches[:, 1].astype(np.int16),
        "goal_cycle": goals[:, 0].astype(np.int32), "goal_team": goals[:, 1].astype(np.int8),
        "goal_player": goals[:, 2].astype(np.int16),
    }


def _quantise(error: np.ndarray, steps: tuple[float, ...]) -> np.ndarray:
    """Errors in whole ``steps`` (one per last-axis column) as int16; NaN -> UNKNOWN_Q."""
    q = np.round(error / np.asarray(steps, dtype=np.float64))
    q = np.clip(np.nan_to_num(q, nan=UNKNOWN_Q), UNKNOWN_Q, 32767)
    return q.astype(np.int16)


def _unquantise(q: np.ndarray, steps: tuple[float, ...]) -> np.ndarray:
    out = q.astype(np.float32) * np.asarray(steps, dtype=np.float32)
    out[q == UNKNOWN_Q] = np.nan
    return out


def _player_index(agent: Any, side: str, team_size: int) -> int:
    prefix = f"{side}_"
    if not isinstance(agent, str) or not agent.startswith(prefix):
        raise ConfigError(f"replay annotations: {side} team named agent {agent!r}, "
                          f"expected {prefix}1..{prefix}{team_size}")
    try:
        unum = int(agent[len(prefix):])
    except ValueError:
        unum = 0
    if not 1 <= unum <= team_size:
        raise ConfigError(f"replay annotations: {side} team named agent {agent!r}, "
                          f"expected {prefix}1..{prefix}{team_size}")
    return (0 if side == "left" else team_size) + unum - 1


def _fill_annotation(values: Mapping[str, Any], i: int, sign: float, pose: np.ndarray,
                     ball: np.ndarray, role: np.ndarray, vector: np.ndarray, agent: str) -> None:
    """One agent's annotation, from its team's frame into the world frame (x, y times the
    side's attack sign; heading turned by pi when it attacks -x)."""
    unknown = set(values) - set(ANNOTATION_KEYS)
    if unknown:
        raise ConfigError(f"replay annotations of {agent!r}: unknown key(s) {sorted(unknown)}; "
                          f"known: {list(ANNOTATION_KEYS)}")
    if values.get("pose") is not None:
        x, y, h = (float(v) for v in values["pose"])
        pose[i] = (sign * x, sign * y, math.remainder(h + (0.0 if sign > 0 else math.pi),
                                                      2.0 * math.pi))
    if values.get("ball") is not None:
        bx, by = (float(v) for v in values["ball"])
        ball[i] = (sign * bx, sign * by)
    if values.get("role") is not None:
        role[i] = int(values["role"])
    if values.get("role_vector") is not None:
        v = np.asarray(values["role_vector"], dtype=np.int64).ravel()
        if v.size != vector.shape[1]:
            raise ConfigError(f"replay annotations of {agent!r}: role_vector has {v.size} "
                              f"entries, expected {vector.shape[1]}")
        vector[i] = v


def load_replay(path: str | Path) -> Replay:
    """Load a replay written by ReplayRecorder (format 1, 2 or 3).

    A missing, truncated, damaged or malformed file, and a format-3 file whose content does
    not match its checksum, raise ConfigError naming the file and what is wrong with it."""
    name = str(path)
    where = f"replay {name!r}"
    arrays = read_npz(path, where, what="teamenv replay file")
    if "metadata" not in arrays:
        raise ConfigError(f"{where}: not a teamenv replay file (no metadata; it holds "
                          f"{sorted(arrays)})")
    try:
        meta = json.loads(arrays.pop("metadata").tobytes().decode("utf-8"))
    except (UnicodeDecodeError, ValueError, RecursionError) as exc:
        raise ConfigError(f"{where}: its metadata is not JSON text ({exc})") from None
    fmt = meta.get("format") if isinstance(meta, dict) else None
    if isinstance(fmt, bool) or fmt not in READABLE_FORMATS:
        raise ConfigError(f"{where}: format {value_repr(fmt if isinstance(meta, dict) else meta)}"
                          f", this teamenv reads formats {list(READABLE_FORMATS)}")
    wanted = ["ball", "players", "play_mode", "score", "time_s"]
    if fmt >= 2:
        wanted += _FORMAT_2_ARRAYS
    missing = [k for k in wanted if k not in arrays]
    if missing:
        raise ConfigError(f"{where}: format {fmt} but the array(s) {missing} are missing")
    if meta.get("extras"):
        wanted += [k for k in _EXTRA_ARRAYS if k in arrays]
    _check_shapes(name, {k: arrays[k] for k in wanted})
    if fmt >= 3:  # after the structure checks, whose messages say more about a hand-made file
        _check_checksum(where, arrays, meta)
    arrays = {k: arrays[k] for k in wanted}
    team_size = meta.get("team_size")
    if team_size is not None and team_size != arrays["players"].shape[1] // 2:
        raise ConfigError(f"{where}: metadata says team_size {value_repr(team_size)} but "
                          f"players holds {arrays['players'].shape[1]} players")
    if "belief_pose_error" in arrays:  # beliefs stored as errors from the truth
        error = _unquantise(arrays.pop("belief_pose_error"), POSE_ERROR_STEPS)
        pose = arrays["players"].astype(np.float32) + error
        pose[..., 2] = np.remainder(pose[..., 2] + np.pi, 2.0 * np.pi) - np.pi
        arrays["belief_pose"] = pose
    if "belief_ball_error" in arrays:
        error = _unquantise(arrays.pop("belief_ball_error"), POSE_ERROR_STEPS[:2])
        arrays["belief_ball"] = arrays["ball"][:, None, :2].astype(np.float32) + error
    known = {f.name for f in fields(Replay)}
    return Replay(metadata=meta, **{k: v for k, v in arrays.items() if k in known})


def _check_checksum(where: str, arrays: Mapping[str, np.ndarray], meta: dict[str, Any]) -> None:
    stored = meta.get(CHECKSUM_KEY)
    if not isinstance(stored, str):
        raise ConfigError(f"{where}: format {meta['format']} but its metadata has no "
                          f"{CHECKSUM_KEY!r} checksum (got {value_repr(stored)})")
    actual = replay_checksum(arrays, meta)
    if stored != actual:
        raise ConfigError(f"{where}: checksum mismatch: the content's SHA-256 is "
                          f"{actual[:16]}..., the file says {value_repr(stored, 24)}: it was "
                          "damaged or changed after it was written")


#: dtype kinds and trailing shape of each array (None: the 2N players; "T": rows; "N": N)
_ARRAY_SPECS: dict[str, tuple[str, tuple[Any, ...]]] = {
    "ball": ("f", ("T", 4)), "players": ("f", ("T", None, 3)), "play_mode": ("iu", ("T",)),
    "score": ("iu", ("T", 2)), "time_s": ("f", ("T",)), "attack_sign": ("iu", ("T",)),
    "fallen": ("b", ("T", None)), "say_bytes": ("iu", ("T", None)),
    "say_drops": ("iu", ("T", None)), "heard_from": ("iu", ("T", None)),
    "kick_cycle": ("iu", ("K",)), "kick_player": ("iu", ("K",)), "kick_distance": ("f", ("K",)),
    "kick_direction": ("f", ("K",)), "touch_cycle": ("iu", ("M",)),
    "touch_player": ("iu", ("M",)), "goal_cycle": ("iu", ("G",)), "goal_team": ("iu", ("G",)),
    "goal_player": ("iu", ("G",)), "belief_pose_error": ("iu", ("T", None, 3)),
    "belief_ball_error": ("iu", ("T", None, 2)), "role": ("iu", ("T", None)),
    "role_vector": ("iu", ("T", None, "N")), "belief_pose": ("f", ("T", None, 3)),
    "belief_ball": ("f", ("T", None, 2)),
}


def _check_shapes(name: str, arrays: dict[str, np.ndarray]) -> None:
    """Each array of the dtype kind and shape its name says (per-cycle arrays of time_s's
    length, players (T, 2N, 3), event arrays of one length per event kind); events point at
    recorded rows and real players."""
    t = len(arrays["time_s"]) if arrays["time_s"].ndim else 0
    players = arrays["players"]
    if players.ndim != 3 or players.shape[2] != 3 or players.shape[1] % 2 or \
            not players.shape[1]:
        raise ConfigError(f"replay {name!r}: players has shape {players.shape}, "
                          "expected (cycles, 2 x team size, 3)")
    sizes: dict[str, int] = {"T": t, "N": players.shape[1] // 2}
    for key, array in arrays.items():
        kinds, shape = _ARRAY_SPECS[key]
        if array.dtype.kind not in kinds:
            raise ConfigError(f"replay {name!r}: {key} has dtype {array.dtype}, expected "
                              f"{'a float' if kinds == 'f' else 'a bool' if kinds == 'b' else 'an integer'} "
                              "dtype")
        if array.ndim != len(shape):
            raise ConfigError(f"replay {name!r}: {key} has shape {array.shape}, expected "
                              f"{len(shape)} dimension(s)")
        for axis, (size, want) in enumerate(zip(array.shape, shape, strict=True)):
            if want is None:
                want = players.shape[1]
            if isinstance(want, str):
                if want not in sizes:
                    sizes[want] = size  # the first event array of a kind sets its count
                if size != sizes[want] and want == "T":
                    raise ConfigError(f"replay {name!r}: {key} has {size} rows but time_s "
                                      f"has {t}")
                if size != sizes[want]:
                    raise ConfigError(f"replay {name!r}: {key} has {size} entries on axis "
                                      f"{axis} but the other {key.split('_')[0]} arrays "
                                      f"{sizes[want]}")
            elif size != want:
                raise ConfigError(f"replay {name!r}: {key} has shape {array.shape}, expected "
                                  f"{want} on axis {axis}")
    for key in ("kick_cycle", "touch_cycle", "goal_cycle"):
        if key in arrays and arrays[key].size and (arrays[key].min() < 0 or
                                                   arrays[key].max() >= t):
            raise ConfigError(f"replay {name!r}: {key} points outside the {t} recorded cycles")
    n = players.shape[1]
    for key, low in (("kick_player", 0), ("touch_player", 0), ("goal_player", -1),
                     ("goal_team", 0)):
        high = 2 if key == "goal_team" else n
        if key in arrays and arrays[key].size and (arrays[key].min() < low or
                                                   arrays[key].max() >= high):
            raise ConfigError(f"replay {name!r}: {key} holds values outside [{low}, {high - 1}]")
