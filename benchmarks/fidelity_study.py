"""The ranking-fidelity study in one resumable command: does a ranking made in teamenv hold on
the league's humanoid server?

    python benchmarks/fidelity_study.py --out study                 # the whole study
    python benchmarks/fidelity_study.py --out study                 # again: resumes, loses nothing
    python benchmarks/fidelity_study.py --out study --ray-address auto   # league matches on Ray
    python benchmarks/fidelity_study.py --out study --analyse-only  # tables, JSON, figure, page

Three round robins of the same strategies, in the league's format (7 v 7, ``mj7v7``, the
``mj`` camera and channel, every pairing with both sides, tournament seeds from the evaluation
range of ``teamenv.seeds``), each stored as it is played in its own SQLite file under
``--out`` (a killed run resumes where it stopped, with ``run_tournament``'s resume):

- ``teamenv``: the env with the ``t1_mj`` profile (the league's reference walking network);
- ``teamenv calibrated``: the env with the ``t1_league`` profile (what our league client's
  robot does, measured on the server);
- ``league``: the same matches on ``LocalServer`` (rcsssmj's own simulation in this process,
  seeded; ``--ray-address`` plays them as Ray tasks), recorded as replays so both worlds get
  the same statistics (``teamenv.analytics.stats``).

A teamenv world's database is tied to the profile file it was played with: ``--out``'s
``profiles.json`` keeps each world's profile name and the SHA-256 of its file, and a resume
under a changed profile (e.g. ``t1_league`` recalibrated) stops with an error instead of
mixing matches of two bodies in one table.

A league match is one stretch of ``--seconds`` of play (the server's half is 300 s); the env
plays the same stretch as one half. The analysis is ``benchmarks/fidelity_ranking.py``'s
(Spearman rho and Kendall tau between the worlds' rankings, by points, goal difference, xG
and ball progress, with percentile bootstrap intervals over matches; per-match statistics of
each world). It writes the results JSON, a figure (each strategy's rank in teamenv against
its rank on the server) and a docs page.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import math
import signal
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

#: strategies of graded strength: the full team, it tuned by ``teamenv optimize`` (docs/optimize.md's
#: opt1 run, its exported config inline), without voting, without talking, with the
#: defensive formation in attack, the ball chaser and the static team
STRATEGIES = (
    "full",
    "full:ball_pull=0.2974,dribble_speed=1.148,kick_goal_weight=43.55,"
    "kick_possession_weight=5.184,kick_progress_weight=0.07352,pressure_m=3.8",
    "full:vote=false",
    "silent",
    "full:formation_attack=defend",
    "chaser",
    "static",
)
#: the per-match statistics the worlds should agree on within 25 %
COMPARED = ("goals", "kicks", "ball_progress_m", "attacking_third_pct", "falls")
WORLDS = {"teamenv": "t1_mj", "teamenv calibrated": "t1_league"}
WORLD_NAMES = tuple(w.replace(" ", "_") for w in WORLDS) + ("league",)
ROOT = Path(__file__).resolve().parents[1]


def _ranking_module():
    path = Path(__file__).resolve().with_name("fidelity_ranking.py")
    spec = importlib.util.spec_from_file_location("fidelity_ranking", path)
    module = importlib.util.module_from_spec(spec)
    sys.modules.setdefault("fidelity_ranking", module)   # its dataclasses look it up there
    spec.loader.exec_module(module)
    return module


def env_options(seconds: float, team_size: int, profile: str):
    from teamenv.match import MatchOptions

    # the league's rules, its double-touch rule included (every league server applies it)
    return MatchOptions(field="mj7v7", team_size=team_size, half_time_s=seconds, halves=1,
                        observation_mode="vision", vision="mj", channel="mj",
                        locomotion_profile=profile, double_touch=True)


PROFILES_FILE = "profiles.json"


def profile_digest(profile: str) -> str:
    """SHA-256 of the profile file a world plays with (``locomotion.PROFILES`` by name)."""
    import hashlib

    from locomotion import load_profile

    return hashlib.sha256(Path(load_profile(profile).path).read_bytes()).hexdigest()


def check_profile(out: Path, world: str, profile: str) -> None:
    """Record the profile ``world`` is played with in ``out/profiles.json``, or stop when its
    stored matches were played with another version of that profile."""
    path = out / PROFILES_FILE
    recorded = json.loads(path.read_text()) if path.is_file() else {}
    digest = profile_digest(profile)
    before = recorded.get(world)
    if before is not None and (before["profile"], before["sha256"]) != (profile, digest):
        raise SystemExit(
            f"{world}: the matches stored in {out / (world + '.sqlite')} were played with "
            f"profile {before['profile']} (sha256 {before['sha256'][:12]}), this run would "
            f"play with {profile} (sha256 {digest[:12]}): move that database away to play the "
            f"world again with the current profile, or check out the profile it was played "
            f"with")
    if before is None and (out / f"{world}.sqlite").is_file():
        raise SystemExit(
            f"{world}: {out / (world + '.sqlite')} has no profile record in "
            f"{path}: add one ({{\"{world}\": {{\"profile\": \"{profile}\", "
            f"\"sha256\": ...}}}}, the file it was played with) or move it away")
    recorded[world] = {"profile": profile, "sha256": digest}
    path.write_text(json.dumps(recorded, indent=2, sort_keys=True) + "\n")


def play(args: argparse.Namespace) -> None:
    """Play (or finish) the three round robins."""
    from teamenv.league.match import LeagueMatchOptions
    from teamenv.league.tournament import run_league_tournament
    from teamenv.tournament import round_robin, run_tournament

    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    teams = list(args.teams)
    for world, profile in WORLDS.items():
        name = world.replace(" ", "_")
        if name not in args.worlds:
            continue
        check_profile(out, name, profile)
        t = round_robin(name, teams, games_per_pairing=args.games, swap_sides=True,
                        seed=args.seed, options=env_options(args.seconds, args.team_size,
                                                            profile))
        print(f"== {world} ({profile}): {len(t.schedule())} matches", flush=True)
        run_tournament(t, out / f"{name}.sqlite", name=name, resume=True, jobs=args.jobs,
                       progress=not args.no_progress)
    if "league" not in args.worlds:
        return
    options = LeagueMatchOptions(team_size=args.team_size, game_s=args.seconds, server="local")
    print("== league (LocalServer)", flush=True)
    run_league_tournament("league", out / "league.sqlite", teams, options, games=args.games,
                          seed=args.seed, resume=True, server="local", workers=args.jobs,
                          replay_dir=out / "league_replays", ray_address=args.ray_address,
                          progress=not args.no_progress)


def analyse(out: Path, bootstrap: int, seed: int, figure: Path | None,
            page: Path | None, note: str = "", worlds: Sequence[str] = WORLD_NAMES,
            common_pairings: bool = False) -> dict[str, Any]:
    """The analysis of a stored run: results JSON (``out/results.json``), figure, page.
    ``worlds``: the teamenv worlds to compare with the league (those stored);
    ``common_pairings``: only the pairings every world has played (a run under way)."""
    fr = _ranking_module()
    results_path = out / "results.json"
    argv = ["--league-db", str(out / "league.sqlite"), "--league-name", "league",
            "--bootstrap", str(bootstrap), "--seed", str(seed), "--json", str(results_path)]
    for name, flag in (("teamenv", "--teamenv"), ("teamenv_calibrated", "--calibrated")):
        if name in worlds and (out / f"{name}.sqlite").is_file():
            argv += [f"{flag}-db", str(out / f"{name}.sqlite"), f"{flag}-name", name]
    if common_pairings:
        argv.append("--common-pairings")
    fr.main(argv)
    results = json.loads(results_path.read_text())
    if (out / PROFILES_FILE).is_file():   # which body each teamenv world was played with
        results["profiles"] = json.loads((out / PROFILES_FILE).read_text())
    results["ranks"] = ranks(results["ranking"])
    results["stat_ratios"] = stat_ratios(results["stats"])
    results_path.write_text(json.dumps(results, indent=2))
    if figure is not None:
        draw(results, figure)
    if page is not None:
        page.write_text(render_page(results, figure, page, note))
    return results


def ranks(ranking: dict[str, dict[str, dict[str, float]]]) -> dict[str, dict[str, dict]]:
    """world -> metric -> team -> rank (1 = best; tied teams share their mean rank)."""
    from scipy.stats import rankdata

    out: dict[str, dict[str, dict]] = {}
    for world, metrics in ranking.items():
        for metric, table in metrics.items():
            teams = sorted(table)
            r = rankdata([-table[t] for t in teams], method="average")
            out.setdefault(world, {})[metric] = {t: float(k) for t, k in zip(teams, r,
                                                                             strict=True)}
    return out


def stat_ratios(stats: dict[str, dict[str, float]]) -> dict[str, dict[str, Any]]:
    """world -> statistic -> {value, league, ratio, within_25pct} for ``COMPARED``."""
    league = stats.get("league", {})
    out: dict[str, dict[str, Any]] = {}
    for world, values in stats.items():
        if world == "league":
            continue
        for key in COMPARED:
            a, b = values.get(key), league.get(key)
            if a is None or b is None:
                continue
            ratio = a / b if b else (math.inf if a else 1.0)
            out.setdefault(world, {})[key] = {"value": a, "league": b, "ratio": ratio,
                                              "within_25pct": 0.75 <= ratio <= 1.25}
    return out


def headline_metric(results: dict[str, Any]) -> str:
    """Points when the league's points table separates the teams, else the finest metric
    that does (goal difference, then ball progress)."""
    league = results["ranking"].get("league", {})
    for metric in ("points", "goal_diff", "progress_diff", "xg_diff"):
        table = league.get(metric)
        if table and len(set(table.values())) > 1:
            return metric
    return "points"


def draw(results: dict[str, Any], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    metric = headline_metric(results)
    worlds = [w for w in WORLDS if w in results["ranks"] and metric in results["ranks"][w]]
    league = results["ranks"].get("league", {}).get(metric, {})
    fig, axes = plt.subplots(1, max(len(worlds), 1), figsize=(5.2 * max(len(worlds), 1), 5),
                             squeeze=False)
    n = max(len(league), 1)
    for ax, world in zip(axes[0], worlds, strict=False):
        mine = results["ranks"][world][metric]
        teams = sorted(set(mine) & set(league))
        ax.plot([0.5, n + 0.5], [0.5, n + 0.5], color="0.8", lw=1, zorder=0)
        ax.scatter([league[t] for t in teams], [mine[t] for t in teams], s=40)
        # teams that share a place in both rankings are labelled one under the other
        placed: dict[tuple[float, float], int] = {}
        for t in teams:
            spot = (league[t], mine[t])
            row = placed[spot] = placed.get(spot, -1) + 1
            ax.annotate(_short(t), spot, textcoords="offset points",
                        xytext=(5, 4 - 11 * row), fontsize=8)
        agreement = results["agreement"].get(f"{world} vs league, {metric}", {})
        rho, ci = agreement.get("rho", math.nan), agreement.get("rho_ci", [math.nan] * 2)
        ax.set_title(f"{world} vs league, by {metric}\nSpearman rho {rho:+.2f} "
                     f"[{ci[0]:+.2f}, {ci[1]:+.2f}]", fontsize=10)
        ax.set_xlabel("rank on the league server (1 = best)")
        ax.set_ylabel(f"rank in {world}")
        ax.set_xlim(n + 0.5, 0.5)
        ax.set_ylim(n + 0.5, 0.5)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _short(spec: str, limit: int = 28) -> str:
    return spec if len(spec) <= limit else spec[:limit - 3] + "..."


def render_page(results: dict[str, Any], figure: Path | None, page: Path,
                note: str = "") -> str:
    """The docs page of a run: agreement table, rankings, per-match statistics."""
    metric = headline_metric(results)
    lines = ["# The fidelity study", "",
             "Generated by `python benchmarks/fidelity_study.py` from the stored run "
             "(see [league matches](league.md#the-fidelity-study) for the protocol); "
             f"league matches: {results['league_matches']}. Headline ranking: **{metric}** "
             "(points when the league's table separates the teams, else the finest ranking "
             "that does).", ""]
    if note:
        lines += [note, ""]
    if figure is not None:
        rel = Path(figure).resolve().relative_to(Path(page).resolve().parent) \
            if Path(figure).resolve().is_relative_to(Path(page).resolve().parent) else figure
        lines += [f"![each strategy's rank in teamenv against its rank on the server]({rel})",
                  ""]
    lines += ["| worlds, ranked by | teams | Spearman rho [95 % CI] | Kendall tau [95 % CI] |",
              "|---|---|---|---|"]
    for key, a in results["agreement"].items():
        lines.append(f"| {key} | {a['teams']} | {_fmt(a['rho'])} [{_fmt(a['rho_ci'][0])}, "
                     f"{_fmt(a['rho_ci'][1])}] | {_fmt(a['tau'])} [{_fmt(a['tau_ci'][0])}, "
                     f"{_fmt(a['tau_ci'][1])}] |")
    lines += ["", f"Ranks by {metric} (1 = best):", "",
              "| strategy | " + " | ".join(results["ranks"]) + " |",
              "|---|" + "---|" * len(results["ranks"])]
    teams = sorted(results["ranks"].get("league", {}).get(metric, {}))
    for t in teams:
        row = [f"{results['ranks'][w].get(metric, {}).get(t, math.nan):g}"
               for w in results["ranks"]]
        lines.append(f"| `{_short(t, 60)}` | " + " | ".join(row) + " |")
    lines += ["", "Per match (both teams together; within 25 % of the league's value: yes/no):",
              "", "| statistic | " + " | ".join(results["stats"]) + " |",
              "|---|" + "---|" * len(results["stats"])]
    keys = [k for k in next(iter(results["stats"].values()), {}) if k != "matches"]
    for k in keys + ["matches"]:
        cells = []
        for w, values in results["stats"].items():
            v = values.get(k, math.nan)
            flag = results["stat_ratios"].get(w, {}).get(k, {}).get("within_25pct")
            cells.append(f"{v:.2f}" + ("" if flag is None else (" (yes)" if flag else " (no)")))
        lines.append(f"| {k} | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def _fmt(x: float) -> str:
    return "n/a" if x is None or (isinstance(x, float) and math.isnan(x)) else f"{x:+.2f}"


def _terminate(signum: int, frame: object) -> None:
    from teamenv.errors import Terminated

    raise Terminated()


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", required=True, help="folder of the run's databases, replays "
                        "and results (reused: the run resumes)")
    parser.add_argument("--teams", nargs="+", default=list(STRATEGIES),
                        help="team specs (default: the 7 strategies of graded strength)")
    parser.add_argument("--seconds", type=float, default=240.0,
                        help="game time of each match (s; default 240, as 2 x 120 s)")
    parser.add_argument("--games", type=int, default=1,
                        help="seeded rounds per pairing, each with both sides (default 1)")
    parser.add_argument("--team-size", type=int, default=7, help="players per side (default 7)")
    parser.add_argument("--seed", type=int, default=100_200,
                        help="tournament seed, from the evaluation range (default 100200)")
    parser.add_argument("-j", "--jobs", type=int, default=2, help="matches at once")
    parser.add_argument("--ray-address", default=None,
                        help="play the league matches as Ray tasks: local, auto or an address")
    parser.add_argument("--bootstrap", type=int, default=1000, help="bootstrap resamples")
    parser.add_argument("--worlds", nargs="+", default=list(WORLD_NAMES), choices=WORLD_NAMES,
                        help="which round robins to play and compare (default all three)")
    parser.add_argument("--common-pairings", action="store_true",
                        help="analyse only the pairings every world has played (a run under "
                        "way; the rankings then rest on those matches alone)")
    parser.add_argument("--analyse-only", action="store_true",
                        help="only the analysis of what is stored under --out")
    parser.add_argument("--figure", default=str(ROOT / "docs" / "fidelity_study.png"))
    parser.add_argument("--page", default=str(ROOT / "docs" / "fidelity_study.md"))
    parser.add_argument("--no-progress", action="store_true")
    parser.add_argument("--note", default="", help="a paragraph for the page (what was run)")
    args = parser.parse_args(argv)
    from teamenv.errors import Terminated
    from teamenv.seeds import EVALUATION_SEEDS

    if args.seed not in EVALUATION_SEEDS:
        parser.error(f"--seed {args.seed} is not in the evaluation range {EVALUATION_SEEDS}")
    if not args.analyse_only:
        # SIGTERM stops the run like Ctrl-C, so the worker pools shut down with it (what is
        # stored stays stored and the next run resumes)
        previous = signal.signal(signal.SIGTERM, _terminate)
        try:
            play(args)
        except Terminated:
            return 128 + signal.SIGTERM
        finally:
            signal.signal(signal.SIGTERM, previous)
    analyse(Path(args.out), args.bootstrap, 0, Path(args.figure) if args.figure else None,
            Path(args.page) if args.page else None, args.note, args.worlds,
            args.common_pairings)
    return 0


if __name__ == "__main__":
    sys.exit(main())
