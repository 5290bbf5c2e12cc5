"""``teamenv selfplay``: run (or resume) a self-play league, print its ratings, plot its curve.

    teamenv selfplay run runs/league --generations 8 --steps 20000
    teamenv selfplay run runs/league --resume            # after a kill: same pool, same ratings
    teamenv selfplay ratings runs/league
    teamenv selfplay curve runs/league --out curve.png
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

from teamenv.errors import ConfigError

#: Options of ``run`` that are part of the league's configuration: (flag, dest, type, help).
#: They default to None, so a resumed run can tell which ones were given.
_CONFIG_OPTIONS = (
    ("--seed", "seed", int, "the run's seed (default 0)"),
    ("--steps", "steps_per_generation", int,
     "agent-decisions trained per generation (default 20000)"),
    ("--builtins", "builtins", str,
     "built-in opponents, comma-separated team specs (default chaser,static,full)"),
    ("--pfsp", "pfsp", str, "opponent weighting: hard | variance | linear | uniform "
     "(default hard: (1 - p_win) ** exponent)"),
    ("--pfsp-exponent", "pfsp_exponent", float, "exponent of the hard weighting (default 2)"),
    ("--latest-share", "latest_share", float,
     "share of training episodes against the latest snapshot (default 0)"),
    ("--field", "field", str, "field preset (default simspark)"),
    ("--team-size", "team_size", int, "players per side (default 3)"),
    ("--episode-seconds", "episode_s", float,
     "game seconds per training episode (default 60)"),
    ("--observation", "observation", str,
     "egocentric (nearest-player slots, default) | box (the env's row)"),
    ("--teammate-slots", "teammate_slots", int, "egocentric teammate slots (default 2)"),
    ("--opponent-slots", "opponent_slots", int, "egocentric opponent slots (default 3)"),
    ("--action-repeat", "action_repeat", int, "cycles per decision (default 5)"),
    ("--walk-to-ball", "walk_to_ball", str,
     "true: walking is a reflex (at the ball), the network only kicks (default false)"),
    ("--ball-race", "ball_race", str,
     "true: egocentric rows end with the ball-race columns (distance to the ball, and how "
     "much farther the nearest teammate and opponent are; default false)"),
    ("--game-state", "game_state", str,
     "false: egocentric rows leave out the clock, half and score (default true)"),
    ("--option-team", "option_team", str,
     "a team that plays options the network scores, e.g. full_options (its open-play "
     "options: play the ball, cover, hold); default none: the network's outputs are actions"),
    ("--shaping", "shaping", str, "potential-based shaping, NAME=WEIGHT,... over ball_to_goal "
     "and team_to_ball, or none (default ball_to_goal=1,team_to_ball=0.5)"),
    ("--gamma", "gamma", float, "discount per decision (default 0.99)"),
    ("--rating-games", "games_per_pairing", int,
     "rating rounds per pairing, each from both sides (default 1)"),
    ("--rating-half-time", "half_time_s", float, "rating match half length, s (default 60)"),
    ("--rating-halves", "halves", int, "halves per rating match (default 2)"),
    ("--rating-recent", "recent", int,
     "earlier snapshots each new one is rated against (default 3)"),
    ("--bootstrap", "n_bootstrap", int, "bootstrap resamples of the intervals (default 200)"),
    ("--learner", "learner", str, "ppo (Stable-Baselines3, default) | imitation (PPO "
     "warm-started by cloning a teacher: --learner-option teacher=chaser) | module:Class"),
)
_TRAINING_KEYS = ("field", "team_size", "episode_s", "observation", "teammate_slots",
                  "opponent_slots", "gamma")
_ACTION_KEYS = ("action_repeat", "walk_to_ball")
_RATING_KEYS = ("games_per_pairing", "half_time_s", "halves", "recent", "n_bootstrap")


def add_parser(sub: argparse._SubParsersAction) -> None:
    """Register ``selfplay {run,ratings,curve}`` on the ``teamenv`` parser."""
    top = sub.add_parser("selfplay", help="self-play league: PFSP opponents, snapshots rated "
                         "by the tournament runner, resumable",
                         description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    _one_line_errors(top)
    commands = top.add_subparsers(dest="selfplay_command", required=True)

    run = commands.add_parser("run", help="run or resume a league in a run directory")
    _one_line_errors(run)
    run.add_argument("run_dir", type=Path, help="the run directory (created if new)")
    run.add_argument("--generations", type=_count, default=10,
                     help="train until this many generations are rated after the untrained "
                          "snapshot 0 (default 10; a resumed run may be extended)")
    run.add_argument("--resume", action="store_true",
                     help="continue the league stored in the run directory (its configuration; "
                          "options given must agree with it)")
    for flag, dest, kind, text in _CONFIG_OPTIONS:
        run.add_argument(flag, dest=dest, type=_typed(flag, kind), default=None, help=text)
    run.add_argument("--learner-option", action="append", default=[], metavar="KEY=VALUE",
                     help="a learner option, e.g. copies=4 or n_steps=512 (repeatable)")
    run.add_argument("--backend", default="process",
                     help="where rating matches run: process (worker pool, default) | serial")
    run.add_argument("-j", "--jobs", type=_count, default=None,
                     help="rating worker processes (default: all cores)")
    run.set_defaults(func=_run)

    ratings = commands.add_parser("ratings", help="the ratings and opponents of a run")
    _one_line_errors(ratings)
    ratings.add_argument("run_dir", type=Path, help="the run directory of a league")
    ratings.add_argument("--generation", type=_count, default=None,
                         help="after this generation (default: the last rated)")
    ratings.add_argument("--json", type=Path, default=None,
                         help="also write every generation's record and ratings as JSON")
    ratings.set_defaults(func=_ratings)

    curve = commands.add_parser("curve", help="plot the rating curve of a run (PNG)")
    _one_line_errors(curve)
    curve.add_argument("run_dir", type=Path, help="the run directory of a league")
    curve.add_argument("--out", type=Path, required=True, help="the PNG to write")
    curve.set_defaults(func=_curve)


def _one_line_errors(parser: argparse.ArgumentParser) -> None:
    """A usage error prints one line (``teamenv selfplay run: error: ...``), exit status 2."""
    def error(message: str):
        print(f"{parser.prog}: error: {message} (see --help)", file=sys.stderr)
        raise SystemExit(2)
    parser.error = error  # type: ignore[method-assign]


def _count(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number >= 0, got {text!r}") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"expected a whole number >= 0, got {text!r}")
    return value


def _typed(flag: str, kind: type):
    def parse(text: str):
        try:
            return kind(text)
        except ValueError:
            raise argparse.ArgumentTypeError(
                f"expected {'a whole number' if kind is int else 'a number'}, got "
                f"{text!r}") from None
    parse.__name__ = kind.__name__
    return parse if kind in (int, float) else str


def build_config(args: argparse.Namespace, base: dict[str, Any] | None = None):
    """The ``LeagueConfig`` of the given options over ``base`` (a stored configuration's
    JSON; the defaults when None)."""
    from teamenv.selfplay.config import LeagueConfig
    from teamenv.tournament.spec import parse_value

    data = LeagueConfig().to_json() if base is None else json.loads(json.dumps(base))
    given = {dest: getattr(args, dest) for _, dest, _, _ in _CONFIG_OPTIONS
             if getattr(args, dest) is not None}
    for key, value in given.items():
        if key in _TRAINING_KEYS:
            data["training"][key] = value
        elif key == "shaping":
            data["training"]["shaping"] = _weights(value, "--shaping")
        elif key == "option_team":
            data["training"]["option_team"] = value
        elif key in ("ball_race", "game_state"):
            if value.lower() not in ("true", "false"):
                raise ConfigError(f"--{key.replace('_', '-')}: true or false, got {value!r}")
            data["training"][key] = value.lower() == "true"
        elif key in _ACTION_KEYS:
            if key == "walk_to_ball":
                if value.lower() not in ("true", "false"):
                    raise ConfigError(f"--walk-to-ball: true or false, got {value!r}")
                value = value.lower() == "true"
            data["training"]["actions"][key] = value
        elif key in _RATING_KEYS:
            data["rating"][key] = value
        elif key == "builtins":
            data["builtins"] = [b.strip() for b in value.split(",") if b.strip()]
        else:
            data[key] = value
    options = dict(data.get("learner_options", {}))
    for item in args.learner_option:
        key, sep, raw = item.partition("=")
        if not sep or not key.strip():
            raise ConfigError(f"--learner-option: expected KEY=VALUE, got {item!r}")
        options[key.strip()] = parse_value(raw.strip())
    data["learner_options"] = options
    if "option_team" in given:
        data["training"]["actions"] = _option_actions(data["training"])
    return LeagueConfig.from_json(data), bool(given or args.learner_option)


def _option_actions(training: dict[str, Any]) -> dict[str, Any]:
    """The action setup (JSON) of a network that scores the options of the training's
    ``option_team`` (none: the default action setup, keeping its action repeat)."""
    from dataclasses import asdict

    from teamenv.errors import TeamLoadError
    from teamenv.selfplay.training_setup import ActionSetup, option_actions
    from teamenv.teams import resolve_team_class
    from teamenv.tournament.errors import TournamentError
    from teamenv.tournament.spec import parse_team_spec

    repeat = training.get("actions", {}).get("action_repeat", 5)
    if not training["option_team"]:
        actions = ActionSetup(action_repeat=repeat)
    else:
        try:
            cls = resolve_team_class(parse_team_spec(training["option_team"]).name)
        except (TeamLoadError, TournamentError) as exc:
            raise ConfigError(f"--option-team: {exc}") from None
        names = getattr(cls, "option_names", None)
        if names is None:
            raise ConfigError(f"--option-team {training['option_team']!r}: the team plays no "
                              f"options (no option_names); full_options does")
        actions = option_actions(len(names), repeat)
    out = asdict(actions)
    for key in ("learned", "scale", "fixed"):
        out[key] = list(out[key])
    return out


def _weights(text: str, flag: str) -> dict[str, float]:
    """``NAME=WEIGHT,...`` (or ``none``) as a dict."""
    if text.strip().lower() == "none":
        return {}
    out = {}
    for item in text.split(","):
        name, sep, raw = item.partition("=")
        try:
            out[name.strip()] = float(raw) if sep else 1.0
        except ValueError:
            raise ConfigError(f"{flag}: expected NAME=WEIGHT,..., got {item!r}") from None
    return out


def _run(args: argparse.Namespace) -> int:
    from teamenv.selfplay.league import run_league
    from teamenv.selfplay.league_store import LEAGUE_DB, LeagueStore

    if args.backend not in ("process", "serial"):
        raise ConfigError(f"--backend: process or serial, got {args.backend!r}")
    config = None
    if args.resume:
        db = args.run_dir / LEAGUE_DB
        stored = None
        if db.is_file():
            with LeagueStore(db) as store:
                stored = store.config()
        if stored is not None:
            config, given = build_config(args, stored)
            if not given:
                config = None  # the stored one, as it is
    else:
        config, _ = build_config(args)
    summary = run_league(args.run_dir, args.generations, config, resume=args.resume,
                         backend=args.backend, jobs=args.jobs, log=_print)
    print(summary.describe())
    return 0


def _print(text: str) -> None:
    print(text, flush=True)


def _open_store(run_dir: Path):
    from teamenv.selfplay.league_store import LEAGUE_DB, LeagueStore

    if not (run_dir / LEAGUE_DB).is_file():
        raise ConfigError(f"selfplay: {str(run_dir)!r} holds no league ({LEAGUE_DB} missing)")
    return LeagueStore(run_dir / LEAGUE_DB)


def _ratings(args: argparse.Namespace) -> int:
    with _open_store(args.run_dir) as store:
        last = store.last_rated()
        generation = last if args.generation is None else args.generation
        if generation < 0 or generation > last:
            raise ConfigError(f"selfplay: generation {generation} is not rated (rated: 0.."
                              f"{last})" if last >= 0 else "selfplay: no generation rated yet")
        ratings = store.ratings(generation)
        records = store.generations()
        print(f"ratings after generation {generation} ({ratings.n_games} matches, "
              f"{ratings.confidence:.0%} bootstrap intervals, Elo scale):")
        print(f"  {'team':10s} {'Bradley-Terry':>28s} {'Elo':>28s}")
        for team, r in ratings.bradley_terry.items():
            e = ratings.elo[team]
            print(f"  {team:10s} {r.rating:8.1f} [{r.low:7.1f}, {r.high:7.1f}]   "
                  f"{e.rating:8.1f} [{e.low:7.1f}, {e.high:7.1f}]")
        for record in records[1:generation + 1]:
            mix = ", ".join(f"{o['team']} {o['probability']:.2f}" for o in record.opponents)
            print(f"  generation {record.generation} trained against: {mix}")
        if args.json is not None:
            out = {"generations": [
                {**r.comparable(), "train_wall_s": r.train_wall_s, "rate_wall_s": r.rate_wall_s,
                 "ratings": None if store.ratings(r.generation) is None
                 else store.ratings(r.generation).to_json()} for r in records]}
            args.json.parent.mkdir(parents=True, exist_ok=True)
            args.json.write_text(json.dumps(out, indent=1) + "\n")
            print(f"wrote {args.json}")
    return 0


def _curve(args: argparse.Namespace) -> int:
    from teamenv.selfplay.curve import plot_rating_curve

    with _open_store(args.run_dir) as store:
        print(f"wrote {plot_rating_curve(store, args.out)}")
    return 0
