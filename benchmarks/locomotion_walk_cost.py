"""Benchmark: cost of locomotion.Bodies.step for 22 players per 20 ms cycle (target < 5% of ~1 ms)."""

from __future__ import annotations

import argparse
import time

import numpy as np

import locomotion

ENV_STEP_US = 1000.0  # an env step is about 1 ms (DESIGN.md); the target is 5% of it


def bench(profile: str, n: int, cycles: int, scenario: str, seed: int = 0) -> float:
    """Mean wall time (µs) of one Bodies.step call over ``cycles`` calls after a warm-up."""
    p = locomotion.load_profile(profile)
    b = locomotion.Bodies(p, n)
    rng = np.random.default_rng(seed)
    crng = np.random.default_rng(seed + 1)
    cmds = crng.uniform(p.command_low, p.command_high, size=(64, n, 3))
    z = np.zeros(n)
    if scenario == "match":  # new commands every cycle, occasional kicks and collisions
        reqs = crng.random((64, n)) < 0.005
        imps = np.where(crng.random((64, n)) < 0.01, crng.exponential(10.0, (64, n)), 0.0)
    elif scenario == "stress":  # many kicks and falls at once
        reqs = crng.random((64, n)) < 0.05
        imps = crng.exponential(5.0, (64, n))
    else:  # steady walking, nobody kicks or falls
        reqs = np.zeros((64, n), bool)
        imps = np.zeros((64, n))
        cmds[:] = cmds[0]
    power = np.full(n, 0.8)
    for i in range(500):
        b.step(cmds[i % 64], reqs[i % 64], power, z, imps[i % 64], rng)
    t0 = time.perf_counter()
    for i in range(cycles):
        b.step(cmds[i % 64], reqs[i % 64], power, z, imps[i % 64], rng)
    return (time.perf_counter() - t0) / cycles * 1e6


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--players", type=int, default=22)
    ap.add_argument("--cycles", type=int, default=20000)
    args = ap.parse_args()
    print(
        f"locomotion.Bodies.step, {args.players} players, {args.cycles} cycles, numpy {np.__version__}"
    )
    for profile in ("t1_mj", "nao_simspark"):
        for scenario in ("steady", "match", "stress"):
            us = bench(profile, args.players, args.cycles, scenario)
            print(
                f"  {profile:13s} {scenario:6s}: {us:7.1f} µs/cycle = {100 * us / ENV_STEP_US:4.1f}% of a "
                f"{ENV_STEP_US:.0f} µs env step (target < 5%)  {'OK' if us < 0.05 * ENV_STEP_US else 'MISSED'}"
            )


if __name__ == "__main__":
    main()
