"""Action validation and conversion: Dict or flat-Box actions of many agents -> Commands arrays.

Strict mode raises ActionError/MessageError naming the agent, field and value. Lenient mode
never raises for a bad value: a non-finite or malformed field is dropped (its default is used),
an out-of-range number is clipped, an illegal message is not sent; every such drop is listed in
that agent's ``infos["dropped"]`` and a warning is issued.
"""

from __future__ import annotations

import math
import warnings
from typing import Any, Mapping

import numpy as np

from teamenv.errors import ActionError, MessageError
from teamenv.field import FieldSpec
from teamenv.sim.simulation import Commands

DICT_KEYS = ("walk", "kick", "beam", "beam_request", "say")
_FAST_KEYS = frozenset({"walk", "kick", "say"})
_DICT = {dict}
BOX_SIZE = 9


class ActionParser:
    """Turns the caller's per-agent actions into rows of a Commands object."""

    def __init__(self, field: FieldSpec, command_low: np.ndarray, command_high: np.ndarray,
                 channel: Any, action_format: str, strict: bool) -> None:
        self.field = field
        self.walk_low = np.asarray(command_low, dtype=float)
        self.walk_high = np.asarray(command_high, dtype=float)
        self.kick_low = np.array([0.0, -math.pi])
        self.kick_high = np.array([1.0, math.pi])
        self.beam_low = np.array([-field.half_length, -field.half_width, -math.pi])
        self.beam_high = np.array([0.0, field.half_width, math.pi])
        # Tolerant bounds of the fast path (NaN and inf fail them too).
        self._walk_lo, self._walk_hi = self.walk_low - 1e-6, self.walk_high + 1e-6
        self._kick_lo, self._kick_hi = self.kick_low - 1e-6, self.kick_high + 1e-6
        self.channel = channel
        profile = getattr(channel, "profile", None)
        self._all_legal = profile.all_legal if hasattr(profile, "all_legal") else (
            lambda texts: all(isinstance(t, str) and channel.check_message(t) is None
                              for t in texts))
        self.action_format = action_format
        self.strict = strict

    # -- public ----------------------------------------------------------------------------
    def fill(self, cmd: Commands, rows: list[int], agents: list[str], actions: list[Any],
             dropped: dict[str, list[str]]) -> None:
        """Write the actions of ``agents`` (player rows ``rows``) into ``cmd``."""
        if not agents:
            return
        if self.action_format == "box":
            self._fill_box(cmd, rows, agents, actions, dropped)
        elif not self._fill_dict_fast(cmd, rows, actions):
            for row, agent, action in zip(rows, agents, actions):
                self._fill_dict(cmd, row, agent, action, dropped)

    def _fill_dict_fast(self, cmd: Commands, rows: list[int], actions: list[Any]) -> bool:
        """Vectorized path for the common case (only valid walk/kick/say keys). Returns False,
        touching nothing, when anything is unusual; the per-agent path then names the fault."""
        if set(map(type, actions)) != _DICT:
            return False
        keys = actions[0].keys()
        try:
            # Every agent gives the same keys (the usual case): gather column by column.
            # Same size as the first dict and holding each of its keys = the same keys.
            if not keys <= _FAST_KEYS or len(set(map(len, actions))) != 1:
                raise KeyError
            walk_rows = kick_rows = rows
            walks = [action["walk"] for action in actions] if "walk" in keys else []
            kicks = [action["kick"] for action in actions] if "kick" in keys else []
            texts = [action["say"] for action in actions] if "say" in keys else []
        except KeyError:
            texts = None
        if texts is not None:
            if not texts:  # no "say" key
                says = []
            elif all(texts):
                says = list(zip(rows, texts, strict=True))
            else:
                if any(not _silence(text) for text in texts if not text):
                    return False  # a falsy non-str (0, b"", []): the per-agent path rejects it
                says = [(row, text) for row, text in zip(rows, texts, strict=True) if text]
        else:
            walk_rows, walks, kick_rows, kicks, says = [], [], [], [], []
            fast_keys = _FAST_KEYS
            for row, action in zip(rows, actions, strict=True):
                if not fast_keys.issuperset(action):
                    return False
                if "walk" in action:
                    walk_rows.append(row)
                    walks.append(action["walk"])
                if "kick" in action:
                    kick_rows.append(row)
                    kicks.append(action["kick"])
                text = action.get("say")
                if text:
                    says.append((row, text))
                elif not _silence(text):
                    return False  # a falsy non-str: the per-agent path rejects it
        try:
            walk = np.asarray(walks, dtype=float).reshape(len(walks), 3)
            kick = np.asarray(kicks, dtype=float).reshape(len(kicks), 2)
        except (TypeError, ValueError):
            return False
        # In range (with the 1e-6 tolerance) also means finite: NaN fails both comparisons.
        if walks and not ((walk >= self._walk_lo) & (walk <= self._walk_hi)).all():
            return False
        if kicks and not ((kick >= self._kick_lo) & (kick <= self._kick_hi)).all():
            return False
        # Legal non-empty str texts, all in one match (False for a non-str: path below names it).
        if says and not self._all_legal([text for _, text in says]):
            return False
        if walk_rows is rows and type(rows) is list and _is_range(rows):  # rows 0..k-1: a slice
            walk_rows = kick_rows = slice(0, len(rows))
            if len(says) == len(rows):
                cmd.say[:len(rows)] = [text for _, text in says]
                says = []
        if walks:
            cmd.walk[walk_rows] = walk
        if kicks:
            cmd.kick_power[kick_rows] = kick[:, 0]
            cmd.kick_dir[kick_rows] = kick[:, 1]
        say = cmd.say
        for row, text in says:
            say[row] = text
        return True

    # -- flat Box --------------------------------------------------------------------------
    def _fill_box(self, cmd: Commands, rows: list[int], agents: list[str], actions: list[Any],
                  dropped: dict[str, list[str]]) -> None:
        try:
            arr = np.asarray(actions, dtype=float)
        except (TypeError, ValueError):
            arr = None
        if arr is None or arr.shape != (len(agents), BOX_SIZE):
            arr = np.zeros((len(agents), BOX_SIZE))
            for k, (agent, action) in enumerate(zip(agents, actions)):
                arr[k] = self._box_row(agent, action, dropped)
        bad = ~np.isfinite(arr)
        if bad.any():
            k, j = np.argwhere(bad)[0]
            self._problem(agents[k], f"action[{j}]", arr[k, j], "must be finite", dropped)
            arr[bad] = 0.0
        out = (arr < -1.0 - 1e-6) | (arr > 1.0 + 1e-6)
        if out.any():
            k, j = np.argwhere(out)[0]
            self._problem(agents[k], f"action[{j}]", arr[k, j], "must be in [-1, 1]", dropped)
            arr = np.clip(arr, -1.0, 1.0)
        idx = np.asarray(rows)
        vx = np.where(arr[:, 0] >= 0, arr[:, 0] * self.walk_high[0], -arr[:, 0] * self.walk_low[0])
        vy = np.where(arr[:, 1] >= 0, arr[:, 1] * self.walk_high[1], -arr[:, 1] * self.walk_low[1])
        vt = np.where(arr[:, 2] >= 0, arr[:, 2] * self.walk_high[2], -arr[:, 2] * self.walk_low[2])
        cmd.walk[idx] = np.stack([vx, vy, vt], axis=1)
        cmd.kick_power[idx] = np.maximum(arr[:, 3], 0.0)
        cmd.kick_dir[idx] = arr[:, 4] * math.pi
        cmd.beam_request[idx] = arr[:, 5] > 0.0
        cmd.beam[idx, 0] = (arr[:, 6] - 1.0) * 0.5 * self.field.half_length
        cmd.beam[idx, 1] = arr[:, 7] * self.field.half_width
        cmd.beam[idx, 2] = arr[:, 8] * math.pi

    def _box_row(self, agent: str, action: Any, dropped: dict[str, list[str]]) -> np.ndarray:
        try:
            row = np.asarray(action, dtype=float)
        except (TypeError, ValueError):
            row = None
        if row is None or row.shape != (BOX_SIZE,):
            shape = getattr(row, "shape", None)
            self._problem(agent, "action", action if row is None else f"shape {shape}",
                          f"must be a float array of shape ({BOX_SIZE},)", dropped)
            return np.zeros(BOX_SIZE)
        return row

    # -- Dict ------------------------------------------------------------------------------
    def _fill_dict(self, cmd: Commands, row: int, agent: str, action: Any,
                   dropped: dict[str, list[str]]) -> None:
        if not isinstance(action, Mapping):
            self._problem(agent, "action", action, "must be a dict with keys " + str(DICT_KEYS),
                          dropped)
            return
        for key in action:
            if key not in DICT_KEYS:
                self._problem(agent, repr(key), action[key],
                              f"unknown action key; known keys are {DICT_KEYS}", dropped)
        if "walk" in action:
            value = self._vector(agent, "walk", action["walk"], 3, self.walk_low, self.walk_high,
                                 dropped)
            if value is not None:
                cmd.walk[row] = value
        if "kick" in action:
            value = self._vector(agent, "kick", action["kick"], 2, self.kick_low, self.kick_high,
                                 dropped)
            if value is not None:
                cmd.kick_power[row], cmd.kick_dir[row] = value
        if "beam" in action:
            value = self._vector(agent, "beam", action["beam"], 3, self.beam_low, self.beam_high,
                                 dropped)
            if value is not None:
                cmd.beam[row] = value
        if "beam_request" in action:
            flag = action["beam_request"]
            if isinstance(flag, (bool, np.bool_)) or (
                    isinstance(flag, (int, np.integer)) and int(flag) in (0, 1)):
                cmd.beam_request[row] = bool(flag)
            else:
                self._problem(agent, "beam_request", flag, "must be 0 or 1", dropped)
        if "say" in action:
            text = action["say"]
            if text is None or text == "":
                return
            if not isinstance(text, str):
                self._problem(agent, "say", text, "must be a str", dropped, MessageError)
                return
            reason = self.channel.check_message(text)
            if reason is not None:
                self._problem(agent, "say", text,
                              f"breaks the {self.channel.profile.name} channel's rules ({reason}); "
                              "the league drops such a message whole", dropped, MessageError)
                return
            cmd.say[row] = text

    def _vector(self, agent: str, name: str, value: Any, size: int, low: np.ndarray,
                high: np.ndarray, dropped: dict[str, list[str]]) -> np.ndarray | None:
        try:
            arr = np.asarray(value, dtype=float)
        except (TypeError, ValueError):
            self._problem(agent, name, value, f"must be {size} numbers", dropped)
            return None
        if arr.shape != (size,):
            self._problem(agent, name, value, f"must have shape ({size},), got {arr.shape}",
                          dropped)
            return None
        if not np.isfinite(arr).all():
            self._problem(agent, name, value, "must be finite (no NaN/inf)", dropped)
            return None
        if ((arr < low - 1e-6) | (arr > high + 1e-6)).any():
            self._problem(agent, name, value,
                          f"out of range [{_fmt(low)}, {_fmt(high)}]; clipped in lenient mode",
                          dropped)
            return np.clip(arr, low, high)
        return arr

    def _problem(self, agent: str, field: str, value: Any, why: str,
                 dropped: dict[str, list[str]], error: type[ActionError] = ActionError) -> None:
        message = f"agent {agent!r}: {field} = {_short(value)}: {why}"
        if self.strict:
            raise error(message)
        dropped.setdefault(agent, []).append(message)
        warnings.warn(message, RuntimeWarning, stacklevel=4)


_RANGES: dict[int, list[int]] = {}


def _silence(text: Any) -> bool:
    """A falsy ``say`` the per-agent path takes as silence (None or ""), not as bad input."""
    return text is None or type(text) is str


def _is_range(rows: list[int]) -> bool:
    """True when ``rows`` is [0, 1, ..., len(rows) - 1]."""
    k = len(rows)
    ref = _RANGES.get(k)
    if ref is None:
        ref = _RANGES[k] = list(range(k))
    return rows == ref


def _fmt(arr: np.ndarray) -> str:
    return ", ".join(f"{v:.3g}" for v in arr)


def _short(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 80 else text[:77] + "..."
