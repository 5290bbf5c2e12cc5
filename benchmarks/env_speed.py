"""Env steps per second (11 v 11, random actions) against a bare pymunk loop, in one run.

Runs: random Dict actions with a ``say`` message from every agent every cycle (as a
communicating team does; texts drawn from the channel's alphabet, lengths within its budget),
random Dict actions without messages, random Box actions; each against the *reference*: a bare
pymunk loop with the same 2N + 1 bodies and walls that each step sets 2N velocities and reads
2N + 1 positions through pymunk's per-body attributes (``body.velocity = ...``,
``body.position``), then calls ``space.step(0.02)``. Target (issue 16): env(Dict + say) >= 0.25
x the reference. Actions are drawn before timing.

Usage: python benchmarks/env_speed.py [--steps 3000] [--team-size 11] [--repeats 3]
                                     [--observation vision [--vision simspark|mj]]
"""

from __future__ import annotations

import argparse
import base64
import math
import platform
import time

import numpy as np

import teamenv
from teamenv.env import TIMING_PHASES
from teamenv.sim.world import World

PHASES: dict[str, dict[str, float]] = {}  # env.timings() of the timed runs, by run name


def random_say(rng: np.random.Generator, profile) -> str:
    """A random legal say text of ``profile``: 1..max_chars characters of its alphabet (the
    padded base64 of 1..payload_bytes random bytes on a base64 channel such as ``mj``)."""
    if profile.base64_payload:
        n = int(rng.integers(1, profile.payload_bytes + 1))
        return base64.b64encode(rng.bytes(n)).decode("ascii")
    chars = profile.charset
    n = int(rng.integers(1, profile.max_chars + 1))
    return "".join(chars[k] for k in rng.integers(0, len(chars), n))


def bench_env(steps: int, team_size: int, action_format: str, seed: int = 0, say: bool = False,
              name: str | None = None, repeats: int = 1, read: bool = False, **obs: str) -> float:
    """Best steps/s of ``repeats`` timed runs of ``steps`` steps (timings of the best run).
    ``read``: every step also reads every agent's observation and info (the env builds the
    per-agent dicts of both on first access)."""
    env = teamenv.parallel_env(team_size=team_size, action_format=action_format,
                               rules={"half_time_s": 1e6}, **obs)
    env.reset(seed=seed)
    rng = np.random.default_rng(seed)
    profile = env.sim.channel.profile
    # Actions are drawn before timing: we measure the env, not the action sampler.
    pool = []
    for _ in range(64):
        if action_format == "box":
            acts = rng.uniform(-1, 1, (len(env.agents), 9)).astype(np.float32)
            pool.append(dict(zip(env.agents, acts)))
        else:
            acts = {}
            for a in env.agents:
                acts[a] = {"walk": rng.uniform([-1, -0.4, -1.5], [1.5, 0.4, 1.5]).astype(np.float32),
                           "kick": np.array([rng.random() * (rng.random() < 0.1), 0], np.float32)}
                if say:
                    acts[a]["say"] = random_say(rng, profile)
            pool.append(acts)
    for k in range(100):  # warm-up
        env.step(pool[k % 64])
    best, best_timings = 0.0, None
    for _ in range(repeats):
        env.reset_timings()
        start = time.perf_counter()
        if read:
            for k in range(steps):
                observations, _, _, _, infos = env.step(pool[k % 64])
                for agent in observations:
                    observations[agent], infos[agent]
        else:
            for k in range(steps):
                env.step(pool[k % 64])
        rate = steps / (time.perf_counter() - start)
        if rate > best:
            best, best_timings = rate, env.timings()
    if name is None:
        name = f"{action_format.capitalize()}" + (" + say" if say else "") + \
            (", read" if read else "")
    PHASES[name] = {k: v / steps for k, v in best_timings.items()}
    return best


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
    PHASES[f"{left} vs {right}"] = {k: v / steps for k, v in env.timings().items()}
    return rate


