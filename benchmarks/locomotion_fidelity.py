"""Fidelity report: standard manoeuvres of the 2D walk model against the T1 humanoid walking
them with the LIPM walker (native MuJoCo), plus the 2D model's steady state against rcsssmj."""

from __future__ import annotations

import argparse
import json
import math
from collections.abc import Callable

import numpy as np

import locomotion
from locomotion.walk import compose

DT = 0.02

# Steady-state reference measured on the league server (rcsssmj 0.2.1, reference walking
# network, 15 s runs), compared with the t1_mj profile.
RCSSSMJ_STEADY = {
    "vx 0.25": ((0.25, 0, 0), (0.26, 0, 0)),
    "vx 0.5": ((0.5, 0, 0), (0.49, 0, 0)),
    "vx 0.75": ((0.75, 0, 0), (0.72, 0, 0)),
    "vx 1.0": ((1.0, 0, 0), (0.91, 0, 0)),
    "vx 1.5": ((1.5, 0, 0), (1.24, 0, 0)),
    "vx -0.5": ((-0.5, 0, 0), (-0.45, 0, 0)),
    "vy 0.15": ((0, 0.15, 0), (0, 0.135, 0)),
    "turn 0.5": ((0, 0, 0.5), (0, 0, 0.51)),
    "turn 1.0": ((0, 0, 1.0), (0, 0, 0.96)),
    "arc": ((0.5, 0, 0.5), (0.50, 0, 0.47)),
}


WARMUP_S = 1.0  # both models step in place this long before a manoeuvre starts (s)
STOP_SPEED = (
    0.03  # m/s: "stopped" = mean planar speed over the last gait cycle (2 steps) below this
)


def _rel(origin: np.ndarray, pose: np.ndarray) -> np.ndarray:
    """``pose`` in the frame of ``origin`` (x, y, yaw unwrapped by the caller)."""
    c, s = math.cos(origin[2]), math.sin(origin[2])
    d = pose[:2] - origin[:2]
    return np.array([c * d[0] + s * d[1], -s * d[0] + c * d[1], pose[2] - origin[2]])


class _Tracker:
    """Turns a manoeuvre policy ``policy(rel_pose, speed, t) -> command | None`` into a
    ``command_fn(t, world_pose)`` for either model: the pose is taken relative to the pose at
    the end of the warm-up (yaw unwrapped), speed is the planar speed over the last two step
    periods (one gait cycle, so the humanoid's sway cancels), and the time when the policy
    first returns None is recorded."""

    def __init__(self, policy: Callable, step_period: float, warmup: float = WARMUP_S) -> None:
        self.policy, self.T, self.warmup = policy, step_period, warmup
        self.origin: np.ndarray | None = None
        self.hist: list[tuple[float, np.ndarray]] = []
        self.path: list[np.ndarray] = []
        self.done: float | None = None
        self.yaw_prev: float | None = None
        self.yaw_acc = 0.0

    def __call__(self, t: float, pose: np.ndarray):
        pose = np.asarray(pose, float).copy()
        if self.yaw_prev is not None:
            self.yaw_acc += (pose[2] - self.yaw_prev + math.pi) % (2 * math.pi) - math.pi
        else:
            self.yaw_acc = pose[2]
        self.yaw_prev = pose[2]
        pose[2] = self.yaw_acc
        if t < self.warmup - 1e-9:
            return (0.0, 0.0, 0.0)
        if self.origin is None:
            self.origin = pose.copy()
        rel = _rel(self.origin, pose)
        tm = t - self.warmup
        self.hist.append((tm, rel))
        self.path.append(rel)
        old = [r for (tt, r) in self.hist if tt <= tm - 2 * self.T]
        speed = float(np.hypot(*(rel[:2] - old[-1][:2]))) / (2 * self.T) if old else math.inf
        cmd = self.policy(rel, speed, tm)
        if cmd is None:
            self.done = tm
        return cmd


def run_2d(profile: locomotion.Profile, policy: Callable, t_max: float = 60.0, seed: int = 0):
    """One body of the 2D model (``locomotion.Bodies``) under ``policy``.

    Returns (time s or inf, path (k, 3) relative poses)."""
    b = locomotion.Bodies(profile, 1)
    rng = np.random.default_rng(seed)
    tr = _Tracker(policy, profile.step_period)
    pose = np.zeros((1, 3))
    z = np.zeros(1)
    t = 0.0
    while t < t_max + WARMUP_S:
        cmd = tr(t, pose[0])
        if cmd is None:
            break
        r = b.step(np.asarray(cmd, float)[None], np.zeros(1, bool), z, z, z, rng, DT)
        pose = compose(pose, r.delta_pose)
        t += DT
    return (tr.done if tr.done is not None else math.inf), np.array(tr.path)


