"""When a T1 on the league server counts as fallen, from the torso pose it perceives.

One test for everyone who asks: the adapter (a fall cancels a kick and starts the get-up), the
get-up motion (is it up again), the walk/kick/get-up trials, the replay recorder and the
vision observation's ``body`` row. It imports only the perception types, so all of them can
import it (it lived in observation.py, which imports the adapter: a cycle).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from .perception import Perception

#: torso tilt (rad from upright) beyond which a robot counts as fallen (our walker leans
#: up to ~40° while starting and recovers: not a fall)
FALL_TILT = math.radians(60.0)
#: torso height (m) under which a robot counts as fallen (it stands at ~0.66 m)
FALL_HEIGHT_M = 0.4


def torso_down(quat: Sequence[float], height: float) -> bool:
    """Torso (quaternion w, x, y, z; height m) tilted beyond ``FALL_TILT`` or lower than
    ``FALL_HEIGHT_M``."""
    _, x, y, _ = quat
    up_z = 1.0 - 2.0 * (x * x + y * y)  # z of the torso's up axis in the world
    return up_z < math.cos(FALL_TILT) or height < FALL_HEIGHT_M


def is_fallen(p: Perception) -> bool:
    """``torso_down`` of the perceived torso (False when the perception has no torso pose)."""
    q = p.orientations.get("torso_quat")
    pos = p.positions.get("torso_pos")
    if q is None or pos is None:
        return False
    return torso_down(q, pos[2])
