"""Regenerate the ``t1_league`` locomotion profile from what the league client's T1 does.

    python benchmarks/calibrate_t1_league.py --kicks kicks.json --getup getup.json \
        --replays study/league_replays          # measures the walk itself, writes the profile
    python benchmarks/calibrate_t1_league.py --skip-walk --kicks kicks.json --dry-run

Sources, each optional (a parameter without a source keeps its value and provenance):

- **walk** (measured here on ``LocalServer``, unless ``--skip-walk``): the league matches'
  default walking controller (``teamenv.league.match.WALKERS``) walks each command of an axis
  grid for ``--walk-seconds`` from ``--walk-trials`` start poses; the tracking curve of an axis
  is the median achieved velocity per command (trials that fell left out), and the envelope
  the largest achieved speed each way;
- **kicks**: kick-trial files of ``benchmarks/league_kick_trials.py --out`` (rows with the ball's
  ``travel`` and the direction ``error_deg``): distance mean / s.d. / min / max, and the
  accuracy as the share within the profile's ``kick_accuracy_half_angle``;
- **kick reach** (``--kick-reach``): the far corner of the league kick's start spot (the
  ball's farthest place from which the kick starts without backing away first);
- **kick angle** (``--kick-angle FILE``, from ``benchmarks/league_kick_angle.py --out``): the
  largest angle off the heading at which the kick, approached from beside the ball, still
  strikes with the robot up (``kick_max_angle``; the team then walks round the ball itself
  for kicks further off);
- **get-up**: a trial file of ``benchmarks/league_getup_trials.py --json``: with successes, the
  mean time to up; with none, the referee's rule stays (a robot that lay 15 s is stood up);
- **falls and get-up time in matches**: league replays (``teamenv league-tournament
  --replay-dir``, the study's ``league_replays``): falls per robot and minute of play and the
  share with another robot within 1 m just before, written into the profile's
  ``measurements`` (the 2D model's falls come from its push thresholds and command jumps,
  which these numbers are compared with); and the mean time a fallen robot stayed down
  (``teamenv.league.replay.down_times``: second tries and the referee included), which is the
  get-up time (it replaces the trials' time of the successes, which leaves those out);
- **the walk's falls** (``--fit-falls``, with ``--replays``): the command-jump fall model
  (``command_jump_threshold``, ``command_jump_fall_probability``) fitted so that teamenv,
  playing the replays' pairings under this profile, falls as often as the league robots did,
  alone and near another robot (``benchmarks/league_fall_fit.py``; minutes of CPU per grid
  point);
- **the kick's set-up** (``--fit-kick-setup``, with ``--replays``): ``kick_prep_time`` fitted
  so that teamenv's kick set-up time (``teamenv.league.replay.kick_setups``: from the kicker's
  last arrival within ``kick_reach`` of the ball to the contact) on the replays' pairings
  has the league's median (``benchmarks/league_kick_setup_fit.py``; ``--fit-matches N``
  plays the first N pairings only). ``--skip-getup`` keeps the get-up time and the fall
  statistics measured before (a run for the set-up alone changes nothing else).
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import league_fall_fit  # noqa: E402  (the sibling script)
import league_kick_setup_fit  # noqa: E402  (the sibling script)

ROOT = Path(__file__).resolve().parents[1]
PROFILE = ROOT / "locomotion" / "profiles" / "t1_league.json"
#: commands per axis (m/s, m/s, rad/s); each is walked along its axis only
AXES = {
    "vx": (-0.8, -0.4, -0.2, 0.2, 0.4, 0.8, 1.2, 1.5),
    "vy": (-0.3, -0.12, 0.12, 0.3),
    "turn": (-2.0, -1.0, -0.5, 0.5, 1.0, 2.0),
}
SCRIPT = "benchmarks/calibrate_t1_league.py"


def measure_walk(trials: int, seconds: float, seed0: int = 4000) -> dict[str, Any]:
    """Achieved velocity per command and axis with the league's default walker."""
    from locomotion.humanoid.envelope import achieved_velocity
    from teamenv.league.match import WALKERS, LeagueMatchOptions
    from teamenv.league.walk_trial import walk_trial

    walker = LeagueMatchOptions().walker
    make = WALKERS[walker]
    out: dict[str, Any] = {"walker": walker, "trials": trials, "seconds": seconds, "axes": {}}
    for k, (axis, commands) in enumerate(AXES.items()):
        rows = []
        for command in commands:
            cmd = tuple(command if a == axis else 0.0 for a in AXES)
            achieved, falls = [], 0
            for t in range(trials):
                rng = np.random.default_rng(seed0 + 100 * k + t)
                start = (float(rng.uniform(-20, -8)), float(rng.uniform(-12, 12)),
                         float(rng.uniform(-math.pi, math.pi)))
                r = walk_trial(make(), lambda _t, c=cmd: c, seconds, stand_s=1.0, start=start)
                if r.fell:
                    falls += 1
                    continue
                achieved.append(float(achieved_velocity(r.times, r.poses, 1.5)[k]))
            rows.append({"command": command, "achieved": achieved, "falls": falls})
            print(f"walk {axis} {command:+.2f}: achieved {np.round(achieved, 3).tolist()}, "
                  f"falls {falls}/{trials}", flush=True)
        out["axes"][axis] = rows
    return out


