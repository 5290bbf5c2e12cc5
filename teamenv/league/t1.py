"""The T1's motors and joint sensors as the league server names them (rcsssmj 0.2.1 MJCF).

Motor effector ``he1`` drives the joint whose angle arrives as ``q_hj1`` (``HJ`` perceptor):
the sensor name is the motor name with ``e`` -> ``j`` and a ``q_`` prefix."""

from __future__ import annotations

import re

#: motor effector name -> MJCF joint name, in the MJCF's order
T1_MOTORS: dict[str, str] = {
    "he1": "AAHead_yaw", "he2": "Head_pitch",
    "lae1": "Left_Shoulder_Pitch", "lae2": "Left_Shoulder_Roll", "lae3": "Left_Elbow_Pitch",
    "lae4": "Left_Elbow_Yaw",
    "rae1": "Right_Shoulder_Pitch", "rae2": "Right_Shoulder_Roll", "rae3": "Right_Elbow_Pitch",
    "rae4": "Right_Elbow_Yaw",
    "te1": "Waist",
    "lle1": "Left_Hip_Pitch", "lle2": "Left_Hip_Roll", "lle3": "Left_Hip_Yaw",
    "lle4": "Left_Knee_Pitch", "lle5": "Left_Ankle_Pitch", "lle6": "Left_Ankle_Roll",
    "rle1": "Right_Hip_Pitch", "rle2": "Right_Hip_Roll", "rle3": "Right_Hip_Yaw",
    "rle4": "Right_Knee_Pitch", "rle5": "Right_Ankle_Pitch", "rle6": "Right_Ankle_Roll",
}

_MOTOR = re.compile(r"([a-z]+)e(\d)")


def joint_sensor(motor: str) -> str:
    """The ``HJ`` sensor name of a motor: ``he1`` -> ``q_hj1``."""
    m = _MOTOR.fullmatch(motor)
    if m is None or motor not in T1_MOTORS:
        raise KeyError(f"T1 has no motor {motor!r}; motors: {list(T1_MOTORS)}")
    return f"q_{m.group(1)}j{m.group(2)}"
