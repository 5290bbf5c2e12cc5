"""Action validation and conversion: Dict or flat-Box actions of many agents -> Commands arrays.

Strict mode raises ActionError/MessageError naming the agent, field and value. Lenient mode
never raises for a bad value: a non-finite or malformed field is dropped (its default is used),
an out-of-range number is clipped, an illegal message is not sent; every such drop is listed in
that agent's ``infos["dropped"]`` and a warning is issued.
"""

from __future__ import annotations

import numbers
import warnings
from collections.abc import Mapping
from typing import Any

import numpy as np

from teamenv.box_layout import (
    ACTION_SIZE,
    KICK_HIGH,
    KICK_LOW,
    beam_bounds,
    decode_box_actions,
)
from teamenv.errors import ActionError, MessageError, value_repr
from teamenv.field import FieldSpec
from teamenv.sim.simulation import Commands

DICT_KEYS = ("walk", "kick", "beam", "beam_request", "say")
_FAST_KEYS = frozenset(DICT_KEYS)
_FLAG_TYPES = frozenset({bool, int, np.bool_})  # beam_request values the fast path reads
_DICT = {dict}
_STR = {str}
_SILENCE_OR_STR = frozenset({str, type(None)})
_KERNEL_FLOATS = (np.dtype(np.float64), np.dtype(np.float32))  # read by the Box kernel as they are
_REAL_KINDS = frozenset("biuf")  # numpy dtype kinds of real numbers: bool, int, uint, float


