"""Env steps per second (11 v 11, random actions) against a bare pymunk loop, in one run.

Runs: random Dict actions with a ``say`` message from every agent every cycle (as a
communicating team does; texts drawn from the channel's alphabet, lengths within its budget),
random Dict actions without messages, random Box actions; each against the *reference*: a bare
pymunk loop with the same 2N + 1 bodies and walls that each step sets 2N velocities and reads
2N + 1 positions through pymunk's per-body attributes (``body.velocity = ...``,
``body.position``), then calls ``space.step(0.02)``. Target: env(Dict + say) >= 0.25
x the reference. Actions are drawn before timing.

Usage: python benchmarks/env_speed.py [--steps 1000] [--team-size 11] [--repeats 10]
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


class EnvRun:
    """One timed configuration of the env: random actions drawn before timing, warmed up;
    each call times ``steps`` steps and keeps the best rate (and that run's env.timings()).
    ``read``: every step also reads every agent's observation and info (the env builds the
    per-agent dicts of both on first access). ``every_key``: Dict actions also carry ``beam``
    and ``beam_request`` (0), as the action space's samples do."""

    def __init__(self, steps: int, team_size: int, action_format: str, seed: int = 0,
                 say: bool = False, read: bool = False, name: str | None = None,
                 every_key: bool = False, **obs: str) -> None:
        self.steps, self.read = steps, read
        self.name = name or (f"{action_format.capitalize()}" + (" + say" if say else "")
                             + (", read" if read else "") + (", every key" if every_key else ""))
        env = self.env = teamenv.parallel_env(team_size=team_size, action_format=action_format,
                                              rules={"half_time_s": 1e6}, **obs)
        env.reset(seed=seed)
        rng = np.random.default_rng(seed)
        profile = env.sim.channel.profile
        # Actions are drawn before timing: we measure the env, not the action sampler.
        self.pool = pool = []
        for _ in range(64):
            if action_format == "box":
                acts = rng.uniform(-1, 1, (len(env.agents), 9)).astype(np.float32)
                pool.append(dict(zip(env.agents, acts, strict=True)))
            else:
                acts = {}
                for a in env.agents:
                    acts[a] = {
                        "walk": rng.uniform([-1, -0.4, -1.5], [1.5, 0.4, 1.5]).astype(np.float32),
                        "kick": np.array([rng.random() * (rng.random() < 0.1), 0], np.float32)}
                    if say:
                        acts[a]["say"] = random_say(rng, profile)
                    if every_key:
                        acts[a]["beam"] = rng.uniform(env.parser.beam_low,
                                                      env.parser.beam_high).astype(np.float32)
                        acts[a]["beam_request"] = 0
                pool.append(acts)
        self.k = 0
        self._run(100)  # warm-up
        self.best = 0.0

    def _run(self, count: int) -> None:
        env, pool, k = self.env, self.pool, self.k
        if self.read:
            for j in range(k, k + count):
                observations, _, _, _, infos = env.step(pool[j % 64])
                for agent in observations:
                    observations[agent], infos[agent]
        else:
            for j in range(k, k + count):
                env.step(pool[j % 64])
        self.k = k + count

    def __call__(self) -> float:
        self.env.reset_timings()
        start = time.perf_counter()
        self._run(self.steps)
        rate = self.steps / (time.perf_counter() - start)
        if rate > self.best:
            self.best = rate
            PHASES[self.name] = {k: v / self.steps for k, v in self.env.timings().items()}
        return self.best


class ReferenceRun:
    """The reference loop: the env's World (the same 2N players + ball, goal posts,
    nets and walls) driven from plain Python through pymunk's per-body attributes. Each step
    sets 2N velocities (``body.velocity = (vx, vy)``), reads 2N + 1 positions
    (``body.position``), then calls ``space.step(0.02)``. Each call times ``steps`` steps and
    keeps the best rate."""

    def __init__(self, steps: int, team_size: int, field: str = "simspark",
                 seed: int = 0) -> None:
        env = teamenv.parallel_env(field=field, team_size=team_size)
        env.reset(seed=seed)
        world: World = env.sim.world
        self.space, self.players = world.space, world.players
        self.bodies = [*world.players, world.ball]
        rng = np.random.default_rng(seed)
        n = 2 * team_size
        self.vel = [[(float(vx), float(vy)) for vx, vy in rng.uniform(-1, 1, (n, 2))]
                    for _ in range(64)]
        self.steps, self.k, self.best = steps, 0, 0.0
        self._run(100)

    def _run(self, count: int) -> list:
        space, bodies, players, vel = self.space, self.bodies, self.players, self.vel
        positions = []
        for k in range(self.k, self.k + count):
            for body, v in zip(players, vel[k % 64], strict=True):
                body.velocity = v
            positions = [body.position for body in bodies]
            space.step(0.02)
        self.k += count
        return positions

    def __call__(self) -> float:
        start = time.perf_counter()
        self._run(self.steps)
        self.best = max(self.best, self.steps / (time.perf_counter() - start))
        return self.best


def bench_env(steps: int, team_size: int, action_format: str, seed: int = 0, say: bool = False,
              name: str | None = None, repeats: int = 1, read: bool = False, **obs: str) -> float:
    """Best steps/s of ``repeats`` timed runs of ``steps`` steps (timings of the best run)."""
    run = EnvRun(steps, team_size, action_format, seed, say, read, name, **obs)
    for _ in range(repeats):
        run()
    return run.best


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
    """Best steps/s of ``repeats`` runs of the reference loop (see ReferenceRun)."""
    run = ReferenceRun(steps, team_size, field, seed)
    for _ in range(repeats):
        run()
    return run.best


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
    for _ in range(steps):
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
    if sim.obs_mode.is_vision:
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
    parser.add_argument("--steps", type=int, default=1000, help="steps per timed run")
    parser.add_argument("--team-size", type=int, default=11)
    parser.add_argument("--repeats", type=int, default=10,
                        help="timed runs of the reference and each env run, in turn; the best "
                             "of each is kept")
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
    # The reference and the env runs are timed in turn, repeat after repeat, and each keeps
    # its best: on a shared machine every run sees the same quiet and busy spells.
    reference_run = ReferenceRun(s, n, field=args.field)
    runs = {"say": EnvRun(s, n, "dict", say=True, **obs),
            "read": EnvRun(s, n, "dict", say=True, read=True, **obs),
            "dict": EnvRun(s, n, "dict", **obs),
            "every": EnvRun(s, n, "dict", every_key=True, **obs),
            "box": EnvRun(s, n, "box", **obs)}
    for _ in range(r):
        reference_run()
        for run in runs.values():
            run()
    reference = reference_run.best
    env_say, env_read, env_dict, env_box = (runs[k].best for k in ("say", "read", "dict", "box"))
    world_rate, space_rate = bench_bare_pymunk(s, n)
    rows = [
        ("reference: per-body velocity/position + space.step", reference, None),
        ("bare pymunk: space.step only (env's substep rule)", space_rate, None),
        ("bare world: velocities + space.step + ball drag", world_rate, None),
        (f"env, {2 * n} agents, random Dict actions + say", env_say, reference),
        ("  same, reading every observation and info", env_read, reference),
        (f"env, {2 * n} agents, random Dict actions, silent", env_dict, reference),
        ("  same, every key (beam, beam_request too)", runs["every"].best, reference),
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
