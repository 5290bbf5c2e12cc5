"""Benchmark: how fast the replay viewer opens a full 11 v 11 match and starts playing.

Records (once) a full-length match, ``full`` v ``chaser`` on ``simspark``, 11 v 11, two halves
of 300 s (30,000 cycles; ~3 min of CPU), as ``teamenv match full chaser --replay PATH`` does,
then in headless chromium (Debian's, driven by Playwright) opens ``/?autoplay=1`` and waits
until the page has drawn a cycle later than the first while playing. Timed:

- ``navigation -> playing``: wall time from ``page.goto`` to that frame, measured in Python;
- in the page (``performance.now()``, from the start of navigation): header loaded, core
  arrays loaded (what playing needs), first frame drawn (ready), first played frame, and the
  overlay arrays loaded (they arrive while it plays).

``cold``: a fresh source and server per run: ``teamenv view`` loads and checks the .npz
before it serves (timed apart, ``load``) and then encodes the arrays in the background while
the browser starts, as the page's first request would; ``warm``:
the same server again (the encoded replay is kept). A new browser page every run;
the browser's own launch is reported apart. ``--repeat`` runs (default 3); min and median are
printed. Usage::

    .venv/bin/python benchmarks/viewer_startup.py [--replay out/bench/full_11v11.npz] \
        [--repeat 3] [--json out/bench/viewer_startup.json] \
        [--screenshot docs/viewer.png --cycle 1200 --select 6]
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import time
from pathlib import Path

from teamenv.match import MatchOptions, play_match
from teamenv.viewer.server import ViewerServer
from teamenv.viewer.sources import open_source

PLAYING = "window.teamenvViewer && teamenvViewer.state.timing.playingMs !== undefined"


def record_full_match(path: Path) -> None:
    print(f"recording a full 11 v 11 match to {path} (full v chaser, seed 0) ...", flush=True)
    start = time.perf_counter()
    result = play_match("full", "chaser", seed=0, options=MatchOptions(), replay_path=path)
    print(f"  {result.summary().splitlines()[0]}  [{time.perf_counter() - start:.0f} s]")


def open_and_play(browser, server: ViewerServer) -> dict[str, float]:
    page = browser.new_page(viewport={"width": 1400, "height": 900}, device_scale_factor=1)
    try:
        start = time.perf_counter()
        page.goto(server.url + "?autoplay=1")
        page.wait_for_function(PLAYING, timeout=120_000, polling="raf")
        wall = time.perf_counter() - start
        page.wait_for_function("teamenvViewer.state.overlaysLoaded", timeout=120_000)
        timing = page.evaluate("teamenvViewer.state.timing")
        cycles = page.evaluate("teamenvViewer.state.nCycles")
    finally:
        page.close()
    return {"wall_s": wall, "cycles": cycles, **{k: v / 1000.0 for k, v in timing.items()}}


def screenshot(browser, server: ViewerServer, path: Path, cycle: int, select: int | None) -> None:
    page = browser.new_page(viewport={"width": 1400, "height": 860}, device_scale_factor=1)
    try:
        page.goto(server.url + f"?cycle={cycle}")
        page.wait_for_function(f"window.teamenvViewer && teamenvViewer.state.cycle === {cycle}"
                               " && !['—', 'computing…'].includes("
                               "document.getElementById('stats-body').textContent)",
                               timeout=120_000)
        if select is not None:
            page.evaluate(f"teamenvViewer.select({select})")
        path.parent.mkdir(parents=True, exist_ok=True)
        page.screenshot(path=str(path))
    finally:
        page.close()
    print(f"screenshot: {path}")


def summary(runs: list[dict[str, float]], key: str) -> str:
    values = [r[key] for r in runs]
    return f"min {min(values):6.3f} s   median {statistics.median(values):6.3f} s"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--replay", type=Path, default=Path("out/bench/full_11v11.npz"),
                        help="a full-match replay (recorded here when missing)")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--json", type=Path, default=None, help="write the runs here")
    parser.add_argument("--screenshot", type=Path, default=None,
                        help="also save a screenshot of the page here (docs/viewer.png)")
    parser.add_argument("--cycle", type=int, default=0, help="the screenshot's cycle")
    parser.add_argument("--select", type=int, default=None,
                        help="the screenshot's selected player (index 0 .. 2N-1)")
    args = parser.parse_args()
    if not args.replay.is_file():
        record_full_match(args.replay)

    from playwright.sync_api import sync_playwright

    chromium = shutil.which("chromium")
    if chromium is None:
        raise SystemExit("needs Debian's chromium on PATH: apt-get install -y chromium")
    results: dict[str, list[dict[str, float]]] = {"cold": [], "warm": []}
    with sync_playwright() as playwright:
        start = time.perf_counter()
        browser = playwright.chromium.launch(
            executable_path=chromium, headless=True,
            args=["--disable-dev-shm-usage"] + (["--no-sandbox"] if os.geteuid() == 0 else []))
        launch_s = time.perf_counter() - start
        for _ in range(args.repeat):
            start = time.perf_counter()
            source = open_source(args.replay)  # as `teamenv view` does before it serves
            source_s = time.perf_counter() - start
            with ViewerServer(source).start() as server:
                results["cold"].append({"load_s": source_s, **open_and_play(browser, server)})
                results["warm"].append(open_and_play(browser, server))
        if args.screenshot:
            with ViewerServer(open_source(args.replay)).start() as server:
                screenshot(browser, server, args.screenshot, args.cycle, args.select)
        browser.close()
    with ViewerServer(open_source(args.replay)) as server:
        header, blobs = server.encoded(0)
    sizes = {group: len(blob) for group, blob in blobs.items()}
    print(f"replay {args.replay}: {header['cycles']} cycles, {2 * header['team_size']} players, "
          f"{args.replay.stat().st_size / 1e6:.1f} MB on disk, arrays sent: "
          + ", ".join(f"{group} {n / 1e6:.1f} MB" for group, n in sizes.items())
          + f"; chromium {chromium}, launched in {launch_s:.2f} s")
    for kind, runs in results.items():
        print(f"{kind} ({len(runs)} runs)")
        if kind == "cold":
            print(f"  {'load + check the .npz (before serving)':40s}  {summary(runs, 'load_s')}")
        print(f"  {'navigation -> playing (wall)':40s}  {summary(runs, 'wall_s')}")
        for key, label in (("headerMs", "header loaded"), ("arraysMs", "core arrays loaded"),
                           ("readyMs", "first frame drawn"), ("playingMs", "first played frame"),
                           ("overlaysMs", "overlay arrays loaded (playing)")):
            print(f"  {label:40s}  {summary(runs, key)}")
    if args.json:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps({"replay": str(args.replay), "launch_s": launch_s,
                                         "bytes": sizes, **results}, indent=2))


if __name__ == "__main__":
    main()
