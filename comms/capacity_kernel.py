"""The compiled kernel of the `simspark` hearing model (`Channel._hear_by_capacity`): the
listener -> speaker offsets and distances, hearing range, hearing capacity per sender class in
arrival order, each listener's slots and the direction each message is heard from, in one loop
(numba) instead of some forty small NumPy operations of about a microsecond each.

It computes what the NumPy formulas computed, operation for operation, so every bit is the
same: differences of positions, the C library's `hypot` and `atan2` (NumPy's float64 `hypot`
and `portable_math.arctan2` call the same functions), Python's (= NumPy's) float remainder,
and products rounded one by one (no fused multiply-add, no fast-math). Imported on the first
delivery, not with `comms`: importing numba takes a few tenths of a second, compiling once
(then cached on disk) a few seconds.
"""

import math

import numpy as np

from portable_math.jit import numba  # SVML off: the same bits on every machine

_PI = math.pi
_TWO_PI = 2.0 * math.pi


# The squared distance is within a few ulp of hypot's square: outside this relative margin of
# the hearing range squared it decides `hypot(dx, dy) <= range` alone.
_MARGIN = 1e-9


@numba.njit(cache=True, inline="always")
def _within(dx: float, dy: float, hearing_range: float, near: float, far: float) -> bool:
    """`hypot(dx, dy) <= hearing_range` (False for NaN), the C library's hypot only where the
    squared distance is too close to the range's square to decide."""
    squared = dx * dx + dy * dy
    if squared < near:
        return True
    if squared > far:
        return False
    return math.hypot(dx, dy) <= hearing_range


@numba.njit(cache=True)
def hear_by_capacity(speakers, teams, positions, headings, hearing_range, capacity, cost,
                     self_echo, max_heard, quantum, pair_ids, pair_flags, pair_directions,
                     out_of_range, over):
    """Who hears which message: per listener its own message (when `self_echo`), then its
    teammates', then its opponents', each class in arrival order, within hearing range and
    (`cost` > 0) within the listener's hearing capacity of that class, at most `max_heard`;
    and the direction each is heard from.

    speakers (S,) agent ids in arrival order; teams (N,) 0/1; positions (N, 2), headings (N,)
    every agent's; a message is out of range unless its distance is <=
    `hearing_range` (so NaN is out); capacity (2, N) int64, row 0 teammates, row 1 opponents,
    decreased by `cost` per message heard (`cost` 0: no capacity); quantum: the profile's
    direction step in degrees (0: none).

    Fills the first P columns of pair_ids (2, N * max_heard) intp with (listener, speaker
    slot), pair_flags (2, ...) bool with (is_self, teammate) and pair_directions (P,) float64
    with the direction (rad, listener frame, wrapped to [-pi, pi), 0 for its own message) of
    every pair heard, sorted by listener and in slot order; `out_of_range` (S, N) bool and
    `over` (2, S, N) bool, zeros on entry, with the messages out of range, over capacity and
    over `max_heard`. The caller allocates the outputs (a NumPy array returned from a kernel
    costs about a microsecond more). Returns (P, any out of range, any over capacity, any over
    max_heard).
    """
    n_spk = speakers.shape[0]
    n = teams.shape[0]
    any_out = False
    any_over_capacity = False
    any_over_max = False
    count = 0
    near = hearing_range * hearing_range * (1.0 - _MARGIN)
    far = hearing_range * hearing_range * (1.0 + _MARGIN)
    to_steps = 180.0 / _PI / quantum if quantum > 0.0 else 0.0
    step = quantum * _PI / 180.0
    for li in range(n):
        allowed_mate = capacity[0, li] // cost if cost > 0 else n_spk
        allowed_opp = capacity[1, li] // cost if cost > 0 else n_spk
        heard_mate = 0
        heard_opp = 0
        slots = 0
        # pass 0: own message; pass 1: teammates; pass 2: opponents (range checked in pass 1)
        for kind in range(3):
            if kind == 0 and not self_echo:
                continue
            for s in range(n_spk):
                speaker = speakers[s]
                own = speaker == li
                rel_x = positions[speaker, 0] - positions[li, 0]
                rel_y = positions[speaker, 1] - positions[li, 1]
                if kind == 0:
                    if not own:
                        continue
                else:
                    if own:
                        continue
                    same = teams[speaker] == teams[li]
                    if (kind == 1) != same:
                        continue
                    if not _within(rel_x, rel_y, hearing_range, near, far):
                        out_of_range[s, li] = True
                        any_out = True
                        continue
                    if kind == 1:
                        heard_mate += 1
                        if heard_mate > allowed_mate:
                            over[0, s, li] = True
                            any_over_capacity = True
                            continue
                    else:
                        heard_opp += 1
                        if heard_opp > allowed_opp:
                            over[0, s, li] = True
                            any_over_capacity = True
                            continue
                if slots >= max_heard:
                    over[1, s, li] = True
                    any_over_max = True
                    continue
                slots += 1
                pair_ids[0, count] = li
                pair_ids[1, count] = s
                pair_flags[0, count] = own
                pair_flags[1, count] = own or kind == 1
                if own:
                    direction = 0.0
                else:
                    direction = math.atan2(rel_y, rel_x) - headings[li]
                    direction = (direction + _PI) % _TWO_PI - _PI
                    if quantum > 0.0:
                        direction = np.trunc(direction * to_steps) * step
                pair_directions[count] = direction
                count += 1
        if cost > 0:
            capacity[0, li] -= cost * min(heard_mate, allowed_mate)
            capacity[1, li] -= cost * min(heard_opp, allowed_opp)
    return count, any_out, any_over_capacity, any_over_max
