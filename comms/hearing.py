"""The channel's two hearing models as formulas on plain values, for reading and testing:
`mj`'s volume falling with distance and its random loss of quiet messages, `simspark`'s
per-listener hearing capacity. `comms.channel.Channel` applies the same rules to a whole
cycle's arrays at once."""

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

import portable_math as pm
from comms.profiles import HearingCapacity


def received_volume(
    volume: Any, distance_m: Any, db_per_doubling: float = 6.0, reference_m: float = 1.0
) -> np.ndarray:
    """Volume (percent) at which a message said at `volume` arrives `distance_m` metres away.

    Falls `db_per_doubling` dB (amplitude) per doubling of distance beyond `reference_m`
    (RCSSServerMJ: 6 dB, 1 m, i.e. roughly volume / distance).
    """
    d = np.maximum(np.asarray(distance_m, dtype=np.float64), reference_m)
    return np.asarray(volume, dtype=np.float64) * pm.power(
        10.0, -db_per_doubling * pm.log2(d / reference_m) / 20.0
    )


def loss_probability(
    received: Any,
    max_volume: float = 100.0,
    midpoint_m: float = 50.0,
    db_per_doubling: float = 6.0,
    reference_m: float = 1.0,
) -> np.ndarray:
    """`mj`: probability that a message arriving at volume `received` is lost.

    RCSSServerMJ's distance-based loss p = 0.5 tanh(pi d / midpoint - pi) + 0.5, evaluated at
    the distance from which a max-volume message would arrive this loud (so for volume 100 it
    is the true distance: 25 m 4 %, 40 m 22 %, 50 m 50 %, 60 m 78 %, 75 m 96 %).
    """
    rec = np.asarray(received, dtype=np.float64)
    with np.errstate(divide="ignore"):
        d_eff = reference_m * pm.exp2(-20.0 * pm.log10(rec / max_volume) / db_per_doubling)
    return 0.5 * pm.tanh(math.pi * d_eff / midpoint_m - math.pi) + 0.5


def hearing_capacity_trace(
    arrivals: Sequence[int], capacity: HearingCapacity | None = None
) -> list[int]:
    """How many messages of one sender class (teammates or opponents) one listener hears.

    `arrivals[t]`: messages of that class arriving in cycle t (within range). Returns the
    number heard in each cycle. Same rule as the channel: the counter starts at `maximum`,
    gains `increment` at the start of every cycle (capped), and each message heard needs and
    costs `cost`; messages beyond that are dropped in arrival order. Default: the league's
    HearingCapacity(maximum=2, increment=1, cost=2).
    """
    if capacity is None:
        capacity = HearingCapacity()
    cap = capacity.maximum
    out = []
    for a in arrivals:
        cap = min(cap + capacity.increment, capacity.maximum)
        k = min(int(a), cap // capacity.cost)
        cap -= k * capacity.cost
        out.append(k)
    return out
