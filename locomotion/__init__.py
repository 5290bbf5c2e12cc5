"""Humanoid locomotion model (walk, kick, fall) and robot profiles; must not import teamenv, strategy or comms.

Public API (see docs/CONTRACTS.md, "Locomotion"):

* :func:`load_profile` -- a validated :class:`Profile` by name (shipped, or added to
  :data:`PROFILES`, a ``paramkit.Registry``) or path;
* :class:`Bodies` -- vectorised per-cycle walk/kick/fall state of all players;
* :func:`omni_displacement` -- seed 001 eq. 4 in a form exact as the turn rate goes to 0.

The brax/MuJoCo humanoid used to measure profiles lives in :mod:`locomotion.humanoid` and is
imported only on demand (``pip install -e '.[humanoid]'``).
"""

from __future__ import annotations

from .bodies import Bodies, StepResult
from .errors import LocomotionError, ProfileError, StepInputError
from .profile import PROFILES, Profile, load_profile, profile_from_dict, shipped_profiles
from .walk import apply_envelope, omni_displacement

__all__ = [
    "Bodies",
    "StepResult",
    "PROFILES",
    "Profile",
    "load_profile",
    "profile_from_dict",
    "shipped_profiles",
    "omni_displacement",
    "apply_envelope",
    "LocomotionError",
    "ProfileError",
    "StepInputError",
]
