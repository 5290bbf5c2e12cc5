"""The progress display of ``teamenv optimize``: generations and the current one's matches."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from teamenv.optimize.cmaes_loop import CandidateScore


class RichReporter:
    """Two rich progress bars (generations; matches of the running generation) and one line
    per finished generation (best and mean fitness). ``enabled=False``: the lines only."""

    def __init__(self, console: Any, enabled: bool = True) -> None:
        from rich.progress import (
            BarColumn,
            MofNCompleteColumn,
            Progress,
            TextColumn,
            TimeElapsedColumn,
            TimeRemainingColumn,
        )

        self.console = console
        self.enabled = enabled
        self.progress = Progress(TextColumn("[bold]{task.description}"), BarColumn(),
                                 MofNCompleteColumn(), TimeElapsedColumn(),
                                 TimeRemainingColumn(), TextColumn("{task.fields[last]}"),
                                 console=console, disable=not enabled)
        self.gen_task = None
        self.match_task = None

    def __enter__(self) -> RichReporter:
        self.progress.__enter__()
        return self

    def __exit__(self, *exc: Any) -> None:
        self.progress.__exit__(*exc)

    def generation_started(self, generation: int, generations: int, matches: int,
                           done: int) -> None:
        if generations:  # the loop's call: the generation bar
            if self.gen_task is None:
                self.gen_task = self.progress.add_task("generations", total=generations,
                                                       completed=generation, last="")
            self.progress.update(self.gen_task, total=generations, completed=generation)
        if matches:  # the evaluator's call: this generation's matches
            if self.match_task is not None:
                self.progress.remove_task(self.match_task)
            self.match_task = self.progress.add_task(f"g{generation} matches", total=matches,
                                                     completed=done, last="")

    def match_done(self, text: str) -> None:
        if self.match_task is not None:
            self.progress.update(self.match_task, advance=1, last=text)

    def generation_done(self, generation: int, scores: Sequence[CandidateScore]) -> None:
        values = [s.fitness for s in scores]
        best = max(scores, key=lambda s: s.fitness)
        parts = f"best {best.fitness:+.3f}"
        if best.goal_difference is not None:
            parts += f" (goal diff {best.goal_difference:+.2f}"
            parts += f", fine metric {best.fine:+.3f})" if best.fine is not None else ")"
        self.console.print(f"generation {generation}: {parts}, mean {sum(values) / len(values):+.3f}"
                           f" over {len(values)} candidates")
        if self.gen_task is not None:
            self.progress.update(self.gen_task, completed=generation + 1,
                                 last=f"best {best.fitness:+.3f}")
