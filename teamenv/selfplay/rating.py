"""Rating the league's snapshots with the tournament runner.

Every new snapshot plays a gauntlet (``teamenv.tournament``) against every built-in opponent
and the ``recent`` snapshots before it: ``games_per_pairing`` seeded rounds per pairing, each
played from both sides, full matches (``half_time_s`` x ``halves``) on the training field and
team size; the untrained snapshot 0 plays a round robin with the built-in teams instead, so
they meet each other once too. Each is one tournament, ``gen-0003``, in the run's
``ratings.sqlite``: stored match by match, so a killed rating resumes where it stopped
(``run_tournament``'s resume) and loses nothing.

The ratings after generation g are fitted to every match of the tournaments ``gen-0000`` ..
``gen-g`` together (``teamenv.tournament.ratings.compute_ratings``: Bradley–Terry with a
bootstrap interval over matches, and sequential Elo in schedule order, both on the Elo scale,
mean 1500). Built-in teams are rated in every gauntlet, so they anchor the scale across
generations; a snapshot's rating moves as later snapshots play it.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import asdict, dataclass, replace
from pathlib import Path

import portable_math as pm
from teamenv.errors import ConfigError
from teamenv.match import MatchOptions
from teamenv.tournament import ResultStore, gauntlet, round_robin, run_tournament
from teamenv.tournament.ratings import Ratings, compute_ratings
from teamenv.tournament.runner import TournamentSummary
from teamenv.tournament.schedule import Tournament
from teamenv.tournament.spec import TeamSpec

RATINGS_DB = "ratings.sqlite"


@dataclass(frozen=True)
class RatingSetup:
    """How snapshots are rated: ``games_per_pairing`` rounds (x2: both sides) per pairing of
    full matches of ``halves`` x ``half_time_s`` seconds, against the built-in teams and the
    ``recent`` snapshots before; intervals from ``n_bootstrap`` resamples."""

    games_per_pairing: int = 1
    half_time_s: float = 60.0
    halves: int = 2
    recent: int = 3
    n_bootstrap: int = 200

    def __post_init__(self) -> None:
        for name in ("games_per_pairing", "halves", "recent", "n_bootstrap"):
            value = getattr(self, name)
            low = 1 if name in ("games_per_pairing", "halves") else 0
            if isinstance(value, bool) or not isinstance(value, int) or value < low:
                raise ConfigError(f"rating: {name} must be an int >= {low}, got {value!r}")
        if self.halves > 2:
            raise ConfigError(f"rating: halves must be 1 or 2, got {self.halves!r}")
        if not (isinstance(self.half_time_s, (int, float)) and math.isfinite(self.half_time_s)
                and self.half_time_s > 0):
            raise ConfigError(f"rating: half_time_s must be a number of seconds > 0, got "
                              f"{self.half_time_s!r}")

    def to_json(self) -> dict:
        return asdict(self)


def gauntlet_name(generation: int) -> str:
    """The tournament that rates the snapshot of ``generation``."""
    return f"gen-{generation:04d}"


def rating_tournament(generation: int, snapshot: TeamSpec, builtins: Sequence[TeamSpec],
                      earlier: Sequence[TeamSpec], field: str, team_size: int,
                      rating: RatingSetup, seed: int) -> Tournament:
    """The tournament that rates the snapshot of ``generation``: for generation 0 a round
    robin of the untrained snapshot and the built-in teams (the built-in teams meet each
    other once, which anchors the scale), later a gauntlet of the snapshot against the
    built-in teams and the ``earlier`` snapshots."""
    options = MatchOptions(field=field, team_size=team_size, half_time_s=rating.half_time_s,
                           halves=rating.halves)
    common = {"games_per_pairing": rating.games_per_pairing, "swap_sides": True, "seed": seed,
              "options": options}
    if generation == 0:
        return round_robin(gauntlet_name(0), [snapshot, *builtins], **common)
    return gauntlet(gauntlet_name(generation), snapshot, [*builtins, *earlier], **common)


def play_gauntlet(db: str | Path, tournament: Tournament, backend: str = "process",
                  jobs: int | None = None) -> TournamentSummary:
    """Play what is missing of ``tournament`` in ``db`` (all of it the first time)."""
    return run_tournament(tournament, db, resume=True, backend=backend, jobs=jobs,
                          progress=False, stats=False)


def league_ratings(db: str | Path, generation: int, names: Mapping[str, str],
                   n_bootstrap: int, seed: int) -> Ratings:
    """Ratings after ``generation``: every match of the gauntlets 0..``generation``, each team
    under its name in ``names`` (team label -> name; labels not in it keep their label)."""
    records = []
    with ResultStore(db) as store:
        for g in range(generation + 1):
            found = store.find_tournament(gauntlet_name(g))
            if found is None:
                continue
            for r in store.matches(found[0]):
                records.append(replace(r, left_team=names.get(r.left_team, r.left_team),
                                       right_team=names.get(r.right_team, r.right_team)))
    teams = sorted({r.left_team for r in records} | {r.right_team for r in records})
    return compute_ratings(records, teams, n_bootstrap=n_bootstrap, seed=seed)


def expected_score(ratings: Ratings, team: str, opponent: str) -> float:
    """P(``team`` beats ``opponent``) under the Bradley–Terry fit, a draw counted as half a
    win (400 Elo points = 10:1 odds); 0.5 for a team that has not been rated yet."""
    bt = ratings.bradley_terry
    if team not in bt or opponent not in bt:
        return 0.5
    diff = bt[team].rating - bt[opponent].rating
    return float(1.0 / (1.0 + pm.power(10.0, -diff / 400.0)))
