"""``teamenv league-match A B``: one match on the league's real server (rcssservermj);
``teamenv league-tournament A B C ...``: a round robin there, stored as one tournament."""

from __future__ import annotations

import argparse
from collections.abc import Iterator
from contextlib import contextmanager

from teamenv.errors import MissingExtraError

#: The humanoid extra's top-level modules: a league command missing one of them is a missing
#: extra (one line naming it), not a traceback.
HUMANOID_MODULES = ("rcsssmj", "mujoco", "jax", "brax")

SERVER_HELP = ("real: rcssservermj as a child process over TCP (default); local: the same "
               "simulation, referee and protocol code of rcsssmj in this process, no sockets "
               "(faster joins, seeded: the same seed replays the match)")


def add_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("league-match", help="play a match on the league server (rcsssmj, "
                       "needs the humanoid extra) and record it in a tournament database")
    p.add_argument("left", help="left side: a team spec, as in the tournament CLI (a registered "
                   "team such as chaser, name:key=value,... config, or pkg.mod:Class); it plays "
                   "in vision mode (mj profile, mj channel)")
    p.add_argument("right", help="right side (a team spec)")
    p.add_argument("--team-size", type=int, default=7, help="players per side, 1-7 (default 7)")
    p.add_argument("--seconds", type=float, default=30.0, help="game time to play (s)")
    p.add_argument("--seed", type=int, default=0, help="seed stored with the match")
    p.add_argument("--kick-off", default="Left", choices=("Left", "Right"),
                   help="the side that kicks off (default Left)")
    p.add_argument("--db", default=None, help="SQLite results database to record the match in")
    p.add_argument("--name", default="league", help="tournament name in --db (default league): "
                   "the match is the one match of this new tournament (a name already holding "
                   "one is an error)")
    p.add_argument("--log-dir", default=None, help="where the server's log goes (default: tmp)")
    p.add_argument("--server", default="real", choices=("real", "local"), help=SERVER_HELP)
    p.add_argument("--walker", default=None,
                   help="the robots' walk controller: network (the league's reference walking "
                        "network, about 1.2 m/s; the default) or lipm (our LIPM walker, "
                        "about 0.55 m/s)")
    p.add_argument("--ramp", action="store_true",
                   help="walk requests change no faster than the t1_league body's "
                        "accelerations (default: as the team asks them, each cycle)")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.set_defaults(func=_run)

    t = sub.add_parser("league-tournament", help="a round robin of team specs on the league "
                       "server (one match at a time, each stored as it ends; --resume)")
    t.add_argument("teams", nargs="*", help="team specs (at least two; none with --resume)")
    t.add_argument("--db", required=True, help="SQLite results database")
    t.add_argument("--name", required=True, help="tournament name in --db")
    t.add_argument("--games", type=int, default=1,
                   help="seeded rounds per pairing, each played once with either team left")
    t.add_argument("--team-size", type=int, default=7, help="players per side, 1-7 (default 7)")
    t.add_argument("--seconds", type=float, default=30.0, help="game time per match (s)")
    t.add_argument("--seed", type=int, default=0, help="the tournament's base seed")
    t.add_argument("--resume", action="store_true", help="play what is missing of --name")
    t.add_argument("--log-dir", default=None, help="where the servers' logs go (default: tmp)")
    t.add_argument("--server", default="real", choices=("real", "local"), help=SERVER_HELP)
    t.add_argument("-j", "--jobs", type=int, default=1,
                   help="matches at once, each in its own process and server (default 1)")
    t.add_argument("--replay-dir", default=None,
                   help="record every match here and store its statistics (--server local)")
    t.add_argument("--ray-address", default=None,
                   help="play the matches as Ray tasks: local (a local Ray instance with --jobs "
                        "CPUs), auto or ray://host:10001 (a cluster with the humanoid extra)")
    t.set_defaults(func=_run_tournament)


def _missing_module(exc: BaseException) -> str | None:
    """The name of the module whose import failed in ``exc`` or the errors it came from."""
    seen: set[int] = set()
    while exc is not None and id(exc) not in seen:
        seen.add(id(exc))
        if isinstance(exc, ImportError) and exc.name:
            return exc.name
        exc = exc.__cause__ or exc.__context__
    return None


@contextmanager
def _humanoid_extra(feature: str) -> Iterator[None]:
    """Turn an ImportError of one of ``HUMANOID_MODULES`` into a MissingExtraError."""
    try:
        yield
    except ImportError as exc:
        missing = _missing_module(exc)
        if missing is None or missing.split(".")[0] not in HUMANOID_MODULES:
            raise
        raise MissingExtraError("humanoid", missing.split(".")[0], feature) from exc


def _run(args: argparse.Namespace) -> int:
    with _humanoid_extra(f"league-match --server {args.server}"):
        return _play(args)


def _play(args: argparse.Namespace) -> int:
    from tqdm import tqdm

    from .match import (
        LeagueMatchOptions,
        check_league_record,
        play_league_match,
        record_league_match,
    )

    walker = {} if args.walker is None else {"walker": args.walker}
    options = LeagueMatchOptions(team_size=args.team_size, game_s=args.seconds,
                                 kick_off=args.kick_off, server=args.server,
                                 ramp=args.ramp, **walker)
    if args.db:
        check_league_record(args.db, args.name, args.left, args.right)  # before playing
    bar = tqdm(total=round(args.seconds, 2), unit="s game", disable=args.no_progress,
               bar_format="{l_bar}{bar}| {n:.2f}/{total:.2f} s game [{elapsed}<{remaining}]")

    def progress(t: float, score: tuple[int, int]) -> None:
        bar.update(max(0.0, min(t, bar.total) - bar.n))
        bar.set_postfix_str(f"{args.left} {score[0]}-{score[1]} {args.right}", refresh=False)

    try:
        result = play_league_match(args.left, args.right, options, seed=args.seed,
                                   on_cycle=progress, log_dir=args.log_dir)
    finally:
        bar.close()
    print(result.summary())
    if args.db:
        record_league_match(args.db, args.name, result, options)
        print(f"recorded in {args.db} (tournament {args.name!r})")
    return 0


def _run_tournament(args: argparse.Namespace) -> int:
    with _humanoid_extra(f"league-tournament --server {args.server}"):
        return _play_tournament(args)


def _play_tournament(args: argparse.Namespace) -> int:
    from .match import LeagueMatchOptions
    from .tournament import run_league_tournament

    teams = args.teams or None
    options = None if args.resume and not teams else LeagueMatchOptions(
        team_size=args.team_size, game_s=args.seconds, server=args.server)

    def report(done: int, total: int, result) -> None:
        print(f"[{done}/{total}] {result.summary().splitlines()[0]}", flush=True)

    summary = run_league_tournament(args.name, args.db, teams, options, games=args.games,
                                    seed=args.seed, resume=args.resume, log_dir=args.log_dir,
                                    on_match=report, server=args.server, workers=args.jobs,
                                    replay_dir=args.replay_dir, ray_address=args.ray_address)
    print(f"{args.name}: {summary.played} played, {summary.skipped} already stored, "
          f"{summary.scheduled} scheduled ({summary.wall_s:.0f} s wall)")
    return 0
