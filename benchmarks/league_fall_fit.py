"""Fit the 2D body's falls to the league robots': the command-jump fall model of a profile.

The env's bodies fall from collisions and pushes (thresholds measured on the humanoid) and
from **command jumps**: at a step boundary, a demanded velocity change larger than
``command_jump_threshold`` (in units of the body's acceleration limits over a step) fells the
body with ``command_jump_fall_probability``. On the league server most falls come from what
the team asks the walk to do, so those two numbers decide how often a teamenv robot falls.

``fit`` plays, for each (threshold, probability) of a grid, the pairings of the league
replays again in teamenv (the study's env options: ``mj7v7``, vision ``mj``, channel ``mj``,
the league's double-touch rule; one match per pairing of ``seconds``, on tuning seeds) with
the profile changed in those two numbers only, counts every match's falls the way the
league's are counted (``teamenv.league.replay.fall_events``: latched falls during play, and
whether another robot was within 1 m just before), and keeps the grid point whose falls per
robot-minute, alone and near another robot, are nearest the league's (the sum of the squared
relative errors). Used by ``benchmarks/calibrate_t1_league.py --fit-falls``::

    python benchmarks/calibrate_t1_league.py --skip-walk --replays study/league_replays \
        --fit-falls
"""

from __future__ import annotations

import json
import sys
import tempfile
from collections.abc import Sequence
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))
from fidelity_study import env_options  # noqa: E402  (the sibling script: the study's options)

#: (command_jump_threshold, command_jump_fall_probability) points tried by default
GRID: tuple[tuple[float, float], ...] = ((1.0, 0.1), (1.0, 0.15), (1.25, 0.2), (1.25, 0.3),
                                         (1.5, 0.3), (1.5, 0.45))
NEAR_M = 1.0
#: the first tuning seed of the fit's matches (one per pairing, consecutive)
SEED0 = 41_000


