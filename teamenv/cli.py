"""The teamenv command line: matches, replays, statistics, the viewer, tournaments, league
matches and parameter search."""

from __future__ import annotations

import argparse
import json
import os
import signal
import sys
import threading
from collections.abc import Sequence
from pathlib import Path

from teamenv import __version__
from teamenv.errors import TeamEnvError, Terminated
from teamenv.match import MatchOptions
from teamenv.tournament.cli import add_report_command
from teamenv.viewer.cli import add_parser as add_view_parser


def _add_match(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("match", help="play one match between two teams and print the result")
    p.add_argument("left", help="left team: a registered name (see `teamenv teams`) or module:Class")
    p.add_argument("right", help="right team")
    p.add_argument("--seed", type=int, default=0,
                   help="match seed: the same seed plays the same match (default 0)")
    MatchOptions.add_arguments(p)
    p.add_argument("--left-config", default="{}", help="JSON dict of the left team's config")
    p.add_argument("--right-config", default="{}", help="JSON dict of the right team's config")
    p.add_argument("--replay", type=Path, help="save a replay (.npz) here")
    p.add_argument("--replay-extras", action="store_true",
                   help="record each agent's belief and roles in the replay too")
    p.add_argument("--gif", type=Path, help="render the match to a GIF/MP4 (needs [render])")
    p.add_argument("--gif-every", type=int, default=10, help="render every k-th cycle")
    p.add_argument("--json", action="store_true", help="print the result as JSON")
    p.set_defaults(func=_run_match)


def _run_match(args: argparse.Namespace) -> int:
    from teamenv.match import play_match

    options = MatchOptions.from_arguments(args)
    replay_path = args.replay
    if args.gif and replay_path is None:
        replay_path = args.gif.with_suffix(".npz")
    result = play_match(args.left, args.right, args.seed, options,
                        left_config=_json_dict(args.left_config, "--left-config"),
                        right_config=_json_dict(args.right_config, "--right-config"),
                        replay_path=replay_path, replay_extras=args.replay_extras)
    if args.json:
        print(json.dumps(result.to_dict(), default=str, indent=2))
    else:
        print(result.summary())
    if replay_path:
        print(f"replay: {replay_path}")
    if args.gif:
        from teamenv.render import render_replay_gif

        print(f"video: {render_replay_gif(replay_path, args.gif, every=args.gif_every)}")
    return 0


def _add_render(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("render", help="render a replay file to a GIF/MP4 (needs [render])")
    p.add_argument("replay", type=Path, help="a replay (.npz) written by `teamenv match --replay`")
    p.add_argument("out", type=Path, help="the GIF (.gif) or video (.mp4, needs imageio's "
                   "ffmpeg plugin) to write")
    p.add_argument("--every", type=int, default=10,
                   help="draw every k-th cycle (default 10: 5 frames per game second)")
    p.add_argument("--fps", type=int, default=10,
                   help="frames per second of the output (default 10; a GIF stores each "
                   "frame's delay in whole centiseconds)")
    p.set_defaults(func=lambda a: print(
        __import__("teamenv.render", fromlist=["x"]).render_replay_gif(
            a.replay, a.out, fps=a.fps, every=a.every)) or 0)


def _add_teams(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("teams", help="list the registered teams (entry points teamenv.teams)")
    p.set_defaults(func=_list_teams)


def _list_teams(args: argparse.Namespace) -> int:
    from teamenv.teams import registered_teams

    for name, target in sorted(registered_teams().items()):
        print(f"{name:20s} {target}")
    return 0


def _json_dict(text: str, flag: str) -> dict:
    try:
        value = json.loads(text)
    except json.JSONDecodeError as exc:
        raise TeamEnvError(f"{flag}: not valid JSON ({exc}): {text!r}") from exc
    if not isinstance(value, dict):
        raise TeamEnvError(f"{flag}: expected a JSON object, got {text!r}")
    return value


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="teamenv", description=__doc__,
                                     usage="teamenv [-h] [--version] COMMAND ...",
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--version", action="version", version=f"teamenv {__version__}",
                        help="print the version of teamenv and exit")
    # the commands are listed in the description (one line each); not twice
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND", prog="teamenv",
                                help=argparse.SUPPRESS)
    _add_match(sub)
    _add_render(sub)
    _add_teams(sub)
    __import__("teamenv.analytics.cli", fromlist=["add_parser"]).add_parser(sub)  # stats
    add_report_command(sub)  # report: a replay's page or a tournament database's
    add_view_parser(sub)
    __import__("teamenv.league.cli", fromlist=["add_parser"]).add_parser(sub)  # league-match
    try:
        from teamenv.tournament.cli import add_tournament_commands
    except ImportError:
        pass
    else:
        add_tournament_commands(sub)
    from teamenv.optimize.cli import add_parser as add_optimize_command

    add_optimize_command(sub)
    __import__("teamenv.selfplay.cli", fromlist=["add_parser"]).add_parser(sub)  # selfplay
    parser.description = _describe_commands(sub)
    return parser


def _describe_commands(sub: argparse._SubParsersAction) -> str:
    """The module docstring and one line per command (from the commands' own help)."""
    helps = {action.dest: action.help for action in sub._choices_actions}
    width = max(len(name) for name in sub.choices)
    lines = [f"  {name:{width}s}  {helps.get(name) or ''}".rstrip() for name in sub.choices]
    return (__doc__.strip() + "\n\ncommands (`teamenv COMMAND --help` for each one's "
            "arguments):\n" + "\n".join(lines))


def _terminate(signum: int, frame: object) -> None:
    raise Terminated()


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    previous = None
    if threading.current_thread() is threading.main_thread():
        previous = signal.signal(signal.SIGTERM, _terminate)
    try:
        status = int(args.func(args) or 0)
        sys.stdout.flush()   # a closed pipe shows here, not at interpreter exit
        return status
    except TeamEnvError as exc:
        print(f"teamenv: error: {exc}", file=sys.stderr)
        return 2
    except Terminated:
        return 128 + signal.SIGTERM
    except BrokenPipeError:
        # the reader went away (`teamenv tournament matches | head`): stop quietly, and keep
        # Python from complaining again when it flushes stdout at exit
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 128 + signal.SIGPIPE
    finally:
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)

