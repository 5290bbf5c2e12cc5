"""Tournament definitions and schedules: round robin or gauntlet, seeded rounds, side swaps.

A match is fully determined by its *match key*: (left spec, right spec, match options, seed,
time budgets). Every pairing plays ``games_per_pairing`` rounds; round k uses the same seed
for every pairing (common random numbers), derived from the tournament seed with numpy's
SeedSequence. With ``swap_sides`` each round is played twice, once with each team on the left.
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from paramkit.checks import check_fields, in_range, non_negative, positive
from teamenv.match import MatchOptions
from teamenv.tournament.errors import TournamentConfigError
from teamenv.tournament.spec import TeamSpec, parse_team_spec

FORMATS = ("round_robin", "gauntlet")
DEFINITION_FORMAT = 1


@dataclass(frozen=True)
class Tournament:
    """What a tournament plays; everything that changes a result is in here (and its hash).

    Attributes:
        name: the tournament's name, unique within a results database.
        teams: the field (round robin: every pair plays; gauntlet: the challenger's opponents).
        format: "round_robin" or "gauntlet".
        challenger: the gauntlet's challenger (None for round robin).
        games_per_pairing: seeded rounds per pairing (>= 1); x2 matches with ``swap_sides``.
        swap_sides: play every round once with each team on the left.
        seed: base seed of the tournament (round seeds derive from it).
        options: how each match is played (field preset, team size, half length in seconds...).
        cycle_time_budget_s: a team whose act() takes longer in one cycle forfeits (seconds).
        stall_timeout_s: a cycle still running after this long is interrupted; the acting team
            forfeits ("stalled") (seconds; None disables).
    """

    name: str
    teams: tuple[TeamSpec, ...]
    format: str = "round_robin"
    challenger: TeamSpec | None = None
    games_per_pairing: int = field(default=2, metadata=in_range(1))
    swap_sides: bool = True
    seed: int = field(default=0, metadata=non_negative())
    options: MatchOptions = field(default_factory=MatchOptions)
    cycle_time_budget_s: float | None = field(default=None, metadata=positive(infinite=True))
    stall_timeout_s: float | None = field(default=10.0, metadata=positive(infinite=True))

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name.strip():
            raise TournamentConfigError(f"tournament name: must be a non-empty string, got "
                                        f"{self.name!r}")
        object.__setattr__(self, "teams", tuple(parse_team_spec(t) for t in self.teams))
        if self.challenger is not None:
            object.__setattr__(self, "challenger", parse_team_spec(self.challenger))
        if self.format not in FORMATS:
            raise TournamentConfigError(f"tournament format: {self.format!r}; choose one of "
                                        f"{list(FORMATS)}")
        if self.format == "gauntlet":
            if self.challenger is None:
                raise TournamentConfigError("gauntlet: a challenger team is required")
            if len(self.teams) < 1:
                raise TournamentConfigError("gauntlet: at least one opponent is required")
        else:
            if self.challenger is not None:
                raise TournamentConfigError(f"round robin: challenger {self.challenger.label!r} "
                                            "given; use format='gauntlet'")
            if len(self.teams) < 2:
                raise TournamentConfigError(f"round robin: at least two teams are required, got "
                                            f"{[t.label for t in self.teams]}")
        labels = [t.label for t in self.all_teams]
        dupes = sorted({x for x in labels if labels.count(x) > 1})
        if dupes:
            raise TournamentConfigError(f"teams: {dupes} named more than once")
        if not isinstance(self.options, MatchOptions):
            try:
                object.__setattr__(self, "options", MatchOptions.from_dict(self.options))
            except Exception as exc:
                raise TournamentConfigError(f"match options: {exc}") from exc
        check_fields(self, TournamentConfigError)  # the numbers (and every field's type)

    @property
    def all_teams(self) -> tuple[TeamSpec, ...]:
        """Every team in the tournament, challenger first for a gauntlet."""
        return ((self.challenger,) if self.challenger else ()) + self.teams

    def pairings(self) -> list[tuple[TeamSpec, TeamSpec]]:
        """The pairs that meet, in schedule order."""
        if self.format == "gauntlet":
            assert self.challenger is not None
            return [(self.challenger, t) for t in self.teams]
        return [(a, b) for i, a in enumerate(self.teams) for b in self.teams[i + 1:]]

    def round_seeds(self) -> list[int]:
        """The seed of each round (0 <= seed < 2**31), the same for every pairing."""
        return [round_seed(self.seed, k) for k in range(self.games_per_pairing)]

    def schedule(self) -> list[MatchTask]:
        """Every match of the tournament in schedule order (round, pairing, sides)."""
        tasks: list[MatchTask] = []
        for k, seed in enumerate(self.round_seeds()):
            for a, b in self.pairings():
                sides = ((a, b, False), (b, a, True)) if self.swap_sides else ((a, b, False),)
                for left, right, swapped in sides:
                    tasks.append(MatchTask(
                        index=len(tasks), round=k, pairing=f"{a.label} vs {b.label}", seed=seed,
                        swapped=swapped, left=left, right=right, options=self.options,
                        cycle_time_budget_s=self.cycle_time_budget_s,
                        stall_timeout_s=self.stall_timeout_s))
        return tasks

    def to_json(self) -> dict[str, Any]:
        """A JSON-able definition (what the database stores and resume compares)."""
        return {
            "format_version": DEFINITION_FORMAT, "name": self.name, "format": self.format,
            "teams": [t.to_json() for t in self.teams],
            "challenger": self.challenger.to_json() if self.challenger else None,
            "games_per_pairing": self.games_per_pairing, "swap_sides": self.swap_sides,
            "seed": self.seed, "options": self.options.to_dict(),
            "cycle_time_budget_s": self.cycle_time_budget_s,
            "stall_timeout_s": self.stall_timeout_s,
        }

    @classmethod
    def from_json(cls, data: Mapping[str, Any]) -> Tournament:
        """Rebuild a definition written by ``to_json``."""
        def spec(d: Mapping[str, Any]) -> TeamSpec:
            return TeamSpec.of(d["name"], d.get("config") or {})
        return cls(
            name=data["name"], teams=tuple(spec(t) for t in data["teams"]),
            format=data["format"],
            challenger=spec(data["challenger"]) if data.get("challenger") else None,
            games_per_pairing=data["games_per_pairing"], swap_sides=data["swap_sides"],
            seed=data["seed"], options=MatchOptions.from_dict(data["options"]),
            cycle_time_budget_s=data["cycle_time_budget_s"],
            stall_timeout_s=data["stall_timeout_s"])

    def definition_hash(self) -> str:
        return _digest(self.to_json())


@dataclass(frozen=True)
class MatchTask:
    """One scheduled match: everything a worker needs to play it, and where it sits.

    ``index`` is the position in schedule order (Elo is computed in this order, whatever order
    matches finish in); ``swapped`` is True when the pairing's second team plays on the left.
    """

    index: int
    round: int
    pairing: str
    seed: int
    swapped: bool
    left: TeamSpec
    right: TeamSpec
    options: MatchOptions
    cycle_time_budget_s: float | None = None
    stall_timeout_s: float | None = 10.0
    replay_path: str | None = None

    @property
    def key(self) -> str:
        """The match key: a hash of everything that determines the result."""
        return _digest({"left": self.left.to_json(), "right": self.right.to_json(),
                        "options": self.options.to_dict(), "seed": self.seed,
                        "cycle_time_budget_s": self.cycle_time_budget_s,
                        "stall_timeout_s": self.stall_timeout_s})


def round_seed(base_seed: int, k: int) -> int:
    """The seed of round ``k`` of a tournament with seed ``base_seed`` (31-bit int)."""
    state = np.random.SeedSequence([base_seed, k]).generate_state(1, np.uint32)[0]
    return int(state) & 0x7FFFFFFF


def round_robin(name: str, teams: Sequence[str | TeamSpec], **kwargs: Any) -> Tournament:
    """A round robin: every pair of ``teams`` meets (see Tournament for ``kwargs``)."""
    return Tournament(name=name, teams=tuple(teams), format="round_robin", **kwargs)


def gauntlet(name: str, challenger: str | TeamSpec, field_teams: Iterable[str | TeamSpec],
             **kwargs: Any) -> Tournament:
    """A gauntlet: ``challenger`` meets each of ``field_teams`` (see Tournament)."""
    return Tournament(name=name, teams=tuple(field_teams), format="gauntlet",
                      challenger=challenger, **kwargs)


def _digest(data: Any) -> str:
    text = json.dumps(data, sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()[:32]