class ActionParser:
    """Turns the caller's per-agent actions into rows of a Commands object."""

    def __init__(self, field: FieldSpec, command_low: np.ndarray, command_high: np.ndarray,
                 channel: Any, action_format: str, strict: bool) -> None:
        self.field = field
        self.walk_low = np.asarray(command_low, dtype=float)
        self.walk_high = np.asarray(command_high, dtype=float)
        self.kick_low = np.array(KICK_LOW)
        self.kick_high = np.array(KICK_HIGH)
        self.beam_low, self.beam_high = map(np.array, beam_bounds(field.half_length,
                                                                 field.half_width))
        # Tolerant bounds of the fast path (NaN and inf fail them too).
        self._walk_lo, self._walk_hi = self.walk_low - 1e-6, self.walk_high + 1e-6
        self._kick_lo, self._kick_hi = self.kick_low - 1e-6, self.kick_high + 1e-6
        self._beam_lo, self._beam_hi = self.beam_low - 1e-6, self.beam_high + 1e-6
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
            for row, agent, action in zip(rows, agents, actions, strict=True):
                self._fill_dict(cmd, row, agent, action, dropped)

    def _fill_dict_fast(self, cmd: Commands, rows: list[int], actions: list[Any]) -> bool:
        """Vectorized path for the common case (valid values of known keys). Returns False,
        touching nothing, when anything is unusual; the per-agent path then names the fault."""
        if set(map(type, actions)) != _DICT:
            return False
        keys = actions[0].keys()
        try:
            # Every agent gives the same keys (the usual case): gather column by column.
            # Same size as the first dict and holding each of its keys = the same keys.
            if not keys <= _FAST_KEYS or len(set(map(len, actions))) != 1:
                raise KeyError
            walk_rows = kick_rows = beam_rows = flag_rows = rows
            walks = [action["walk"] for action in actions] if "walk" in keys else []
            kicks = [action["kick"] for action in actions] if "kick" in keys else []
            beams = [action["beam"] for action in actions] if "beam" in keys else []
            flags = [action["beam_request"] for action in actions] \
                if "beam_request" in keys else []
            texts = [action["say"] for action in actions] if "say" in keys else []
        except KeyError:
            texts = None
        if texts is not None:
            # Only str (or None) texts stay on this path: truth-testing anything else may
            # raise (a numpy array's truth value is ambiguous) or mean something else.
            if not texts:  # no "say" key
                says = []
            elif (kinds := set(map(type, texts))) == _STR and all(texts):  # every agent talks
                says = list(zip(rows, texts, strict=True))
            elif kinds <= _SILENCE_OR_STR:
                says = [(row, text) for row, text in zip(rows, texts, strict=True) if text]
            else:
                return False  # the per-agent path names the fault (or takes a str subclass)
        else:
            # key sets differ: each key's rows and values, agent by agent
            columns: dict[str, tuple[list[int], list[Any]]] = {
                key: ([], []) for key in ("walk", "kick", "beam", "beam_request")}
            says = []
            fast_keys = _FAST_KEYS
            for row, action in zip(rows, actions, strict=True):
                if not fast_keys.issuperset(action):
                    return False
                for key, (key_rows, values) in columns.items():
                    if key in action:
                        key_rows.append(row)
                        values.append(action[key])
                text = action.get("say")
                if type(text) is str:
                    if text:
                        says.append((row, text))
                elif text is not None:
                    return False  # not a str: the per-agent path names the fault
            (walk_rows, walks), (kick_rows, kicks), (beam_rows, beams), (flag_rows, flags) = \
                columns.values()
        # Real numbers of the exact shape only (numpy would parse text, drop an imaginary
        # part or reshape (3, 1)); the per-agent path names any fault.
        walk = _real_rows(walks, 3)
        kick = _real_rows(kicks, 2)
        beam = _real_rows(beams, 3)
        if walk is None or kick is None or beam is None:
            return False
        # In range (with the 1e-6 tolerance) also means finite: NaN fails both comparisons.
        if walks and not ((walk >= self._walk_lo) & (walk <= self._walk_hi)).all():
            return False
        if kicks and not ((kick >= self._kick_lo) & (kick <= self._kick_hi)).all():
            return False
        if beams and not ((beam >= self._beam_lo) & (beam <= self._beam_hi)).all():
            return False
        # beam_request: bool, numpy bool or the int 0 or 1 (other forms: the per-agent path)
        if flags and not (set(map(type, flags)) <= _FLAG_TYPES
                          and all(flag in (0, 1) for flag in flags)):
            return False
        # Legal non-empty str texts, all in one match (False for a non-str: path below names it).
        if says and not self._all_legal([text for _, text in says]):
            return False
        if walk_rows is rows and type(rows) is list and _is_range(rows):  # rows 0..k-1: a slice
            walk_rows = kick_rows = beam_rows = flag_rows = slice(0, len(rows))
            if len(says) == len(rows):
                cmd.say[:len(rows)] = [text for _, text in says]
                says = []
        if walks:
            cmd.walk[walk_rows] = walk
        if kicks:
            cmd.kick_power[kick_rows] = kick[:, 0]
            cmd.kick_dir[kick_rows] = kick[:, 1]
        if beams:
            cmd.beam[beam_rows] = beam
        if flags:
            cmd.beam_request[flag_rows] = [bool(flag) for flag in flags]
        say = cmd.say
        for row, text in says:
            say[row] = text
        return True

    # -- flat Box --------------------------------------------------------------------------
    def _fill_box(self, cmd: Commands, rows: list[int], agents: list[str], actions: list[Any],
                  dropped: dict[str, list[str]]) -> None:
        arr = _real_rows(actions, ACTION_SIZE)
        idx = np.asarray(rows)
        if arr is not None and arr.dtype.kind not in "iu" and arr.dtype not in _KERNEL_FLOATS:
            arr = arr.astype(float)  # bool, float16, longdouble: as the NumPy path reads them
        if arr is not None and _box_kernel()(
                arr, idx, self.walk_low, self.walk_high, self.field.half_length,
                self.field.half_width, cmd.walk, cmd.kick_power, cmd.kick_dir,
                cmd.beam_request, cmd.beam):
            return  # every action finite and in range: decoded in one compiled pass
        if arr is None:
            arr = np.zeros((len(agents), ACTION_SIZE))
            for k, (agent, action) in enumerate(zip(agents, actions, strict=True)):
                arr[k] = self._box_row(agent, action, dropped)
        else:
            arr = arr.astype(float)  # a copy in float64, the dtype of every result below
        bad = ~np.isfinite(arr)
        if bad.any():
            for k, j in np.argwhere(bad):  # each bad entry of each agent (strict: the first)
                self._problem(agents[k], f"action[{j}]", float(arr[k, j]), "must be finite",
                              dropped)
            arr[bad] = 0.0
        out = (arr < -1.0 - 1e-6) | (arr > 1.0 + 1e-6)
        if out.any():
            for k, j in np.argwhere(out):
                self._problem(agents[k], f"action[{j}]", float(arr[k, j]),
                              "must be in [-1, 1]; clipped in lenient mode", dropped)
            arr = np.clip(arr, -1.0, 1.0)
        decoded = decode_box_actions(arr, self.walk_low, self.walk_high, self.field.half_length,
                                     self.field.half_width)
        cmd.walk[idx] = decoded.walk
        cmd.kick_power[idx] = decoded.kick_power
        cmd.kick_dir[idx] = decoded.kick_direction
        cmd.beam_request[idx] = decoded.beam_request
        cmd.beam[idx] = decoded.beam

    def _box_row(self, agent: str, action: Any, dropped: dict[str, list[str]]) -> np.ndarray:
        row, why = real_numbers(action, ACTION_SIZE)
        if row is None:
            self._problem(agent, "action", action, f"{why} (the flat Box action)", dropped)
            return np.zeros(ACTION_SIZE)
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
                self._problem(agent, value_repr(key), action[key],
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
            if text is None:
                return
            if not isinstance(text, str):  # tested first: `text == ""` on an array is an array
                self._problem(agent, "say", text, "must be a str (None or \"\" is silence)", dropped,
                              MessageError)
                return
            if not text:
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
        arr, why = real_numbers(value, size)
        if arr is None:
            self._problem(agent, name, value, why, dropped)
            return None
        if not np.isfinite(arr).all():
            self._problem(agent, name, value, "must be finite (no NaN/inf)", dropped)
            return None
        if ((arr < low - 1e-6) | (arr > high + 1e-6)).any():
            self._problem(agent, name, value,
                          f"out of range (low [{_fmt(low)}], high [{_fmt(high)}]); clipped in "
                          "lenient mode",
                          dropped)
            return np.clip(arr, low, high)
        return arr

    def _problem(self, agent: str, field: str, value: Any, why: str,
                 dropped: dict[str, list[str]], error: type[ActionError] = ActionError) -> None:
        message = f"agent {agent!r}: {field} = {value_repr(value)}: {why}"
        if self.strict:
            raise error(message)
        dropped.setdefault(agent, []).append(message)
        warnings.warn(message, RuntimeWarning, stacklevel=4)


_RANGES: dict[int, list[int]] = {}


def real_numbers(value: Any, size: int) -> tuple[np.ndarray | None, str]:
    """``value`` as a float64 array of shape ``(size,)``, or ``(None, why not)``.

    Real numbers only: bool, int, float (Python or numpy), in a sequence or an array. Text,
    bytes, complex numbers, dates and objects are refused although numpy would convert some
    of them (``"0.5"`` -> 0.5, ``1+2j`` -> 1.0 with a warning); so are other shapes (also
    ``(size, 1)``, which a reshape would accept)."""
    try:
        raw = np.asarray(value)
    except (TypeError, ValueError, OverflowError):  # ragged nesting, unconvertible objects
        return None, f"must be {size} real numbers"
    kind = raw.dtype.kind
    if kind == "O":  # Python objects: ints too large for int64, None, fractions, mixtures
        if not all(isinstance(v, (numbers.Real, np.bool_)) for v in raw.flat):
            return None, f"must be {size} real numbers"
        try:
            arr = raw.astype(float)
        except OverflowError:
            return None, "must be finite (no NaN/inf): a number too large for a float"
    elif kind in _REAL_KINDS:
        arr = raw.astype(float, copy=False)
    else:
        return None, f"must be {size} real numbers, not {_kind_name(raw.dtype)}"
    if arr.shape != (size,):
        return None, f"must have shape ({size},), got {arr.shape}"
    return arr, ""


def _box_kernel():
    """The compiled Box decoder, imported on the first Box action: importing numba takes a
    few tenths of a second that ``import teamenv`` should not pay."""
    from teamenv.box_kernel import fill_box_rows

    return fill_box_rows


def _kind_name(dtype: np.dtype) -> str:
    names = {"c": "complex numbers", "U": "text", "S": "bytes", "M": "dates", "m": "durations"}
    return names.get(dtype.kind, f"dtype {dtype}")


def _real_rows(values: list[Any], size: int) -> np.ndarray | None:
    """The fast paths' conversion: ``values`` (one entry per agent) as a ``(len, size)`` array
    of real numbers in their own dtype (float32 stays float32), or None when anything is off;
    the per-agent path then names the fault."""
    if not values:
        return np.empty((0, size))
    try:
        arr = np.asarray(values)
    except (TypeError, ValueError, OverflowError):
        return None
    if arr.dtype.kind not in _REAL_KINDS or arr.shape != (len(values), size):
        return None
    return arr


def _is_range(rows: list[int]) -> bool:
    """True when ``rows`` is [0, 1, ..., len(rows) - 1]."""
    k = len(rows)
    ref = _RANGES.get(k)
    if ref is None:
        ref = _RANGES[k] = list(range(k))
    return rows == ref


def _fmt(arr: np.ndarray) -> str:
    return ", ".join(f"{v:.3g}" for v in arr)
