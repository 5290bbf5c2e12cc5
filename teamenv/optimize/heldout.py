"""A team's goal difference (and territory) in a stored tournament, with bootstrap intervals.

For checking an optimized config on held-out seeds, e.g.::

    teamenv tournament run full@opt1 full --db heldout.sqlite --name heldout --games 20 \\
        --seed 9000 --team-size 5 --half-time 20 --replay-dir heldout-replays -j 1
    python -m teamenv.optimize.heldout --db heldout.sqlite --name heldout --team full@opt1

The unit of resampling is the seed (a round is played from both sides on one seed, and the
two matches share its luck), so the interval is a seeded cluster bootstrap over rounds.
Territory (see ``teamenv.optimize.tournament_fitness``) is reported when the matches have
replays.
"""

from __future__ import annotations

import argparse
from collections import defaultdict
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from teamenv.optimize.checkpoint import OptimizeError
from teamenv.tournament.spec import parse_team_spec
from teamenv.tournament.store import MatchRecord, ResultStore


@dataclass(frozen=True)
class Interval:
    mean: float
    low: float
    high: float

    def __str__(self) -> str:
        return f"{self.mean:+.3f} [{self.low:+.3f}, {self.high:+.3f}]"


@dataclass(frozen=True)
class HeldOut:
    """``team``'s matches in a tournament: per-match means with 95 % intervals."""

    team: str
    matches: int
    seeds: int
    wins: int
    draws: int
    losses: int
    goals_for: int
    goals_against: int
    goal_difference: Interval
    territory: Interval | None

    def describe(self) -> str:
        text = (f"{self.team}: {self.matches} matches on {self.seeds} seeds, W/D/L "
                f"{self.wins}/{self.draws}/{self.losses}, goals {self.goals_for}-"
                f"{self.goals_against}\n  goal difference per match {self.goal_difference} "
                "(95 % bootstrap over seeds)")
        if self.territory is not None:
            text += f"\n  territory per match       {self.territory}"
        return text


def bootstrap(values_by_seed: Sequence[Sequence[float]], resamples: int = 2000,
              seed: int = 0) -> Interval:
    """Mean per match and its 95 % percentile interval, resampling whole seeds."""
    sums = np.array([sum(v) for v in values_by_seed], dtype=np.float64)
    counts = np.array([len(v) for v in values_by_seed], dtype=np.float64)
    rng = np.random.default_rng(seed)
    picks = rng.integers(0, len(sums), size=(resamples, len(sums)))
    means = sums[picks].sum(axis=1) / counts[picks].sum(axis=1)
    low, high = np.percentile(means, [2.5, 97.5])
    return Interval(float(sums.sum() / counts.sum()), float(low), float(high))


def held_out(records: Sequence[MatchRecord], team: str, resamples: int = 2000,
             seed: int = 0) -> HeldOut:
    """``team``'s (a label as stored) results over ``records``, its matches only."""
    from teamenv.optimize.tournament_fitness import territory
    from teamenv.replay import load_replay

    mine = [r for r in records if team in (r.left_team, r.right_team)]
    if not mine:
        raise OptimizeError(f"held-out check: no match of {team!r}; the teams are "
                            f"{sorted({r.left_team for r in records} | {r.right_team for r in records})}")
    gd, terr = defaultdict(list), defaultdict(list)
    gf = ga = wins = draws = 0
    have_replays = all(r.replay_path and Path(r.replay_path).is_file() for r in mine)
    for r in mine:
        sign = 1 if r.left_team == team else -1
        ours, theirs = (r.left_official, r.right_official)[::sign]
        gf, ga = gf + ours, ga + theirs
        wins += ours > theirs
        draws += ours == theirs
        gd[r.seed].append(float(ours - theirs))
        if have_replays:
            terr[r.seed].append(sign * territory(load_replay(r.replay_path)))
    seeds = sorted(gd)
    return HeldOut(team, len(mine), len(seeds), wins, draws, len(mine) - wins - draws, gf, ga,
                   bootstrap([gd[s] for s in seeds], resamples, seed),
                   bootstrap([terr[s] for s in seeds], resamples, seed) if have_replays
                   else None)


def main(argv: Sequence[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m teamenv.optimize.heldout", description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--db", type=Path, required=True)
    p.add_argument("--name", default=None, help="tournament (default: the only one)")
    p.add_argument("--team", required=True, help="the team spec to report (e.g. full@opt1)")
    p.add_argument("--resamples", type=int, default=2000)
    p.add_argument("--seed", type=int, default=0, help="seed of the bootstrap")
    args = p.parse_args(argv)
    label = parse_team_spec(args.team).label
    with ResultStore(args.db) as store:
        tid, _ = store.get_tournament(args.name)
        records = store.matches(tid)
    print(held_out(records, label, args.resamples, args.seed).describe())
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
