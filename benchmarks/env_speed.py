"""Env steps per second (11 v 11, random actions) against the bare pymunk loop, in one run.

Usage: python benchmarks/env_speed.py [--steps 3000] [--team-size 11]
                                     [--observation vision [--vision simspark|mj]]
"""

from __future__ import annotations

import argparse
import math
import platform
import time

import numpy as np

import teamenv
from teamenv.env import TIMING_PHASES
from teamenv.sim.world import World

PHASES: dict[str, dict[str, float]] = {}  # env.timings() of the timed runs, by run name


def bench_env(steps: int, team_size: int, action_format: str, seed: int = 0,
              **obs: str) -> float:
    env = teamenv.parallel_env(team_size=team_size, action_format=action_format,
                               rules={"half_time_s": 1e6}, **obs)
    env.reset(seed=seed)
    rng = np.random.default_rng(seed)
    # Actions are drawn before timing: we measure the env, not the action sampler.
    pool = []
    for _ in range(64):
        if action_format == "box":
            acts = rng.uniform(-1, 1, (len(env.agents), 9)).astype(np.float32)
            pool.append(dict(zip(env.agents, acts)))
        else:
            pool.append({a: {"walk": rng.uniform([-1, -0.4, -1.5], [1.5, 0.4, 1.5]).astype(np.float32),
                             "kick": np.array([rng.random() * (rng.random() < 0.1), 0], np.float32)}
                         for a in env.agents})
    for k in range(100):  # warm-up
        env.step(pool[k % 64])
    env.reset_timings()
    start = time.perf_counter()
    for k in range(steps):
        env.step(pool[k % 64])
    rate = steps / (time.perf_counter() - start)
    PHASES[f"env, random {action_format.capitalize()} actions"] = env.timings()
    return rate


def bench_teams(steps: int, team_size: int, left: str, right: str, **obs: str) -> float:
    env = teamenv.parallel_env(team_size=team_size, left=left, right=right,
                               rules={"half_time_s": 1e6}, **obs)
    env.reset(seed=0)
    for _ in range(100):
        env.step({})
    env.reset_timings()
    start = time.perf_counter()
    for _ in range(steps):
        env.step({})
    rate = steps / (time.perf_counter() - start)
    PHASES[f"env, {left} vs {right}"] = env.timings()
    return rate


def bench_bare_pymunk(steps: int, team_size: int, seed: int = 0) -> tuple[float, float]:
    """The same World (bodies, shapes, substep rule) stepped with random velocities: returns
    (steps/s of World.step, steps/s of the pymunk space.step calls alone)."""
    env = teamenv.parallel_env(team_size=team_size)
    env.reset(seed=seed)
    world: World = env.sim.world
    rng = np.random.default_rng(seed)
    n = 2 * team_size
    vel = [np.column_stack([rng.uniform(-1, 1, (n, 2)), rng.uniform(-1, 1, n)]) for _ in range(64)]
    for k in range(100):
        world.step(vel[k % 64])
    start = time.perf_counter()
    for k in range(steps):
        world.step(vel[k % 64])
    world_rate = steps / (time.perf_counter() - start)
    dt = env.physics.cycle_s
    space = world.space
    start = time.perf_counter()
    for k in range(steps):
        substeps = max(1, math.ceil(world.ball.velocity.length * dt / env.physics.max_substep_travel))
        for _ in range(substeps):
            space.step(dt / substeps)
    space_rate = steps / (time.perf_counter() - start)
    return world_rate, space_rate