def bench_reference(steps: int, team_size: int, field: str = "simspark", seed: int = 0,
                    repeats: int = 1) -> float:
    """The reference loop of issue 16: the env's World (the same 2N players + ball, goal posts,
    nets and walls) driven from plain Python through pymunk's per-body attributes. Each step
    sets 2N velocities (``body.velocity = (vx, vy)``), reads 2N + 1 positions
    (``body.position``), then calls ``space.step(0.02)``. Best steps/s of ``repeats`` runs."""
    env = teamenv.parallel_env(field=field, team_size=team_size)
    env.reset(seed=seed)
    world: World = env.sim.world
    space, bodies = world.space, [*world.players, world.ball]
    players = world.players
    rng = np.random.default_rng(seed)
    n = 2 * team_size
    vel = [[(float(vx), float(vy)) for vx, vy in rng.uniform(-1, 1, (n, 2))] for _ in range(64)]

    def run(count: int) -> list:
        positions = []
        for k in range(count):
            for body, v in zip(players, vel[k % 64]):
                body.velocity = v
            positions = [body.position for body in bodies]
            space.step(0.02)
        return positions

    run(100)
    best = 0.0
    for _ in range(repeats):
        start = time.perf_counter()
        run(steps)
        best = max(best, steps / (time.perf_counter() - start))
    return best


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
    profile = env.sim.channel.profile
    actions = {a: {"walk": rng.uniform([-1, -0.4, -1.5], [1.5, 0.4, 1.5]).astype(np.float32),
                   "say": random_say(rng, profile)}
               for a in env.agents}
    for _ in range(50):
        env.step(actions)
    from teamenv.sim.simulation import Commands, CycleReport

    says = [[random_say(rng, profile) for _ in range(n)] for _ in range(16)]
    cycle = [0]

    def deliver() -> None:
        cycle[0] += 1
        sim._deliver(says[cycle[0] % 16], CycleReport())

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
        "action validation (22 Dict actions + say)": timed(
            lambda: env.parser.fill(cmd, rows, env.agents, [actions[a] for a in env.agents], {})),
        "locomotion Bodies.step": timed(
            lambda: sim.bodies.step(walk, kick, zeros, zeros, zeros, sim.rng, dt=0.02)),
        "world.step (pymunk + body I/O)": timed(lambda: sim.world.step(np.zeros((n, 3)))),
        f"say delivery ({n} speakers, channel + heard slots)": timed(deliver),
        "perception (22 observations, eager dicts)": timed(lambda: (sim.world._invalidate(),
                                                                     sim.observations())),
        "perception (22 observations, lazy dicts)": timed(lambda: (sim.world._invalidate(),
                                                                    sim.observations(lazy=True))),
        "whole env.step": timed(lambda: env.step(actions)),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--steps", type=int, default=3000)
    parser.add_argument("--team-size", type=int, default=11)
    parser.add_argument("--repeats", type=int, default=3,
                        help="timed runs of each env and reference loop; the best is kept")
    parser.add_argument("--field", default="simspark")
    parser.add_argument("--channel", default=None, help="say channel: simspark | mj")
    parser.add_argument("--observation", choices=("state", "vision"), default="state")
    parser.add_argument("--vision", default=None, help="vision profile: simspark | mj")
    parser.add_argument("--no-components", action="store_true",
                        help="skip the per-part timings at the end")
    args = parser.parse_args()
    n, s, r = args.team_size, args.steps, args.repeats
    obs = {"observation_mode": args.observation, "field": args.field}
    if args.vision is not None:
        obs["vision"] = args.vision
    if args.channel is not None:
        obs["channel"] = args.channel
    print(f"teamenv {teamenv.__version__}, python {platform.python_version()}, "
          f"{platform.machine()}, {n} v {n}, {s} steps x {r} repeats (best kept), options {obs}")
    reference = bench_reference(s, n, field=args.field, repeats=r)
    world_rate, space_rate = bench_bare_pymunk(s, n)
    env_say = bench_env(s, n, "dict", say=True, repeats=r, **obs)
    env_read = bench_env(s, n, "dict", say=True, repeats=r, read=True, **obs)
    env_dict = bench_env(s, n, "dict", repeats=r, **obs)
    env_box = bench_env(s, n, "box", repeats=r, **obs)
    rows = [
        ("reference: per-body velocity/position + space.step", reference, None),
        ("bare pymunk: space.step only (env's substep rule)", space_rate, None),
        ("bare world: velocities + space.step + ball drag", world_rate, None),
        (f"env, {2 * n} agents, random Dict actions + say", env_say, reference),
        ("  same, reading every observation and info", env_read, reference),
        (f"env, {2 * n} agents, random Dict actions, silent", env_dict, reference),
        (f"env, {2 * n} agents, random Box actions", env_box, reference),
    ]
    try:
        rows.append(("env, chaser vs static teams (no caller agents)",
                     bench_teams(s // 2, n, "chaser", "static", **obs), reference))
    except teamenv.TeamEnvError as exc:  # a built-in team may not play this mode yet
        print(f"(chaser vs static not run: {exc})")
    for name, rate, ref in rows:
        ratio = f"  {rate / ref:5.3f} x reference" if ref else ""
        print(f"{name:54s} {rate:9.0f} steps/s  {1e6 / rate:8.1f} us/step{ratio}")
    ratio = env_say / reference
    print(f"ratio env(Dict + say)/reference: {ratio:.3f}  "
          f"(target >= 0.25: {'met' if ratio >= 0.25 else 'NOT met'})")
    print(f"ratio env(Dict + say, every observation and info read)/reference: "
          f"{env_read / reference:.3f}")
    print(f"ratio env(Dict, silent)/reference: {env_dict / reference:.3f}")
    print(f"ratio env(Box)/reference: {env_box / reference:.3f}")
    print("where an env step goes (env.timings() of the timed runs, us per step; building\n"
          "the per-agent dicts on first access happens outside step(), in no phase):")
    names = list(PHASES)
    print(f"  {'phase':12s}" + "".join(f"{name:>18s}" for name in names))
    for phase in (*TIMING_PHASES, "total"):
        print(f"  {phase:12s}" + "".join(f"{PHASES[name][phase] * 1e6:18.1f}" for name in names))
    if not args.no_components:
        print("where an env step goes (each part timed alone):")
        for name, us in bench_components(s // 2, n, **obs).items():
            print(f"  {name:50s} {us:8.1f} us")


if __name__ == "__main__":
    main()
