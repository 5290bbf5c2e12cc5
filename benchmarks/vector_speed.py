"""Vectorized stepping: env steps/s and agent-steps/s for 1, 2 and 4 envs in subprocesses, against VMAS football on CPU, in one run.

teamenv: every player is a learner (no team plugin), random Box actions in [-1, 1]^9 drawn
before timing, state-mode Box observations, episodes of ``--max-cycles`` (resets included).
Vectorized with SuperSuit: ``pettingzoo_env_to_vec_env_v1`` (the agents become slots) and
``concat_vec_envs_v1(num_vec_envs=N, num_cpus=N)`` (N worker processes, shared-memory
observations); ``serial`` is one env stepped in this process through the same wrappers.

VMAS: ``vmas.make_env("football", device="cpu")`` with the same number of players, every one
an agent (``ai_red_agents=False``; with shooting, so actions include a kick, and without:
``--shooting``), random
continuous actions drawn before timing, at each batch size of ``--vmas-batches``; its best is
the batch size with the most agent-steps/s. VMAS steps all envs of a batch at once in torch.

Every configuration is timed ``--repeats`` times, interleaved (the machine may be shared); the
best and the median rates are kept. For the configurations that run in this process (serial
teamenv, VMAS) it also reports agent-steps per CPU-second of this process (the median), a rate
that other load on a shared machine does not change much. Writes ``benchmarks/results/vector_speed.json``.

Usage: python benchmarks/vector_speed.py [--team-sizes 5 11] [--envs 1 2 4] [--seconds 3]
                                         [--vmas-batches 1 8 32 128 512 2048 4096] [--repeats 3]
                                         [--shooting on|off|both]
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import sys
import time
from pathlib import Path

import numpy as np

import teamenv

RESULTS = Path(__file__).resolve().parent / "results" / "vector_speed.json"


class TeamenvVector:
    """N teamenv envs through SuperSuit (``workers`` processes; 0 = in this process)."""

    def __init__(self, team_size: int, n_envs: int, workers: int, max_cycles: int,
                 seed: int = 0) -> None:
        import supersuit

        env = teamenv.parallel_env(team_size=team_size, observation_format="box",
                                   action_format="box", max_cycles=max_cycles)
        self.agents_per_env = len(env.possible_agents)
        self.n_envs = n_envs
        self.in_process = workers == 0
        self.vec = supersuit.concat_vec_envs_v1(supersuit.pettingzoo_env_to_vec_env_v1(env),
                                                n_envs, num_cpus=workers)
        self.vec.reset(seed=seed)
        rng = np.random.default_rng(seed)
        # A pool of random actions, drawn before timing and cycled through.
        self.actions = rng.uniform(-1, 1, (64, self.vec.num_envs, 9)).astype(np.float32)

    def run(self, steps: int) -> None:
        for k in range(steps):
            self.vec.step(self.actions[k % len(self.actions)])

    def close(self) -> None:
        self.vec.close()


class VmasFootball:
    """VMAS's football scenario, ``batch`` envs stepped as one torch batch on the CPU."""

    def __init__(self, team_size: int, batch: int, seed: int = 0, shooting: bool = True) -> None:
        import torch
        import vmas

        self.env = vmas.make_env("football", num_envs=batch, device="cpu",
                                 continuous_actions=True, seed=seed, n_blue_agents=team_size,
                                 n_red_agents=team_size, ai_red_agents=False,
                                 enable_shooting=shooting)
        self.env.reset()
        self.agents_per_env = len(self.env.agents)
        self.n_envs = batch
        self.in_process = True
        generator = torch.Generator().manual_seed(seed)
        self.actions = [
            [torch.rand((batch, self.env.get_agent_action_size(agent)), generator=generator)
             * 2 - 1 for agent in self.env.agents]
            for _ in range(8)]

    def run(self, steps: int) -> None:
        for k in range(steps):
            self.env.step(self.actions[k % len(self.actions)])

    def close(self) -> None:
        pass


def calibrate(runner, seconds: float) -> int:
    """Steps that take about ``seconds`` (after a warm-up of the same kind)."""
    steps = 10
    while True:
        start = time.perf_counter()
        runner.run(steps)
        elapsed = time.perf_counter() - start
        if elapsed >= 0.25 * seconds or steps >= 1_000_000:
            return max(10, int(steps * seconds / elapsed))
        steps *= 4