def run_humanoid(t1, params, policy: Callable, t_max: float = 60.0):
    """The T1 under the LIPM walker in native MuJoCo under ``policy``.

    Returns (time s or inf, path (k, 3) relative poses, fell: bool)."""
    from locomotion.humanoid.walker import walk_mujoco

    tr = _Tracker(policy, params.step_period)
    _, _, fell = walk_mujoco(t1, tr, t_max + WARMUP_S, params)
    return (tr.done if tr.done is not None and not fell else math.inf), np.array(tr.path), fell


def _hold(k: float, x: float, lim: float) -> float:
    return float(np.clip(-k * x, -lim, lim))


def manoeuvre_policies(p: locomotion.Profile) -> dict[str, tuple[Callable, Callable]]:
    """The five standard manoeuvres: name -> (policy, deviation(path) in m or rad).

    Commands are the highest commanded point of each measured tracking curve (the walker's
    fastest stable command), with the same small heading/track corrections for both models.
    """
    vx = float(p.tracking[0][0].max())
    vy = float(p.tracking[1][0].max())
    w = float(p.tracking[2][0].max())
    arc = (0.5 * vx, 0.0, 0.5 * w)
    out: dict[str, tuple[Callable, Callable]] = {}

    out[f"sprint 5 m (vx {vx:g})"] = (
        lambda s, v, t: None if s[0] >= 5.0 else (vx, 0.0, _hold(1.0, s[2], 0.3 * w)),
        lambda path: float(np.abs(path[:, 1]).max()),
    )
    out[f"turn 180 deg (w {w:g})"] = (
        lambda s, v, t: None if s[2] >= math.pi else (0.0, 0.0, w),
        lambda path: float(np.hypot(path[:, 0], path[:, 1]).max()),
    )
    out[f"side-step 1 m (vy {vy:g})"] = (
        lambda s, v, t: (
            None if s[1] >= 1.0 else (_hold(1.0, s[0], 0.3 * vx), vy, _hold(1.0, s[2], 0.3 * w))
        ),
        lambda path: float(np.abs(path[:, 0]).max()),
    )

    def start_stop(s, v, t):
        # walk to a mark 2 m ahead and stop on it: speed command proportional to the distance
        # left (no abrupt full-speed -> 0 jump, which the 2D model may punish with a fall)
        if abs(2.0 - s[0]) < 0.1 and v < STOP_SPEED:
            return None
        return (float(np.clip(1.5 * (2.0 - s[0]), -0.5 * vx, vx)), 0.0, _hold(1.0, s[2], 0.3 * w))

    out[f"start-stop: to a mark 2 m ahead (vx <= {vx:g})"] = (
        start_stop,
        lambda path: float(abs(path[-1, 0] - 2.0)),
    )
    radius = arc[0] / arc[2]
    out[f"arc half circle ({arc[0]:g} m/s, {arc[2]:g} rad/s)"] = (
        lambda s, v, t: None if s[2] >= math.pi else arc,
        lambda path: float(np.abs(np.hypot(path[:, 0], path[:, 1] - radius) - radius).max()),
    )
    return out


def manoeuvres(p: locomotion.Profile, humanoid: tuple | None = None) -> dict[str, dict]:
    """Every manoeuvre on the 2D model and, with ``humanoid = (t1, WalkParams)``, on the T1."""
    out: dict[str, dict] = {}
    for name, (policy, dev) in manoeuvre_policies(p).items():
        t2, path2 = run_2d(p, policy)
        r: dict = {"time_2d": t2, "path_2d": path2, "dev_2d": dev(path2)}
        if humanoid is not None:
            th, pathh, fell = run_humanoid(*humanoid, policy)
            r.update(time_h=th, path_h=pathh, dev_h=dev(pathh), fell=fell)
            n = min(len(path2), len(pathh))
            if n > 1:  # the two paths at the same share of completion
                i2 = np.linspace(0, len(path2) - 1, 50).astype(int)
                ih = np.linspace(0, len(pathh) - 1, 50).astype(int)
                r["path_gap"] = float(np.hypot(*(path2[i2, :2] - pathh[ih, :2]).T).mean())
        out[name] = r
    return out