def fall_rates(replays: Sequence[Any], near_m: float = NEAR_M,
               side: int | None = None) -> dict[str, float]:
    """Falls per robot-minute of play in ``replays`` (league or teamenv), alone and with
    another robot within ``near_m`` just before (``fall_events``), and the robot-minutes.
    ``side``: count only the robots of the left (0) or the right (1) team."""
    from teamenv.league.replay import fall_events

    alone = near = 0
    robot_minutes = 0.0
    for replay in replays:
        playing = replay.play_mode != 0
        cycle_s = float(replay.metadata["cycle_s"])
        robots = replay.fallen.shape[1]
        counted = range(robots) if side is None else \
            range(side * robots // 2, (side + 1) * robots // 2)
        robot_minutes += float(playing.sum()) * cycle_s / 60.0 * len(counted)
        for fall in fall_events(replay):
            if playing[fall.row] and fall.player in counted:
                if fall.nearest_m < near_m:
                    near += 1
                else:
                    alone += 1
    per = (lambda k: round(k / robot_minutes, 4)) if robot_minutes else (lambda k: None)
    return {"robot_minutes": round(robot_minutes, 2), "falls_alone": alone, "falls_near": near,
            "alone_per_robot_minute": per(alone), "near_per_robot_minute": per(near)}


def pairings(replays: Sequence[Any]) -> list[tuple[str, str]]:
    """The (left, right) team specs of the replays' matches, in order."""
    return [(str(r.metadata["left"]), str(r.metadata["right"])) for r in replays]


def play_replays(profile_path: Path, matches: Sequence[tuple[str, str]], seconds: float,
                 team_size: int, seed0: int, folder: Path) -> list[Any]:
    """The replays of teamenv playing ``matches`` under the profile file (the study's
    options, ``seconds`` each, seeds from ``seed0``; the files in ``folder`` are removed).
    No stall timeout: a measurement on a busy machine must not turn into a forfeit."""
    from teamenv.match import play_match
    from teamenv.replay import load_replay
    from teamenv.tournament.spec import parse_team_spec

    options = env_options(seconds, team_size, str(profile_path))
    replays = []
    for k, (left, right) in enumerate(matches):
        a, b = parse_team_spec(left), parse_team_spec(right)
        path = folder / f"fit-{k:03d}.npz"
        result = play_match(a.name, b.name, seed0 + k, options, left_config=dict(a.config),
                            right_config=dict(b.config), replay_path=path,
                            stall_timeout_s=None)
        if result.forfeit is not None:
            raise SystemExit(f"fit: {left} v {right} (seed {seed0 + k}) forfeited: "
                             f"{result.forfeit}")
        replays.append(load_replay(path))
        path.unlink()
    return replays


def play_rates(profile_path: Path, matches: Sequence[tuple[str, str]], seconds: float,
               team_size: int, seed0: int, folder: Path) -> dict[str, float]:
    """Falls per robot-minute when teamenv plays ``matches`` under the profile file."""
    return fall_rates(play_replays(profile_path, matches, seconds, team_size, seed0, folder))


def _error(rates: dict[str, float], target: dict[str, float]) -> float:
    return sum(((rates[k] - target[k]) / target[k]) ** 2
               for k in ("alone_per_robot_minute", "near_per_robot_minute") if target[k])


def fit(profile: dict[str, Any], replays: Sequence[Any], seconds: float = 60.0,
        grid: Sequence[tuple[float, float]] = GRID, seed0: int = SEED0,
        source: str = "league replays") -> tuple[dict[str, dict], dict[str, Any]]:
    """The two command-jump parameters that bring teamenv's falls nearest the league's in
    ``replays``, as profile entries, and the fit's record (every grid point's rates)."""
    from locomotion.profile import load_profile
    from teamenv.seeds import TUNING_SEEDS

    target = fall_rates(replays)
    matches = pairings(replays)
    if not matches or not target["robot_minutes"]:
        raise SystemExit("--fit-falls: no league replays with play to fit to")
    if not target["falls_alone"] + target["falls_near"]:
        raise SystemExit("--fit-falls: the league replays have no falls to fit to")
    team_size = int(replays[0].metadata["team_size"])
    if seed0 not in TUNING_SEEDS or seed0 + len(matches) - 1 not in TUNING_SEEDS:
        raise SystemExit(f"--fit-seed {seed0}: the fit's {len(matches)} seeds must be tuning "
                         f"seeds ({TUNING_SEEDS.first}-{TUNING_SEEDS.end - 1})")
    points = []
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        for threshold, probability in grid:
            candidate = json.loads(json.dumps(profile))
            for name, value in (("command_jump_threshold", threshold),
                                ("command_jump_fall_probability", probability)):
                candidate["parameters"][name]["value"] = value
            path = folder / "candidate.json"
            path.write_text(json.dumps(candidate))
            load_profile(path)   # a bad grid point fails here, named
            rates = play_rates(path, matches, seconds, team_size, seed0, folder)
            points.append({"threshold": threshold, "probability": probability, **rates,
                           "error": round(_error(rates, target), 4)})
            print(f"fit: threshold {threshold:g}, probability {probability:g}: alone "
                  f"{rates['alone_per_robot_minute']}, near {rates['near_per_robot_minute']} "
                  f"per robot-minute (league {target['alone_per_robot_minute']}, "
                  f"{target['near_per_robot_minute']})", flush=True)
    best = min(points, key=lambda p: p["error"])
    how = (f"benchmarks/calibrate_t1_league.py --fit-falls: of the grid "
           f"{[tuple(g) for g in grid]} (threshold, probability), the point whose teamenv falls "
           f"per robot-minute, alone and within {NEAR_M:g} m of another robot, came nearest "
           f"the league's in {len(matches)} matches of {source} (league {target['alone_per_robot_minute']}"
           f" alone, {target['near_per_robot_minute']} near; teamenv {best['alone_per_robot_minute']}, "
           f"{best['near_per_robot_minute']}): the same pairings, {seconds:g} s each, tuning "
           f"seeds {seed0}-{seed0 + len(matches) - 1}")
    params = {
        "command_jump_threshold": {"value": best["threshold"], "unit": "1", "kind": "derived",
                                   "source": how},
        "command_jump_fall_probability": {"value": best["probability"], "unit": "1",
                                          "kind": "derived", "source": how},
    }
    record = {"league": target, "grid": points, "seconds": seconds, "seed0": seed0,
              "matches": [list(m) for m in matches], "source": source}
    return params, record