def measure(configs: dict[str, object], seconds: float, repeats: int) -> dict[str, dict]:
    """Times every configuration ``repeats`` times, round-robin; rates per configuration."""
    steps = {name: calibrate(runner, seconds) for name, runner in configs.items()}
    rates: dict[str, list[float]] = {name: [] for name in configs}
    cpu_rates: dict[str, list[float]] = {name: [] for name in configs}
    for _ in range(repeats):
        for name, runner in configs.items():
            start, cpu_start = time.perf_counter(), time.process_time()
            runner.run(steps[name])
            rates[name].append(steps[name] / (time.perf_counter() - start))
            cpu_rates[name].append(steps[name] / max(time.process_time() - cpu_start, 1e-9))
    results = {}
    for name, runner in configs.items():
        best, median = max(rates[name]), statistics.median(rates[name])
        env_steps = runner.n_envs
        results[name] = {
            "envs": runner.n_envs, "agents_per_env": runner.agents_per_env,
            "vector_steps_timed": steps[name],
            "env_steps_per_s": best * env_steps,
            "agent_steps_per_s": best * env_steps * runner.agents_per_env,
            "env_steps_per_s_median": median * env_steps,
            "agent_steps_per_s_median": median * env_steps * runner.agents_per_env,
        }
        if runner.in_process:  # CPU time of this process is all the work: a load-free rate
            results[name]["agent_steps_per_cpu_s"] = (
                statistics.median(cpu_rates[name]) * env_steps * runner.agents_per_env)
    return results


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--team-sizes", type=int, nargs="+", default=[5, 11])
    parser.add_argument("--envs", type=int, nargs="*", default=[1, 2, 4],
                        help="vector sizes, each in as many worker processes (none: skip)")
    parser.add_argument("--max-cycles", type=int, default=1000)
    parser.add_argument("--vmas-batches", type=int, nargs="+",
                        default=[1, 8, 32, 128, 512, 2048, 4096])
    parser.add_argument("--shooting", choices=("on", "off", "both"), default="both",
                        help="VMAS football with its shooting action, without, or both")
    parser.add_argument("--seconds", type=float, default=3.0, help="per timed repeat")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--json", type=Path, default=RESULTS)
    args = parser.parse_args(argv)

    import torch

    load_before = os.getloadavg()
    report: dict = {
        "command": "python benchmarks/vector_speed.py " + " ".join(sys.argv[1:] if argv is None else argv),
        "machine": {"cpus": os.cpu_count(), "platform": platform.platform(),
                    "python": platform.python_version(), "torch": torch.__version__,
                    "torch_threads": torch.get_num_threads(),
                    "load_average_1_5_15_before": load_before},
        "team_sizes": {},
    }
    for team_size in args.team_sizes:
        configs: dict[str, object] = {
            "teamenv serial (1 env, in-process)": TeamenvVector(team_size, 1, 0, args.max_cycles)}
        for n in args.envs:
            configs[f"teamenv {n} env(s), {n} process(es)"] = TeamenvVector(
                team_size, n, n, args.max_cycles)
        shooting = {"on": (True,), "off": (False,), "both": (True, False)}[args.shooting]
        for shoots in shooting:
            for batch in args.vmas_batches:
                name = f"vmas football batch {batch}" + ("" if shoots else ", no shooting")
                configs[name] = VmasFootball(team_size, batch, shooting=shoots)
        try:
            results = measure(configs, args.seconds, args.repeats)
        finally:
            for runner in configs.values():
                runner.close()
        vmas_best = max((r for n, r in results.items() if n.startswith("vmas")),
                        key=lambda r: r["agent_steps_per_s"])
        ours_best = max((r for n, r in results.items() if n.startswith("teamenv")),
                        key=lambda r: r["agent_steps_per_s"])
        report["team_sizes"][f"{team_size}v{team_size}"] = {
            "results": results, "vmas_best_batch": vmas_best["envs"],
            "teamenv_best_over_vmas_best_agent_steps": (
                ours_best["agent_steps_per_s"] / vmas_best["agent_steps_per_s"])}
        print(f"\n{team_size} v {team_size} ({2 * team_size} agents per env)")
        print(f"{'configuration':40s} {'env steps/s':>12s} {'agent-steps/s':>14s} "
              f"{'(median)':>12s} {'per CPU-s':>12s}")
        for name, r in results.items():
            per_cpu = r.get("agent_steps_per_cpu_s")
            print(f"{name:40s} {r['env_steps_per_s']:12.0f} {r['agent_steps_per_s']:14.0f} "
                  f"{r['agent_steps_per_s_median']:12.0f} "
                  f"{'' if per_cpu is None else f'{per_cpu:12.0f}'}")
    report["machine"]["load_average_1_5_15_after"] = os.getloadavg()
    args.json.parent.mkdir(parents=True, exist_ok=True)
    args.json.write_text(json.dumps(report, indent=2) + "\n")
    print(f"\nwrote {args.json}")


if __name__ == "__main__":
    main()