def steady_state_check(p: locomotion.Profile) -> list[tuple[str, float, float, float]]:
    """2D model steady speed after 15 s vs the rcsssmj measurement for each commanded point."""
    rows = []
    for name, (cmd, meas) in RCSSSMJ_STEADY.items():
        b = locomotion.Bodies(p, 1)
        rng = np.random.default_rng(0)
        for _ in range(int(15 / DT)):
            r = b.step(
                np.array([cmd], float),
                np.zeros(1, bool),
                np.zeros(1),
                np.zeros(1),
                np.zeros(1),
                rng,
                DT,
            )
        v = r.velocity[0]
        for k, unit in ((0, "vx"), (1, "vy"), (2, "turn")):
            if meas[k] != 0:
                model, ref = float(v[k]), float(meas[k])
                label = name if name != "arc" else f"arc ({unit})"
                rows.append((label, model, ref, abs(model - ref) / abs(ref)))
    return rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--profile", default="t1_lipm", help="2D model profile for the manoeuvres")
    ap.add_argument(
        "--humanoid",
        action="store_true",
        help="also run every manoeuvre on the T1 with the LIPM walker (native MuJoCo; needs the "
        "humanoid extra)",
    )
    ap.add_argument("--json", default=None, help="also write the numbers to this JSON file")
    args = ap.parse_args()
    ref = locomotion.load_profile("t1_mj")
    print(f"Fidelity report ({ref.name} v{ref.version} for steady state)\n")
    print("1. Steady state after 15 s: 2D model (t1_mj) vs rcsssmj 0.2.1 reference walk")
    print(f"   {'command':10s} {'model':>8s} {'measured':>9s} {'error':>6s}")
    rows = steady_state_check(ref)
    for name, m, r, e in rows:
        print(f"   {name:10s} {m:8.3f} {r:9.3f} {100 * e:5.1f}%  {'OK' if e <= 0.10 else 'MISSED'}")
    p = locomotion.load_profile(args.profile)
    hum = None
    if args.humanoid:
        from locomotion.humanoid.t1 import load_t1
        from locomotion.humanoid.walker import WalkParams

        hum = (load_t1(), WalkParams())
    print(
        f"\n2. Manoeuvres: 2D model (profile {p.name}) vs the T1 humanoid under the LIPM walker"
        " in native MuJoCo" + ("" if hum else " (not run: pass --humanoid)")
    )
    print(
        f"   same command policy for both; {WARMUP_S:g} s stepping in place first; time from "
        "the first command to completion"
    )
    print(
        f"   {'manoeuvre':44s} {'2D s':>6s} {'T1 s':>6s} {'2D/T1':>6s} {'target':>7s}"
        f" {'dev 2D':>7s} {'dev T1':>7s} {'gap m':>6s}"
    )
    res = manoeuvres(p, hum)
    report: dict = {"profile_steady": ref.name, "steady": rows, "profile": p.name, "manoeuvres": {}}
    for name, r in res.items():
        th = r.get("time_h", math.nan)
        ratio = r["time_2d"] / th if math.isfinite(th) and th > 0 else math.nan
        ok = "n/a" if not math.isfinite(ratio) else ("met" if abs(ratio - 1) <= 0.10 else "MISSED")
        if r.get("fell"):
            ok = "T1 fell"
        print(
            f"   {name:44s} {r['time_2d']:6.2f} {th:6.2f} {ratio:6.3f} {ok:>7s}"
            f" {r['dev_2d']:7.3f} {r.get('dev_h', math.nan):7.3f} {r.get('path_gap', math.nan):6.3f}"
        )
        report["manoeuvres"][name] = {
            "time_2d_s": r["time_2d"],
            "time_humanoid_s": th,
            "ratio": ratio,
            "target_10pct": ok,
            "deviation_2d": r["dev_2d"],
            "deviation_humanoid": r.get("dev_h"),
            "path_gap_m": r.get("path_gap"),
            "humanoid_fell": r.get("fell"),
            "end_pose_2d": r["path_2d"][-1].tolist(),
            "end_pose_humanoid": r["path_h"][-1].tolist() if "path_h" in r else None,
        }
    print(
        "\n   dev: largest deviation from the ideal path (sprint: |y|, turn: drift of the torso"
        " from the spot, side-step: |x|, start-stop: |x_end - 2|, arc: distance from the circle),"
        " m; gap: mean distance between the two paths at equal shares of completion, m"
    )
    if args.json:
        with open(args.json, "w", encoding="utf-8") as fh:
            json.dump(report, fh, indent=1, default=float)


if __name__ == "__main__":
    main()