def walk_parameters(walk: dict[str, Any]) -> dict[str, dict]:
    """Tracking curves and envelope from ``measure_walk``'s result."""
    params: dict[str, dict] = {}
    src = (f"{SCRIPT}: the league's default walker ({walk['walker']}) on rcsssmj 0.2.1's "
           f"physics (LocalServer), {walk['trials']} start poses x {walk['seconds']:g} s per "
           "command, median achieved velocity after 1.5 s (falls left out); body frame")
    envelope: dict[str, float] = {}
    for axis, rows in walk["axes"].items():
        points = [(0.0, 0.0)]
        for row in rows:
            if row["achieved"]:
                points.append((float(row["command"]), float(np.median(row["achieved"]))))
        points.sort()
        # the profile's tables are non-decreasing: a median that dips below a slower command's
        # (noise, or a controller that barely moves one way) takes that command's value
        achieved = np.maximum.accumulate([a for _, a in points])
        points = [(c, round(float(a), 3)) for (c, _), a in zip(points, achieved, strict=True)]
        lo, hi = points[0], points[-1]
        # flat beyond the grid: the controller's envelope scales larger commands down
        curve = [[-3.0 if axis != "vy" else -1.0, lo[1]], *[[c, a] for c, a in points],
                 [3.0 if axis != "vy" else 1.0, hi[1]]]
        params[f"tracking_{axis}"] = {"value": curve, "unit": "rad/s" if axis == "turn" else "m/s",
                                      "kind": "measured", "source": src}
        fastest_pos = max((a for _, a in points), default=0.0)
        fastest_neg = -min((a for _, a in points), default=0.0)
        if axis == "vx":
            envelope["envelope_vx_forward"] = fastest_pos
            envelope["envelope_vx_backward"] = fastest_neg
        else:   # one envelope for both ways (the profile's is symmetric): the faster way
            envelope[f"envelope_{axis}"] = max(fastest_pos, fastest_neg)
    for name, value in envelope.items():
        params[name] = {"value": round(float(value), 3), "unit": "rad/s" if "turn" in name
                        else "m/s", "kind": "measured", "source": src + "; the fastest each way"}
    return params


def kick_parameters(paths: list[Path], half_angle_rad: float) -> dict[str, dict]:
    rows = [r for p in paths for r in json.loads(Path(p).read_text())["rows"]]
    kicked = [r for r in rows if r.get("kicked")]
    if len(kicked) < 2:
        raise SystemExit(f"--kicks: {len(kicked)} kicks in {[str(p) for p in paths]}; need >= 2")
    travel = np.array([r["travel"] for r in kicked], dtype=float)
    error = np.radians(np.array([r["error_deg"] for r in kicked], dtype=float))
    src = (f"{SCRIPT}: {len(kicked)} kicks of benchmarks/league_kick_trials.py "
           f"({', '.join(Path(p).name for p in paths)}; walking approach on LocalServer, "
           "distance = the ball's travel after the kick)")
    accuracy = float(np.mean(np.abs(error) <= half_angle_rad))
    durations = [r["kick_s"] for r in kicked if r.get("kick_s") is not None]
    timing = {} if not durations else {"kick_duration": {
        "value": round(float(np.mean(durations)), 2), "unit": "s", "kind": "measured",
        "source": src + "; mean time from the kick's start to its end"}}
    return timing | {
        "kick_distance_mean": {"value": round(float(travel.mean()), 3), "unit": "m",
                               "kind": "measured", "source": src},
        "kick_distance_std": {"value": round(float(travel.std(ddof=1)), 3), "unit": "m",
                              "kind": "measured", "source": src},
        "kick_distance_min": {"value": round(float(travel.min()), 3), "unit": "m",
                              "kind": "measured", "source": src},
        "kick_distance_max": {"value": round(float(travel.max()), 3), "unit": "m",
                              "kind": "measured", "source": src},
        "kick_accuracy": {"value": round(accuracy, 3), "unit": "1", "kind": "measured",
                          "source": src + f"; share within +-{math.degrees(half_angle_rad):.0f}"
                                          " deg of the aim"},
    }


