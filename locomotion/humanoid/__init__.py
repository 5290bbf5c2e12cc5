"""The humanoid extra: the league's T1 in brax (and native MuJoCo) to measure locomotion profiles.

Nothing here is imported by ``locomotion`` itself; jax, brax, mujoco and rcsssmj are imported
lazily and a missing one raises ImportError naming ``pip install -e '.[humanoid]'``.

* :mod:`.t1` -- load the T1 MJCF shipped in rcsssmj, stance and joint PD gains;
* :mod:`.brax_sim` -- batched brax (generalized pipeline) rollouts;
* :mod:`.mujoco_sim` -- the same experiment in native MuJoCo (fast reference);
* :mod:`.measure` -- push/fall thresholds, fall duration, writing a measured profile;
* :mod:`.walker` -- 3D-LIPM/ZMP preview-control walker with leg IK and capture-point feedback;
* :mod:`.envelope` -- its walking envelope (commanded -> achieved velocity) as a profile.
"""

from __future__ import annotations

from ._deps import EXTRA_HINT, require

__all__ = ["EXTRA_HINT", "require"]
