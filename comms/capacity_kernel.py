"""The compiled kernel of the `simspark` hearing model (`Channel._hear_by_capacity`): hearing
capacity per sender class in arrival order, then each listener's slots, in one loop (numba)
instead of some twenty small NumPy operations of about a microsecond each.

Integer and boolean work only, plus copying the listener -> speaker offsets of the pairs heard:
no float arithmetic, so nothing can round differently. Imported on the first delivery, not
with `comms`: importing numba takes a few tenths of a second, compiling once (then cached on
disk) a few seconds.
"""

import numba


@numba.njit(cache=True)
def hear_by_capacity(speakers, teams, dist, hearing_range, rel_x, rel_y, capacity, cost,
                     self_echo, max_heard, pair_ids, pair_flags, pair_offsets, over):
    """Who hears which message: per listener its own message (when `self_echo`), then its
    teammates', then its opponents', each class in arrival order, within hearing range and
    (`cost` > 0) within the listener's hearing capacity of that class, at most `max_heard`.

    speakers (S,) agent ids in arrival order; teams (N,) 0/1; dist (S, N) listener -> speaker
    distances, out of range unless <= `hearing_range` (so NaN is out); rel_x, rel_y (S, N)
    listener -> speaker offsets; capacity (2, N) int64, row 0 teammates, row 1 opponents,
    decreased by `cost` per message heard (`cost` 0: no capacity).

    Fills the first P columns of pair_ids (2, N * max_heard) intp with (listener, speaker
    slot), pair_flags (2, ...) bool with (is_self, teammate) and pair_offsets (2, ...)
    float64 with the (y, x) offset of every pair heard, sorted by listener and in slot order;
    `over` (2, S, N) bool, zeros on entry, with the messages over capacity and over
    `max_heard`. The caller allocates the outputs (a NumPy array returned from a kernel
    costs about a microsecond more). Returns (P, any over capacity, any over max_heard).
    """
    n_spk = speakers.shape[0]
    n = teams.shape[0]
    any_over_capacity = False
    any_over_max = False
    count = 0
    for li in range(n):
        allowed_mate = capacity[0, li] // cost if cost > 0 else n_spk
        allowed_opp = capacity[1, li] // cost if cost > 0 else n_spk
        heard_mate = 0
        heard_opp = 0
        slots = 0
        # pass 0: own message; pass 1: teammates; pass 2: opponents
        for kind in range(3):
            if kind == 0 and not self_echo:
                continue
            for s in range(n_spk):
                speaker = speakers[s]
                own = speaker == li
                if kind == 0:
                    if not own:
                        continue
                else:
                    if own or not dist[s, li] <= hearing_range:
                        continue
                    same = teams[speaker] == teams[li]
                    if (kind == 1) != same:
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
                pair_offsets[0, count] = rel_y[s, li]
                pair_offsets[1, count] = rel_x[s, li]
                count += 1
        if cost > 0:
            capacity[0, li] -= cost * min(heard_mate, allowed_mate)
            capacity[1, li] -= cost * min(heard_opp, allowed_opp)
    return count, any_over_capacity, any_over_max