def kick_reach_parameter() -> dict[str, dict]:
    """The league client's kick reach: the farthest ball (from the torso) from which its kick
    starts without stepping back first, the far corner of the kick spot (``teamenv.league.kick``:
    ``spot_x`` and ``foot_y`` of ``LEAGUE_KICK`` plus the start tolerances). A team that asks
    to kick only nearer walks into the ball and the approach has to back away from it."""
    from teamenv.league.kick import LEAGUE_KICK, SPOT_TOLERANCE_X, SPOT_TOLERANCE_Y

    ahead = LEAGUE_KICK.spot_x + SPOT_TOLERANCE_X[1]
    beside = LEAGUE_KICK.foot_y + SPOT_TOLERANCE_Y
    return {"kick_reach": {
        "value": round(math.hypot(ahead, beside), 2), "unit": "m", "kind": "derived",
        "source": f"{SCRIPT} --kick-reach: the far corner of the league kick's start spot "
                  f"(teamenv.league.kick: spot_x {LEAGUE_KICK.spot_x} + {SPOT_TOLERANCE_X[1]} "
                  f"ahead, foot_y {LEAGUE_KICK.foot_y} + {SPOT_TOLERANCE_Y} beside)"}}


def kick_angle_parameter(path: Path) -> dict[str, dict]:
    summary = json.loads(Path(path).read_text())["summary"]
    per = summary["per_offset"]
    shown = ", ".join(f"{float(k):.2f}: {v['counted']}/{v['trials']}" for k, v in per.items())
    return {"kick_max_angle": {
        "value": float(summary["kick_max_angle"]), "unit": "rad", "kind": "measured",
        "source": f"{SCRIPT} --kick-angle: the largest offset between heading and kick "
                  f"direction whose kick trials (benchmarks/league_kick_angle.py, "
                  f"{Path(path).name}; LocalServer, the network walking the approach from "
                  f"0.35-0.6 m behind the ball) struck with the robot up in at least "
                  f"{summary['pass_share']:.0%} (struck and up, by offset in rad: {shown})"}}


def getup_parameters(path: Path) -> dict[str, dict]:
    rows = json.loads(Path(path).read_text())
    ok = [r for r in rows if r.get("success") and r.get("time_to_up") is not None]
    if not ok:
        return {}   # the referee's rule (15 s) stays, with its own provenance
    times = np.array([r["time_to_up"] for r in ok], dtype=float)
    return {"getup_duration": {
        "value": round(float(times.mean()), 2), "unit": "s", "kind": "measured",
        "source": f"{SCRIPT}: mean time to up of {len(ok)}/{len(rows)} successful get-ups "
                  f"(benchmarks/league_getup_trials.py, {Path(path).name})"}}


def load_replays(replay_dir: Path) -> list:
    """Every league replay (``*.npz``) in ``replay_dir``, in name order, loaded once for the
    fall statistics and the get-up time."""
    from teamenv.replay import load_replay

    return [load_replay(path) for path in sorted(Path(replay_dir).glob("*.npz"))]


def getup_from_replays(replays: list, folder: str) -> dict[str, dict]:
    """The mean time fallen robots stayed down in league ``replays`` (from ``folder``), as
    ``getup_duration``."""
    from teamenv.league.replay import down_times

    times, still_down = [], 0
    for replay in replays:
        t, n = down_times(replay, float(replay.metadata["cycle_s"]))
        times += t.tolist()
        still_down += n
    if not times:
        return {}
    return {"getup_duration": {
        "value": round(float(np.mean(times)), 2), "unit": "s", "kind": "measured",
        "source": f"{SCRIPT}: mean time down of {len(times)} falls in league matches (second "
                  f"tries and the referee's stand-up included; {still_down} still down at a "
                  f"match's end left out), replays in {folder}"}}


