"""Statistics speed and replay size of a full 11 v 11 match (30,000 cycles).

    python benchmarks/analytics_speed.py --replay-dir /tmp/speed            # play, then time
    python benchmarks/analytics_speed.py --replay-dir /tmp/speed --half-time 30 --tile 10
    python benchmarks/analytics_speed.py --replay out/m.npz --cli      # time a replay you have

Plays (once; a replay already in ``--replay-dir`` is reused) one match ``--left`` vs
``--right`` (default full vs full, both annotate) on ``simspark`` 11 v 11, 2 x
``--half-time`` s (default 300: 30,000 cycles), in ``--observation`` mode, recorded with
extras; writes it twice, with and without the extras (each agent's belief pose, ball, role and
role vector), and reports both file sizes (and, for a shorter match, the size scaled to 30,000
cycles). Then times (CPU seconds of the process, best of ``--repeats``): loading the replay, ``match_events`` and
``match_stats`` (what ``teamenv stats`` does, less printing), and the HTML report's figures.
``--tile K`` also times a synthetic replay made of the recorded match K times in a row (its
events shifted), to time a full-length replay when playing one is too slow. ``--replay PATH``
times that replay instead of playing one. ``--cli`` also times the command a user runs,
``python -m teamenv stats PATH`` in a child process (interpreter start and imports included;
CPU seconds of the child, best of ``--repeats``).
"""

from __future__ import annotations

import argparse
import json
import resource
import subprocess
import sys
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any


def play(replay_dir: Path, left: str, right: str, seed: int, observation: str,
         half_time: float) -> tuple[Path, Path, dict[str, Any] | None]:
    """The replay with and without extras, and how long playing it took (cycles, wall and CPU
    seconds; None when both files were there already and nothing was played)."""
    import teamenv
    from teamenv.replay import ReplayRecorder

    stem = f"{left}-{right}-{seed}-{observation}-{half_time:g}"
    with_extras, plain = replay_dir / f"{stem}-extras.npz", replay_dir / f"{stem}.npz"
    if with_extras.exists() and plain.exists():
        return with_extras, plain, None
    env = teamenv.parallel_env(left=left, right=right, field="simspark", team_size=11,
                               observation_mode=observation, profile_phases=False,
                               rules={"half_time_s": half_time})
    recorder = ReplayRecorder(env, extras=True)
    env.reset(seed=seed)
    recorder.record()
    start, cpu = time.perf_counter(), time.process_time()
    while not env.episode_over:
        env.step({})
        recorder.record()
    played = {"cycles": int(env.sim.cycle), "wall_s": time.perf_counter() - start,
              "cpu_s": time.process_time() - cpu}
    print(f"played {env.sim.cycle} cycles in {played['wall_s']:.0f} s wall "
          f"({played['cpu_s']:.0f} s CPU)")
    meta = {"left": left, "right": right, "seed": seed}
    recorder.save(with_extras, meta)
    recorder.extras = False  # the same match, written without the extras
    recorder.save(plain, meta)
    return with_extras, plain, played


def tiled(path: Path, times: int, out: Path) -> Path:
    """Write the replay at ``path`` ``times`` times in a row (events shifted) to ``out``."""
    import numpy as np

    from teamenv.replay import write_replay

    with np.load(path) as data:
        arrays = {k: data[k] for k in data.files}
    t = len(arrays["time_s"])
    per_cycle = [k for k, v in arrays.items() if k != "metadata" and len(v) == t
                 and not k.endswith(("_cycle", "_player", "_distance", "_direction", "_team"))]
    events = [k for k in arrays if k.startswith(("kick_", "touch_", "goal_"))]
    out_arrays = dict(arrays)
    for k in per_cycle:
        out_arrays[k] = np.concatenate([arrays[k]] * times)
    out_arrays["time_s"] = np.concatenate([arrays["time_s"] + i * (arrays["time_s"][-1] + 0.02)
                                           for i in range(times)])
    for k in events:
        parts = [arrays[k] + i * t if k.endswith("_cycle") else arrays[k] for i in range(times)]
        out_arrays[k] = np.concatenate(parts)
    meta = json.loads(out_arrays.pop("metadata").tobytes().decode())
    return write_replay(out, out_arrays, meta)  # a new checksum for the new content


WALL: dict[str, float] = {}


def best_of(repeats: int, fn: Any, label: str = "") -> tuple[float, Any]:
    """(least CPU seconds of this process over ``repeats`` calls, the last result); the least
    wall seconds go to ``WALL[label]``. CPU time is the measure: on a shared, loaded machine
    the wall clock also counts the other programs' turns."""
    best, out = float("inf"), None
    wall = float("inf")
    for _ in range(repeats):
        t0, w0 = time.process_time(), time.perf_counter()
        out = fn()
        best = min(best, time.process_time() - t0)
        wall = min(wall, time.perf_counter() - w0)
    WALL[label] = wall
    return best, out


