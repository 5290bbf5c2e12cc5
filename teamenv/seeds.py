"""Which match seeds may be used for what: the project's evaluation protocol, in one place.

A team tuned on the seeds it is judged on looks stronger than it is: goals are rare here
(about two per full-length 7 v 7 match between unequal teams), so a handful of lucky seeds can
make a change look good. Seeds are therefore split into disjoint ranges:

- ``TUNING_SEEDS`` (0–99,999): everything used while building, tuning or analysing a team —
  unit tests, examples, the optimizer's candidates, ``benchmarks/goal_rarity.py``'s analysis
  seeds (5000 up), ad-hoc experiments.
- ``EVALUATION_SEEDS`` (100,000–199,999): every strength claim — the README's tables, the CI
  strength test, the optimizer's held-out comparison. Nobody looks at these while changing a
  team; a number measured here is reported, never tuned against.

Use :func:`evaluation_seeds` / :func:`tuning_seeds` rather than literal numbers, so that a
reader can check which side of the line a number came from.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class SeedRange:
    """A half-open range of match seeds reserved for one purpose."""

    name: str
    first: int
    end: int  # exclusive

    def take(self, count: int, offset: int = 0) -> tuple[int, ...]:
        """``count`` consecutive seeds starting ``offset`` seeds into the range."""
        if count < 0 or offset < 0:
            raise ValueError(f"{self.name} seeds: count and offset must be >= 0, "
                             f"got count={count}, offset={offset}")
        if self.first + offset + count > self.end:
            raise ValueError(f"{self.name} seeds: {count} seeds from offset {offset} run past "
                             f"the end of the range [{self.first}, {self.end})")
        return tuple(range(self.first + offset, self.first + offset + count))

    def __contains__(self, seed: object) -> bool:
        return isinstance(seed, int) and self.first <= seed < self.end


TUNING_SEEDS = SeedRange("tuning", 0, 100_000)
EVALUATION_SEEDS = SeedRange("evaluation", 100_000, 200_000)


def evaluation_seeds(count: int, offset: int = 0) -> tuple[int, ...]:
    """Seeds for strength claims (README tables, CI strength test, held-out comparisons)."""
    return EVALUATION_SEEDS.take(count, offset)


def tuning_seeds(count: int, offset: int = 0) -> tuple[int, ...]:
    """Seeds for building, tuning and analysing teams."""
    return TUNING_SEEDS.take(count, offset)


def purpose_of(seed: int) -> str:
    """``"tuning"`` or ``"evaluation"``: which range a seed belongs to."""
    for seeds in (TUNING_SEEDS, EVALUATION_SEEDS):
        if seed in seeds:
            return seeds.name
    raise ValueError(f"seed {seed} is in no reserved range (tuning [0, 100000), "
                     f"evaluation [100000, 200000))")