def fall_statistics(replays: list, replay_dir: Path, near_m: float = 1.0) -> dict[str, Any]:
    """Falls per robot and minute of play in league ``replays`` (from ``replay_dir``), and the
    share near another robot (``league_fall_fit.fall_rates``, as the fit counts them)."""
    rates = league_fall_fit.fall_rates(replays, near_m)
    falls, robot_minutes = rates["falls_alone"] + rates["falls_near"], rates["robot_minutes"]
    return {"replays": len(replays), "robot_minutes": robot_minutes, "falls": falls,
            "falls_per_robot_minute": round(falls / robot_minutes, 4) if robot_minutes else None,
            f"share_within_{near_m:g}_m": round(rates["falls_near"] / falls, 3) if falls
            else None,
            "source": f"{SCRIPT} on {Path(replay_dir).name}"}


def update_profile(profile: dict[str, Any], params: dict[str, dict],
                   measurements: dict[str, Any]) -> dict[str, Any]:
    """``profile`` with ``params`` replacing its parameters (each keeps a note of what it
    replaced) and ``measurements`` added to ``measurements['league_client']`` (each kind
    replacing the same kind measured before)."""
    from locomotion.profile import OPTIONAL_PARAMETERS

    out = json.loads(json.dumps(profile))
    for name, entry in params.items():
        if name not in out["parameters"] and name not in OPTIONAL_PARAMETERS:
            raise SystemExit(f"profile has no parameter {name!r}")
        value, kind, _ = OPTIONAL_PARAMETERS.get(name, (None, None, None))
        old = out["parameters"].get(name, {"value": value, "kind": kind})
        entry = dict(entry)
        entry["note"] = f"replaces {old.get('value')!r} ({old.get('kind')})"
        out["parameters"][name] = entry
    if measurements:
        # measurements of this run replace their own kind only (a run without the walk keeps
        # the walk measured before)
        out.setdefault("measurements", {}).setdefault("league_client", {}).update(measurements)
    return out