def cli_time(repeats: int, path: Path) -> tuple[float, float]:
    """(least CPU seconds, least wall seconds) of ``python -m teamenv stats path`` in a child."""
    best_cpu = best_wall = float("inf")
    for _ in range(repeats):
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        w0 = time.perf_counter()
        subprocess.run([sys.executable, "-m", "teamenv", "stats", str(path)], check=True,
                       stdout=subprocess.DEVNULL)
        wall = time.perf_counter() - w0
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
        best_cpu, best_wall = min(best_cpu, cpu), min(best_wall, wall)
    return best_cpu, best_wall


def main(argv: Sequence[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--replay-dir", type=Path)
    parser.add_argument("--left", default="full")
    parser.add_argument("--right", default="full")
    parser.add_argument("--seed", type=int, default=5000)
    parser.add_argument("--observation", default="state", choices=("state", "vision"))
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--half-time", type=float, default=300.0)
    parser.add_argument("--tile", type=int, default=1, help="also time the match K times in a row")
    parser.add_argument("--replay", type=Path, help="time this replay instead of playing one")
    parser.add_argument("--cli", action="store_true",
                        help="also time `python -m teamenv stats REPLAY` in a child process")
    parser.add_argument("--json", type=Path)
    args = parser.parse_args(argv)
    if args.replay is None and args.replay_dir is None:
        parser.error("give --replay-dir (to play a match) or --replay (to time a replay)")
    from teamenv.analytics.events import match_events
    from teamenv.analytics.figures import match_figures
    from teamenv.analytics.stats import match_stats
    from teamenv.analytics.xg import XGModel
    from teamenv.replay import load_replay

    model = XGModel.load()
    if args.replay is not None:
        out: dict[str, Any] = {"match": str(args.replay)}
        runs = [("replay", args.replay)]
    else:
        args.replay_dir.mkdir(parents=True, exist_ok=True)
        with_extras, plain, played = play(args.replay_dir, args.left, args.right, args.seed,
                                          args.observation, args.half_time)
        out = {"match": f"{args.left} vs {args.right}, simspark 11 v 11, 2 x "
                        f"{args.half_time:g} s, seed {args.seed}, {args.observation} mode"}
        if played:
            out["played"] = played
        runs = [("plain", plain), ("extras", with_extras)]
    out["xg_model"] = model.fitted.get("data", "")
    if args.tile > 1:
        src = runs[-1][1]
        runs.append((f"{runs[-1][0]} x{args.tile}",
                     tiled(src, args.tile, src.with_name(f"tiled-{args.tile}-{src.name}"))))
    for label, path in runs:
        load_s, replay = best_of(args.repeats, lambda p=path: load_replay(p))
        events_s, events = best_of(args.repeats, lambda r=replay: match_events(r))
        stats_s, _ = best_of(args.repeats, lambda r=replay, e=events: match_stats(r, model, e))
        total_s, stats = best_of(args.repeats, lambda p=path: match_stats(load_replay(p), model),
                                 label)
        size_mb = path.stat().st_size / 1e6
        out[label] = {"cycles": len(replay) - 1, "size_mb": size_mb,
                      "size_mb_per_30000_cycles": size_mb * 30000 / max(len(replay) - 1, 1),
                      "load_s": load_s, "events_s": events_s, "stats_s": stats_s,
                      "load_events_stats_s": total_s, "load_events_stats_wall_s": WALL[label]}
        print(f"{label:6s}: {len(replay) - 1} cycles, {size_mb:.2f} MB "
              f"({size_mb * 30000 / max(len(replay) - 1, 1):.2f} MB per 30,000 cycles); "
              f"load {load_s:.3f} s, events {events_s:.3f} s, stats {stats_s:.3f} s; "
              f"load + events + stats {total_s:.3f} s CPU ({WALL[label]:.3f} s wall), best of "
              f"{args.repeats}")
        if args.cli:
            cli_cpu, cli_wall = cli_time(args.repeats, path)
            out[label].update(cli_stats_s=cli_cpu, cli_stats_wall_s=cli_wall)
            print(f"        python -m teamenv stats: {cli_cpu:.2f} s CPU ({cli_wall:.2f} s wall)")
    figures_s, _ = best_of(1, lambda: match_figures(replay, events, stats))
    out["figures_s"] = figures_s
    print(f"report figures: {figures_s:.2f} s")
    if args.json:
        args.json.write_text(json.dumps(out, indent=1) + "\n")


if __name__ == "__main__":
    main()
