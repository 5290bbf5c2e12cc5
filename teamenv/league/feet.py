"""Where the T1's feet are, from what the robot measures: the torso's pose and every leg joint's
angle put through the T1 model's forward kinematics (needs the ``humanoid`` extra).

The hand-over of a kick's approach with ``stop`` (``teamenv.league.handover``) waits for both
feet to be on the ground: our walker starts its gait standing on both feet, and taking over a
stepping robot with one foot in the air fell more often (docs/league.md, *A hand-over that
stops first*).
"""

from __future__ import annotations

import functools

import numpy as np

from .controller import shared_t1
from .errors import LeagueError
from .perception import Perception
from .t1 import T1_MOTORS, joint_sensor

#: a foot is down when its body's origin is at most this high (m): it is 0.030 m standing flat
FOOT_DOWN_Z = 0.035


@functools.lru_cache(maxsize=1)
def _kinematics():
    """(model, scratch data, the qpos address and sensor of every motor's joint, foot bodies)."""
    import mujoco

    m = shared_t1().model
    joints = []
    for motor, joint in T1_MOTORS.items():
        jid = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, joint)
        joints.append((int(m.jnt_qposadr[jid]), joint_sensor(motor)))
    feet = tuple(mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, f"{s}_foot_link")
                 for s in ("left", "right"))
    return mujoco, m, mujoco.MjData(m), tuple(joints), feet


def feet_heights(perception: Perception) -> tuple[float, float]:
    """World height (m) of the left and the right foot body's origin."""
    mujoco, m, d, joints, feet = _kinematics()
    try:
        qpos = np.array(shared_t1().q_stance, dtype=float)
        qpos[0:3] = perception.positions["torso_pos"]
        qpos[3:7] = perception.orientations["torso_quat"]
        for adr, sensor in joints:
            qpos[adr] = perception.joints[sensor].angle
    except KeyError as exc:
        raise LeagueError(f"perception has no {exc.args[0]!r} (needed for the feet)") from None
    d.qpos[:] = qpos
    mujoco.mj_kinematics(m, d)
    return float(d.xpos[feet[0]][2]), float(d.xpos[feet[1]][2])


def feet_down(perception: Perception) -> bool:
    """Both feet on the ground (``FOOT_DOWN_Z``)."""
    return max(feet_heights(perception)) <= FOOT_DOWN_Z
