"""The league's Booster T1 model (shipped in the rcsssmj package): loading, stance and joint PD."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ._deps import require

__all__ = ["T1Model", "t1_model_path", "load_t1", "STANCE", "PD_GAINS"]

# Standing stance (rad): slightly bent knees, arms down (as booster_gym's T1 default pose).
STANCE: dict[str, float] = {
    "Left_Shoulder_Roll": -1.3,
    "Right_Shoulder_Roll": 1.3,
    "Left_Hip_Pitch": -0.2,
    "Right_Hip_Pitch": -0.2,
    "Left_Knee_Pitch": 0.4,
    "Right_Knee_Pitch": 0.4,
    "Left_Ankle_Pitch": -0.2,
    "Right_Ankle_Pitch": -0.2,
}
# Joint PD gains (kp N*m/rad, kd N*m*s/rad) by joint-name fragment; booster_gym-like values.
PD_GAINS: tuple[tuple[str, float, float], ...] = (
    ("Ankle", 300.0, 3.0),
    ("Knee", 200.0, 5.0),
    ("Hip", 200.0, 5.0),
    ("Waist", 200.0, 5.0),
    ("Shoulder", 40.0, 1.0),
    ("Elbow", 40.0, 1.0),
    ("Head", 20.0, 0.5),
    ("AAHead", 20.0, 0.5),
)
TORSO_STANDING_MIN = 0.35  # m: torso-origin height below which the robot counts as fallen
TORSO_ON_GROUND = 0.30  # m: torso-origin height at which a fall is over (lying)


def t1_model_path() -> Path:
    """Path of ``resources/robots/T1/robot.xml`` in the installed rcsssmj package (no download)."""
    rcsssmj = require("rcsssmj")
    path = Path(rcsssmj.__file__).resolve().parent / "resources" / "robots" / "T1" / "robot.xml"
    if not path.is_file():
        raise FileNotFoundError(f"T1 model not found in the installed rcsssmj package: {path}")
    return path


@dataclass(frozen=True)
class T1Model:
    """A compiled T1 on a floor plane plus what the controllers need (SI units).

    Attributes:
        model: mujoco.MjModel (23 hinge joints + free root, motor actuators only, floor).
        q_stance: (nq,) standing configuration, feet on the floor.
        kp, kd: (nu,) joint PD gains; tau_max: (nu,) actuator torque limits (N*m).
        act_qadr, act_dadr: (nu,) qpos / qvel address of each actuated joint.
        mass: total mass (kg).
    """

    model: Any
    q_stance: np.ndarray
    kp: np.ndarray
    kd: np.ndarray
    tau_max: np.ndarray
    act_qadr: np.ndarray
    act_dadr: np.ndarray
    mass: float


def load_t1() -> T1Model:
    """Build the T1 from rcsssmj's MJCF for both engines.

    Changes from the shipped file, so that brax's generalized pipeline accepts it and both
    engines run the *same* model: the position/velocity actuators are removed (PD torques are
    computed by our controller and applied through the motor actuators), geom priorities are
    set to 0 (brax rejects them), and a floor plane is added.
    """
    mujoco = require("mujoco")
    spec = mujoco.MjSpec.from_file(str(t1_model_path()))
    for act in list(spec.actuators):
        if not act.name.endswith("_tau"):
            spec.delete(act)
    for geom in spec.geoms:
        geom.priority = 0
    spec.worldbody.add_geom(
        name="floor",
        type=mujoco.mjtGeom.mjGEOM_PLANE,
        size=[50, 50, 0.1],
        friction=[1.0, 0.01, 0.005],
    )
    model = spec.compile()
    nu = model.nu
    jnt = model.actuator_trnid[:, 0]
    names = [mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_JOINT, j) for j in jnt]
    kp = np.zeros(nu)
    kd = np.zeros(nu)
    for i, nm in enumerate(names):
        for frag, p, d in PD_GAINS:
            if frag in nm:
                kp[i], kd[i] = p, d
                break
        else:  # pragma: no cover
            raise ValueError(f"no PD gain for T1 joint {nm!r}")
    tau_max = model.jnt_actfrcrange[jnt, 1].copy()
    q = model.qpos0.copy()
    for nm, val in STANCE.items():
        q[model.jnt_qposadr[mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, nm)]] = val
    data = mujoco.MjData(model)
    data.qpos[:] = q
    mujoco.mj_forward(model, data)
    foot_ids = [
        mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, g) for g in ("left_foot", "right_foot")
    ]
    # lowest corner of the foot boxes -> put it on the floor
    lowest = min(
        (data.geom_xpos[g] + data.geom_xmat[g].reshape(3, 3) @ (np.array(c) * model.geom_size[g]))[
            2
        ]
        for g in foot_ids
        for c in np.array(np.meshgrid([-1, 1], [-1, 1], [-1, 1])).T.reshape(-1, 3)
    )
    q[2] -= lowest - 1e-4
    return T1Model(
        model=model,
        q_stance=q,
        kp=kp,
        kd=kd,
        tau_max=tau_max,
        act_qadr=model.jnt_qposadr[jnt].copy(),
        act_dadr=model.jnt_dofadr[jnt].copy(),
        mass=float(model.body_subtreemass[0]),
    )