def _grid(ap: argparse.ArgumentParser, points: list[str] | None
          ) -> tuple[tuple[float, float], ...]:
    if points is None:
        return league_fall_fit.GRID
    out = []
    for point in points:
        try:
            threshold, probability = (float(x) for x in point.split(":"))
        except ValueError:
            ap.error(f"--fit-grid: {point!r} is not THRESHOLD:PROBABILITY (e.g. 1.25:0.2)")
        out.append((threshold, probability))
    return tuple(out)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--profile", default=str(PROFILE), help="the profile to update (t1_league)")
    ap.add_argument("--out", default=None, help="write here instead of over --profile")
    ap.add_argument("--skip-walk", action="store_true", help="keep the walk parameters")
    ap.add_argument("--walk-trials", type=int, default=3, help="start poses per command")
    ap.add_argument("--walk-seconds", type=float, default=5.0, help="walking time per trial")
    ap.add_argument("--walk-json", default=None, help="also write the walk measurement here")
    ap.add_argument("--walk-from", default=None,
                    help="use this walk measurement (a --walk-json file) instead of measuring")
    ap.add_argument("--kicks", nargs="*", default=[], help="league_kick_trials.py --out files")
    ap.add_argument("--kick-reach", action="store_true",
                    help="the kick reach from the league kick's start spot")
    ap.add_argument("--kick-angle", default=None, help="league_kick_angle.py --out file")
    ap.add_argument("--getup", default=None, help="league_getup_trials.py --json file")
    ap.add_argument("--replays", default=None, help="a folder of league match replays")
    ap.add_argument("--fit-falls", action="store_true",
                    help="with --replays: fit the command-jump fall model to the league's falls")
    ap.add_argument("--fit-seconds", type=float, default=60.0,
                    help="game time of each fit match (s)")
    ap.add_argument("--fit-seed", type=int, default=league_fall_fit.SEED0,
                    help="first (tuning) seed of the fit's matches")
    ap.add_argument("--fit-grid", nargs="+", default=None, metavar="THRESHOLD:PROBABILITY",
                    help="the (threshold, probability) points to try (default: "
                    + " ".join(f"{t:g}:{p:g}" for t, p in league_fall_fit.GRID) + ")")
    ap.add_argument("--skip-getup", action="store_true",
                    help="with --replays: keep the get-up time and the fall statistics")
    ap.add_argument("--fit-kick-setup", action="store_true",
                    help="with --replays: fit kick_prep_time to the league kick's set-up time")
    ap.add_argument("--fit-matches", type=int, default=None,
                    help="--fit-kick-setup plays the pairings of the first N replays (default "
                    "all)")
    ap.add_argument("--fit-prep-grid", nargs="+", type=float, default=None, metavar="SECONDS",
                    help="the kick_prep_time values to try (default: "
                    + " ".join(f"{g:g}" for g in league_kick_setup_fit.GRID) + ")")
    ap.add_argument("--dry-run", action="store_true", help="print, write nothing")
    args = ap.parse_args(argv)
    profile = json.loads(Path(args.profile).read_text())
    params: dict[str, dict] = {}
    measurements: dict[str, Any] = {}
    if not args.skip_walk:
        walk = json.loads(Path(args.walk_from).read_text()) if args.walk_from else \
            measure_walk(args.walk_trials, args.walk_seconds)
        if args.walk_json:
            Path(args.walk_json).write_text(json.dumps(walk, indent=1))
        params |= walk_parameters(walk)
        measurements["walk"] = walk
    if args.kicks:
        half = float(profile["parameters"]["kick_accuracy_half_angle"]["value"])
        params |= kick_parameters([Path(p) for p in args.kicks], half)
    if args.kick_reach:
        params |= kick_reach_parameter()
    if args.kick_angle:
        params |= kick_angle_parameter(Path(args.kick_angle))
    if args.getup:
        params |= getup_parameters(Path(args.getup))
    if args.replays:
        replays = load_replays(Path(args.replays))
        if not args.skip_getup:
            measurements["falls"] = fall_statistics(replays, Path(args.replays))
            print("falls:", measurements["falls"])
            # matches count the retries
            params |= getup_from_replays(replays, Path(args.replays).name)
        if args.fit_falls:
            # the fit plays under the profile as updated so far (the get-up time included)
            current = update_profile(profile, params, {})
            fitted, record = league_fall_fit.fit(current, replays, args.fit_seconds,
                                                 grid=_grid(ap, args.fit_grid),
                                                 seed0=args.fit_seed,
                                                 source=Path(args.replays).name)
            params |= fitted
            measurements["fall_fit"] = record
        if args.fit_kick_setup:
            # played under the profile as updated so far (the fitted falls included)
            current = update_profile(profile, params, {})
            fitted, record = league_kick_setup_fit.fit(
                current, replays, args.fit_seconds,
                grid=tuple(args.fit_prep_grid or league_kick_setup_fit.GRID),
                seed0=args.fit_seed, matches=args.fit_matches, source=Path(args.replays).name)
            params |= fitted
            measurements["kick_setup_fit"] = record
    elif args.fit_falls or args.fit_kick_setup:
        ap.error("--fit-falls and --fit-kick-setup need --replays")
    updated = update_profile(profile, params, measurements)
    if params:
        # the description lists everything this script regenerated, in this run or before
        regenerated = {name for name, entry in updated["parameters"].items()
                       if str(entry.get("source", "")).startswith(SCRIPT)}
        parts = []
        if "tracking_vx" in regenerated:
            from teamenv.league.match import LeagueMatchOptions

            walker = measurements["walk"]["walker"] if "walk" in measurements else \
                LeagueMatchOptions().walker
            parts.append(f"walk curves and envelope of the league's default walker ({walker})")
        if "kick_distance_mean" in regenerated:
            parts.append("kick distance, accuracy and duration from kick trials with a walking "
                         "approach")
        if "kick_reach" in regenerated:
            parts.append("kick reach from the league kick's start spot")
        if "kick_max_angle" in regenerated:
            parts.append("the kick's largest angle off the heading from kick trials")
        if "command_jump_fall_probability" in regenerated:
            parts.append("the walk's falls fitted to league matches")
        if "kick_prep_time" in regenerated:
            parts.append("the kick's set-up time fitted to league matches")
        if "getup_duration" in regenerated:
            parts.append("get-up time from " + (
                "league matches" if "league matches" in
                updated["parameters"]["getup_duration"]["source"] else "get-up trials"))
        updated["description"] = (
            "The league's Booster T1 on RCSSServerMJ 0.2.1 as teamenv's league client plays it, "
            f"regenerated by {SCRIPT} on the server's own physics (LocalServer): "
            + "; ".join(parts) + " (each parameter's source says how). Everything not "
            "listed as measured is t1_mj's.")
    for name in params:
        print(f"{name}: {profile['parameters'][name].get('value')!r} -> "
              f"{updated['parameters'][name]['value']!r}")
    if not args.dry_run:
        from locomotion.profile import load_profile

        target = Path(args.out or args.profile)
        target.write_text(json.dumps(updated, indent=2) + "\n")
        load_profile(target)   # the loader's checks: a bad value fails here, not in a match
        print(f"wrote {target}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