def bench_components(steps: int, team_size: int, **obs: str) -> dict[str, float]:
    """Microseconds per cycle of the env's parts, each timed alone on a live env's inputs."""
    env = teamenv.parallel_env(team_size=team_size, rules={"half_time_s": 1e6}, **obs)
    env.reset(seed=0)
    sim, n = env.sim, env.sim.n
    rng = np.random.default_rng(0)
    actions = {a: {"walk": rng.uniform([-1, -0.4, -1.5], [1.5, 0.4, 1.5]).astype(np.float32)}
               for a in env.agents}
    for _ in range(50):
        env.step(actions)
    from teamenv.sim.simulation import Commands

    def timed(fn) -> float:
        start = time.perf_counter()
        for _ in range(steps):
            fn()
        return (time.perf_counter() - start) / steps * 1e6

    cmd = Commands.idle(n)
    rows = [env._row[a] for a in env.agents]
    walk = np.array([actions[a]["walk"] for a in env.agents], dtype=float)
    kick = np.zeros(n, dtype=bool)
    zeros = np.zeros(n)
    parts = {}
    if sim.vision is not None:
        # Vision alone (geometry, noise, rows), then with the Dict views, on an update cycle
        # and on a cycle without one; the mean over a period is what a cycle costs on average.
        cycle, period = sim.cycle, sim.vision.config.update_period_cycles
        for name, at in (("update cycle", 0), ("other cycle", 1 % period)):
            sim.cycle = at
            parts[f"vision observe, {name}"] = timed(lambda: sim.vision.observe(
                sim.cycle, sim.world.player_poses(), sim.world.ball_state(), sim.fallen(),
                sim.odometry, sim.turn, sim.referee.mode, sim.referee.time_s, sim.referee.half,
                sim.referee.score, sim.referee.attack_sign, sim._heard_info, sim._heard_texts))
            parts[f"perception + Dict views, {name}"] = timed(
                lambda: sim.observation_forms(flat=False))
        sim.cycle = cycle
        parts[f"perception, mean over {period} cycles"] = (
            parts["perception + Dict views, update cycle"]
            + (period - 1) * parts["perception + Dict views, other cycle"]) / period
    return parts | {
        "action validation (22 Dict actions)": timed(
            lambda: env.parser.fill(cmd, rows, env.agents, [actions[a] for a in env.agents], {})),
        "locomotion Bodies.step": timed(
            lambda: sim.bodies.step(walk, kick, zeros, zeros, zeros, sim.rng, dt=0.02)),
        "world.step (pymunk + body I/O)": timed(lambda: sim.world.step(np.zeros((n, 3)))),
        "perception (22 observations)": timed(lambda: (sim.world._invalidate(),
                                                        sim.observations())),
        "whole env.step": timed(lambda: env.step(actions)),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--steps", type=int, default=3000)
    parser.add_argument("--team-size", type=int, default=11)
    parser.add_argument("--observation", choices=("state", "vision"), default="state")
    parser.add_argument("--vision", default=None, help="vision profile: simspark | mj")
    args = parser.parse_args()
    n, s = args.team_size, args.steps
    obs = {"observation_mode": args.observation}
    if args.vision is not None:
        obs["vision"] = args.vision
    print(f"teamenv {teamenv.__version__}, python {platform.python_version()}, "
          f"{platform.machine()}, {n} v {n}, {s} steps each, observations {obs}")
    world_rate, space_rate = bench_bare_pymunk(s, n)
    env_dict = bench_env(s, n, "dict", **obs)
    env_box = bench_env(s, n, "box", **obs)
    rows = [
        ("bare pymunk: space.step only", space_rate),
        ("bare world: velocities + space.step + ball drag", world_rate),
        ("env, 22 agents, random Dict actions", env_dict),
        ("env, 22 agents, random Box actions", env_box),
    ]
    try:
        rows.append(("env, chaser vs static teams (no caller agents)",
                     bench_teams(s // 2, n, "chaser", "static", **obs)))
    except teamenv.TeamEnvError as exc:  # a built-in team may not play this mode yet
        print(f"(chaser vs static not run: {exc})")
    for name, rate in rows:
        print(f"{name:52s} {rate:9.0f} steps/s  {1e6 / rate:8.1f} us/step")
    print(f"ratio env(Dict)/bare pymunk loop: {env_dict / space_rate:.2f}  "
          f"(target >= 0.5: {'met' if env_dict / space_rate >= 0.5 else 'NOT met'})")
    print(f"ratio env(Box)/bare pymunk loop:  {env_box / space_rate:.2f}")
    print("where an env step goes (env.timings() of the timed runs, us per step):")
    names = list(PHASES)
    print(f"  {'phase':12s}" + "".join(f"{name:>34s}" for name in names))
    for phase in (*TIMING_PHASES, "total"):
        print(f"  {phase:12s}" + "".join(
            f"{PHASES[name][phase] / (s if 'vs' not in name else s // 2) * 1e6:34.1f}"
            for name in names))
    print("where an env step goes (each part timed alone):")
    for name, us in bench_components(s // 2, n, **obs).items():
        print(f"  {name:40s} {us:8.1f} us")


if __name__ == "__main__":
    main()
