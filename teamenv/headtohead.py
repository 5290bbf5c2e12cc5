"""Head to head: N seeded matches between two teams, sides alternating, on a process pool.

The quick way to ask "is team A better than team B?" without a tournament database:
match k uses seed k, with A on the left for even k and on the right for odd k, so neither team
gets a side's advantage. Results are the same for the same seeds, whatever the pool size.
"""

from __future__ import annotations

from collections.abc import Mapping
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from typing import Any

from teamenv.match import MatchOptions, play_match


@dataclass(frozen=True)
class HeadToHead:
    """Scores of ``team_a`` against ``team_b``, one (goals A, goals B) pair per seed."""

    team_a: str
    team_b: str
    seeds: tuple[int, ...]
    scores: tuple[tuple[int, int], ...]
    forfeits: tuple[str, ...]

    @property
    def goals(self) -> tuple[int, int]:
        """Aggregate (goals of A, goals of B)."""
        return (sum(s[0] for s in self.scores), sum(s[1] for s in self.scores))

    @property
    def record(self) -> tuple[int, int, int]:
        """(wins of A, draws, wins of B)."""
        wins = sum(a > b for a, b in self.scores)
        losses = sum(a < b for a, b in self.scores)
        return wins, len(self.scores) - wins - losses, losses

    def summary(self) -> str:
        won, drawn, lost = self.record
        ga, gb = self.goals
        return (f"{self.team_a} vs {self.team_b}: aggregate {ga}-{gb} over {len(self.scores)} "
                f"matches (W{won} D{drawn} L{lost}); per seed {list(self.scores)}")


def _one(task: tuple[str, str, int, MatchOptions, dict, dict]) -> tuple[int, int, str]:
    a, b, seed, options, config_a, config_b = task
    if seed % 2 == 0:
        r = play_match(a, b, seed, options, left_config=config_a, right_config=config_b)
        score = (r.score[0], r.score[1])
    else:
        r = play_match(b, a, seed, options, left_config=config_b, right_config=config_a)
        score = (r.score[1], r.score[0])
    forfeit = "" if r.forfeit is None else f"seed {seed}: {r.forfeit}"
    return score[0], score[1], forfeit


def head_to_head(team_a: str, team_b: str, seeds: int | tuple[int, ...] = 10,
                 options: MatchOptions | Mapping[str, Any] | None = None,
                 config_a: Mapping[str, Any] | None = None,
                 config_b: Mapping[str, Any] | None = None, jobs: int = 1) -> HeadToHead:
    """Play ``team_a`` against ``team_b`` once per seed (``seeds`` = a count or the seeds).

    ``jobs`` > 1 plays matches in that many processes (same results as ``jobs=1``).
    """
    seed_list = tuple(range(seeds)) if isinstance(seeds, int) else tuple(int(s) for s in seeds)
    if options is None:
        options = MatchOptions()
    elif not isinstance(options, MatchOptions):
        options = MatchOptions.from_dict(options)
    tasks = [(team_a, team_b, s, options, dict(config_a or {}), dict(config_b or {}))
             for s in seed_list]
    if jobs > 1 and len(tasks) > 1:
        with ProcessPoolExecutor(max_workers=jobs) as pool:
            results = list(pool.map(_one, tasks))
    else:
        results = [_one(t) for t in tasks]
    return HeadToHead(team_a, team_b, seed_list, tuple((a, b) for a, b, _ in results),
                      tuple(f for _, _, f in results if f))
