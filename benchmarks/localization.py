"""Monte Carlo localization: error and cost per particle count.

Synthetic walks (``tests.strategy.test_localization.synthetic_walk``: SimSpark's noise and
landmarks on the 30 x 20 m pitch, lines, odometry over-reported by 1.1/1.1/1.05 with 5 %
noise, a look every 3rd cycle): ``--agents`` walkers localized in one ``BatchLocalizer`` from a
uniform prior; the error is measured after a ``--warmup`` (s). Cost: the filter's own calls
(predict every cycle, correct on vision cycles, estimate every cycle) for the whole batch,
per cycle, and one agent alone (``Localizer``).

Env (when ``teamenv`` has ``observation_mode="vision"``): ``--env-team-size`` a side on the
``mj7v7`` pitch, every player walking a scripted pattern (caller-driven), each team localized
by one ``BatchLocalizer`` (its own frame), for both vision profiles; error against
``env.sim.world.player_poses()`` in each team's frame; cost of ``observe`` (dict stacking
included) of both teams per cycle.

No assertions: it prints a table. Timings are wall-clock on whatever machine runs it (the
numbers in README.md say which).

    python benchmarks/localization.py
    python benchmarks/localization.py --particles 50 100 200 --seconds 20 --no-env
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

from strategy.perception.localization import (  # noqa: E402
    BatchLocalizer,
    LocalizationParams,
    Localizer,
)
from tests.strategy.test_localization import synthetic_walk  # noqa: E402

TARGET_MS = 2.0  # all 22 agents localized per cycle


def _stats(pos: np.ndarray, head: np.ndarray) -> dict[str, float]:
    return {"pos_rms": math.sqrt(np.mean(pos ** 2)), "pos_p95": float(np.percentile(pos, 95)),
            "pos_max": float(pos.max()),
            "head_rms": math.degrees(math.sqrt(np.mean(head ** 2))),
            "head_p95": math.degrees(float(np.percentile(head, 95)))}


def _errors(est: np.ndarray, truth: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    pos = np.hypot(est[..., 0] - truth[..., 0], est[..., 1] - truth[..., 1])
    head = np.abs((est[..., 2] - truth[..., 2] + np.pi) % (2 * np.pi) - np.pi)
    return pos, head


def synthetic(n_particles: int, agents: int, seconds: float, warmup: float, seed: int
              ) -> dict[str, float]:
    walks = [synthetic_walk(seed + k, seconds) for k in range(agents)]
    cycles = len(walks[0].observations)
    odometry = np.array([[w.observations[t]["odometry"] for w in walks] for t in range(cycles)])
    gyro = np.array([[w.observations[t]["gyro"][0] for w in walks] for t in range(cycles)])
    looks = {t: (np.stack([w.observations[t]["landmarks"] for w in walks]),
                 np.stack([w.observations[t]["lines"] for w in walks]))
             for t in range(cycles) if "landmarks" in walks[0].observations[t]}
    truth = np.stack([w.poses for w in walks], axis=1)  # (T, A, 3)
    params = LocalizationParams(n_particles=n_particles)
    batch = BatchLocalizer(agents, "simspark", "simspark", 0.5, params,
                           np.random.default_rng(seed))
    est = np.empty_like(truth)
    spent = np.zeros(cycles)
    clock = time.perf_counter
    for t in range(cycles):
        t0 = clock()
        batch.predict(None, odometry[t], gyro[t])
        if t in looks:
            batch.correct(None, *looks[t])
        pose = batch.estimate().pose
        spent[t] = clock() - t0
        est[t] = pose
    first = int(round(warmup / 0.02))
    pos, head = _errors(est[first:], truth[first:])
    out = _stats(pos.ravel(), head.ravel())
    vision = np.array([t in looks for t in range(cycles)])
    out["ms_cycle"] = 1e3 * spent.mean()
    out["ms_vision"] = 1e3 * spent[vision].mean()
    out["us_agent"] = 1e6 * spent.mean() / agents
    # one agent alone (its own Localizer): the per-agent cost without batching
    single = Localizer("simspark", "simspark", 0.5, params, np.random.default_rng(seed))
    t0 = clock()
    for t in range(cycles):
        single.predict(odometry[t, 0], gyro[t, 0])
        if t in looks:
            single.correct(looks[t][0][0], looks[t][1][0])
        single.estimate()
    out["us_alone"] = 1e6 * (clock() - t0) / cycles
    return out


def in_env(n_particles: int, vision: str, team_size: int, seconds: float, warmup: float,
           seed: int) -> dict[str, float]:
    import teamenv

    env = teamenv.parallel_env(observation_mode="vision", vision=vision, field="mj7v7",
                               team_size=team_size, profile_phases=False)
    obs, _ = env.reset(seed=seed)
    cam = env.perception
    params = LocalizationParams(n_particles=n_particles)
    sides = {side: [a for a in env.agents if a.startswith(side)] for side in ("left", "right")}
    locs = {side: BatchLocalizer(team_size, env.field, cam.landmark_kind, cam.camera_height_m,
                                 params, np.random.default_rng(seed + k))
            for k, side in enumerate(sides)}
    cycles = int(round(seconds / 0.02))
    first = int(round(warmup / 0.02))
    pos_all, head_all, spent = [], [], np.zeros(cycles)
    clock = time.perf_counter
    for t in range(cycles):
        world = env.sim.world.player_poses()
        for k, (side, agents) in enumerate(sides.items()):
            t0 = clock()
            est = locs[side].observe([obs[a] for a in agents]).pose
            spent[t] += clock() - t0
            truth = world[k * team_size:(k + 1) * team_size].copy()
            if env.sim.referee.attack_sign[k] < 0:  # this team's frame: the world turned by pi
                truth[:, :2] *= -1.0
                truth[:, 2] += np.pi
            if t >= first:
                pos, head = _errors(est, truth)
                pos_all.append(pos)
                head_all.append(head)
        actions = {a: {"walk": np.array([0.7 + 0.3 * math.sin(t / 90.0 + i),
                                         0.15 * math.sin(t / 25.0 + 2 * i),
                                         0.7 * math.sin(t / 60.0 + i)], dtype=np.float32)}
                   for i, a in enumerate(env.agents)}
        obs, *_ = env.step(actions)
    out = _stats(np.concatenate(pos_all), np.concatenate(head_all))
    period = cam.update_period_cycles
    vision_cycles = np.arange(cycles) % period == 0
    out["ms_cycle"] = 1e3 * spent.mean()
    out["ms_vision"] = 1e3 * spent[vision_cycles].mean()
    out["us_agent"] = 1e6 * spent.mean() / (2 * team_size)
    out["us_alone"] = float("nan")
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--particles", type=int, nargs="+", default=[50, 100, 200])
    ap.add_argument("--agents", type=int, default=22, help="synthetic walkers in one batch")
    ap.add_argument("--seconds", type=float, default=30.0)
    ap.add_argument("--warmup", type=float, default=3.0,
                    help="seconds from the uniform prior before errors count")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--no-env", action="store_true", help="skip the env's vision mode")
    ap.add_argument("--env-team-size", type=int, default=11)
    ap.add_argument("--env-seconds", type=float, default=30.0)
    args = ap.parse_args()

    rows = []
    for n in args.particles:
        rows.append((f"synthetic simspark x{args.agents}", n,
                     synthetic(n, args.agents, args.seconds, args.warmup, args.seed)))
    env_ok = False
    if not args.no_env:
        from teamenv.env import OBSERVATION_MODES
        env_ok = "vision" in OBSERVATION_MODES
        if env_ok:
            for vision in ("simspark", "mj"):
                for n in args.particles:
                    rows.append((f"env {vision} mj7v7 {args.env_team_size}v{args.env_team_size}",
                                 n, in_env(n, vision, args.env_team_size, args.env_seconds,
                                           args.warmup, args.seed)))
        else:
            print("(the env has no vision mode: env rows skipped)")

    head = (f"{'scene':28s} {'N':>4s} {'pos RMS':>8s} {'pos p95':>8s} {'pos max':>8s} "
            f"{'hdg RMS':>8s} {'hdg p95':>8s} {'ms/cyc':>7s} {'ms/look':>8s} "
            f"{'us/agent':>9s} {'us alone':>9s}")
    print(head)
    print("-" * len(head))
    for name, n, r in rows:
        print(f"{name:28s} {n:4d} {r['pos_rms']:7.3f}m {r['pos_p95']:7.3f}m {r['pos_max']:7.3f}m "
              f"{r['head_rms']:7.2f}° {r['head_p95']:7.2f}° {r['ms_cycle']:7.3f} "
              f"{r['ms_vision']:8.3f} {r['us_agent']:9.1f} {r['us_alone']:9.1f}")
    print()
    print("pos/hdg: errors after the warm-up, every agent and cycle; ms/cyc: all agents of the "
          "row per cycle (mean), ms/look: on vision cycles; us/agent = ms/cyc / agents; "
          "us alone: one agent's own Localizer per cycle.")
    for name, n, r in rows:
        agents = args.agents if name.startswith("synthetic") else 2 * args.env_team_size
        if agents == 22:
            ok_err = r["pos_rms"] < 0.2
            ok_time = r["ms_cycle"] < TARGET_MS
            print(f"{name} N={n}: RMS < 0.2 m {'met' if ok_err else 'NOT met'}; 22 agents "
                  f"< {TARGET_MS} ms/cycle {'met' if ok_time else 'NOT met'} "
                  f"(mean {r['ms_cycle']:.3f} ms, vision cycles {r['ms_vision']:.3f} ms)")


if __name__ == "__main__":
    main()
