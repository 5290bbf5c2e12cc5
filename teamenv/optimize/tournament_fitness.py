"""Fitness from seeded matches: each candidate plays a gauntlet against a fixed field.

Generation g's candidates each get a gauntlet tournament ``RUN/gGGG/cCC`` in the results
database, all with the tournament seed ``tune_seed + g``: every candidate meets every
opponent on the same match seeds, from both sides (common random numbers, so the difference
between two candidates is not the luck of their seeds). All the generation's matches go to
one backend run (process pool, Ray or serial); each is stored as it ends, so a killed run
loses only the matches in flight and a resume plays only the missing ones.

Fitness of a candidate = mean official goal difference per match (its goals minus the
opponent's; a forfeit counts 0-3) + ``metric_weight`` x the mean of a finer match metric,
from the candidate's side:
  ``territory``: the ball's mean x position over the match in the candidate's attacking
      direction, in half-lengths of the pitch (-1 at its own goal line, +1 at the other);
  ``xg``: its expected goals minus the opponent's (``teamenv.analytics``' xG model).
Goals are rare in short matches, so goal difference alone is mostly 0; the metric tells a
candidate that pins the opponent back (or shoots from better places) from one that is pinned
back. It is read from each match's replay, stored per match in the database, and the replay
file is deleted. ``metric_weight=0`` gives goal difference alone (no replays recorded).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from teamenv.match import MatchOptions
from teamenv.optimize.checkpoint import CheckpointStore, OptimizeError
from teamenv.optimize.cmaes_loop import CandidateScore, Reporter
from teamenv.tournament.backends import make_backend
from teamenv.tournament.schedule import MatchTask, Tournament, gauntlet
from teamenv.tournament.spec import TeamSpec, parse_team_spec, validate_specs
from teamenv.tournament.store import MatchRecord, ResultStore

TUNE_SEED = 7000  # generation g plays tournament seed TUNE_SEED + g (held-out checks: 9000+)
METRICS = ("territory", "xg")


class TournamentFitness:
    """Scores candidates of ``team`` (a registered name or ``module:Class``, with the fixed
    ``base_config`` under every candidate) by gauntlets against ``field_teams``.

    ``games``: seeded rounds per opponent, each played from both sides (2 x games matches per
    opponent per candidate). ``backend``/``jobs``/``ray_address``: as ``run_tournament``
    (they do not change results, so they are not part of the definition).
    """

    def __init__(self, db: str | Path, run: str, team: str, field_teams: Sequence[str | TeamSpec],
                 *, base_config: dict[str, Any] | None = None,
                 options: MatchOptions | None = None, games: int = 1,
                 tune_seed: int = TUNE_SEED, metric: str = "territory",
                 metric_weight: float = 1.0,
                 cycle_time_budget_s: float | None = None, stall_timeout_s: float | None = 10.0,
                 backend: str = "process", jobs: int | None = None,
                 ray_address: str | None = None) -> None:
        self.db = Path(db)
        self.run = run
        self.team = team
        self.field = tuple(parse_team_spec(t) for t in field_teams)
        if not self.field:
            raise OptimizeError("--against: give at least one opponent team")
        self.base_config = dict(base_config or {})
        self.options = options or MatchOptions()
        if isinstance(games, bool) or not isinstance(games, int) or games < 1:
            raise OptimizeError(f"games: must be an int >= 1, got {games!r}")
        self.games = games
        if isinstance(tune_seed, bool) or not isinstance(tune_seed, int) or tune_seed < 0:
            raise OptimizeError(f"tune seed: must be an int >= 0, got {tune_seed!r}")
        self.tune_seed = tune_seed
        if metric not in METRICS:
            raise OptimizeError(f"metric: {metric!r}; choose one of {list(METRICS)}")
        self.metric = metric
        if isinstance(metric_weight, bool) or not isinstance(metric_weight, (int, float)) \
                or not math.isfinite(metric_weight) or metric_weight < 0:
            raise OptimizeError(f"metric weight: must be a finite number >= 0, got "
                                f"{metric_weight!r}")
        self.metric_weight = float(metric_weight)
        self.cycle_time_budget_s = cycle_time_budget_s
        self.stall_timeout_s = stall_timeout_s
        self.backend = backend
        self.jobs = jobs
        self.ray_address = ray_address
        self.replay_dir = self.db.with_name(self.db.name + ".replays") / _safe(run)
        # an unknown opponent, a rejected override or bad match options fail here, at once
        validate_specs([TeamSpec.of(team, self.base_config), *self.field], self.options)

    def definition(self) -> dict[str, Any]:
        return {"kind": "tournament", "team": self.team, "base_config": self.base_config,
                "field": [t.to_json() for t in self.field], "options": self.options.to_dict(),
                "games": self.games, "tune_seed": self.tune_seed,
                "metric": self.metric, "metric_weight": self.metric_weight,
                "cycle_time_budget_s": self.cycle_time_budget_s,
                "stall_timeout_s": self.stall_timeout_s}

    @classmethod
    def from_definition(cls, data: dict[str, Any], db: str | Path, run: str,
                        **execution: Any) -> TournamentFitness:
        """Rebuild the evaluator of a stored run (``execution``: backend, jobs, ray_address)."""
        if data.get("kind") != "tournament":
            raise OptimizeError(f"optimization run {run!r}: its fitness is {data.get('kind')!r}, "
                                "not matches; resume it from the code that started it")
        return cls(db, run, data["team"], [TeamSpec.of(t["name"], t["config"])
                                           for t in data["field"]],
                   base_config=data["base_config"], options=MatchOptions.from_dict(data["options"]),
                   games=data["games"], tune_seed=data["tune_seed"],
                   metric=data["metric"], metric_weight=data["metric_weight"],
                   cycle_time_budget_s=data["cycle_time_budget_s"],
                   stall_timeout_s=data["stall_timeout_s"], **execution)

    def candidate_spec(self, config: dict[str, Any]) -> TeamSpec:
        return TeamSpec.of(self.team, {**self.base_config, **config})

    def tournament(self, generation: int, index: int, config: dict[str, Any]) -> Tournament:
        """Candidate ``index`` of ``generation``'s gauntlet (same seed for every candidate)."""
        return gauntlet(f"{self.run}/g{generation:03d}/c{index:02d}", self.candidate_spec(config),
                        self.field, games_per_pairing=self.games, swap_sides=True,
                        seed=self.tune_seed + generation, options=self.options,
                        cycle_time_budget_s=self.cycle_time_budget_s,
                        stall_timeout_s=self.stall_timeout_s)

    def evaluate(self, generation: int, configs: list[dict[str, Any]],
                 reporter: Reporter) -> list[CandidateScore]:
        # candidates that decode to the same config (rounded integers, choices) play once:
        # matches are deterministic, so they would score the same anyway
        first: dict[str, int] = {}
        for i, c in enumerate(configs):
            first.setdefault(self.candidate_spec(c).label, i)
        owner = [first[self.candidate_spec(c).label] for c in configs]
        played = sorted(set(owner))
        tournaments = [self.tournament(generation, i, configs[i]) for i in played]
        specs = {s.label: s for t in tournaments for s in t.all_teams}
        versions = validate_specs(list(specs.values()), self.options)
        with ResultStore(self.db) as results, CheckpointStore(self.db) as checkpoints:
            ids = [self._tournament_id(results, t, versions) for t in tournaments]
            todo: list[tuple[int, MatchTask]] = []
            for tid, t in zip(ids, tournaments, strict=True):
                done = results.completed_indices(tid)
                todo += [(tid, self._with_replay(t, task)) for task in t.schedule()
                         if task.index not in done]
            total = sum(len(t.schedule()) for t in tournaments)
            reporter.generation_started(generation, 0, total, total - len(todo))
            self._play(results, checkpoints, todo, reporter)
            scores = {i: self._score(results, checkpoints, tid, t)
                      for i, tid, t in zip(played, ids, tournaments, strict=True)}
            return [scores[i] for i in owner]

    def _tournament_id(self, results: ResultStore, tournament: Tournament,
                       versions: dict[str, str]) -> int:
        found = results.find_tournament(tournament.name)
        if found is None:
            return results.create_tournament(tournament, {s.label: versions[s.label]
                                                          for s in tournament.all_teams})
        tid, stored = found
        if stored.definition_hash() != tournament.definition_hash():
            raise OptimizeError(f"tournament {tournament.name!r} in {str(self.db)!r} has another "
                                "definition than this run's candidate; use a new run name")
        stored_versions = results.team_versions(tid)
        changed = {s.label: (stored_versions.get(s.label), versions[s.label])
                   for s in tournament.all_teams
                   if stored_versions.get(s.label) != versions[s.label]}
        if changed:
            raise OptimizeError(f"tournament {tournament.name!r}: team versions changed since it "
                                f"started {changed} (stored, now); start a new run")
        return tid

    def _with_replay(self, tournament: Tournament, task: MatchTask) -> MatchTask:
        if self.metric_weight == 0:
            return task
        path = self.replay_dir / f"{_safe(tournament.name)}-{task.index:04d}.npz"
        return replace(task, replay_path=str(path))

    def _play(self, results: ResultStore, checkpoints: CheckpointStore,
              todo: list[tuple[int, MatchTask]], reporter: Reporter) -> None:
        if not todo:
            return
        runner = make_backend(self.backend, self.jobs, self.ray_address)
        prepare = getattr(runner, "prepare", None)
        if prepare is not None:
            prepare(sorted({self.team} | {s.name for s in self.field}))
        # candidates differ, so (match key, index) names one task of one candidate's gauntlet
        tid_of = {(task.key, task.index): tid for tid, task in todo}
        failures = []
        outcomes = runner.run([task for _, task in todo])
        try:
            for outcome in outcomes:
                task = outcome.task
                tid = tid_of[(task.key, task.index)]
                if outcome.result is None:
                    results.record_failure(tid, task, outcome.error or "unknown error")
                    failures.append(f"{task.pairing} seed {task.seed}: {outcome.error}")
                    continue
                results.record_match(tid, task, outcome.result)
                if task.replay_path is not None:  # the metric now, then the replay can go
                    record = _record_of(results, tid, task.index)
                    checkpoints.save_match_metric(record.id, self.metric,
                                                  self.metric_of(record))
                    Path(task.replay_path).unlink(missing_ok=True)
                score = outcome.result.score
                reporter.match_done(f"{_short(task.left.label)} {score[0]}-{score[1]} "
                                    f"{_short(task.right.label)}")
        finally:
            outcomes.close()
        if failures:
            raise OptimizeError(f"{len(failures)} match(es) could not be played: "
                                f"{failures[:3]}; fix the cause and --resume")

    def _score(self, results: ResultStore, checkpoints: CheckpointStore, tid: int,
               tournament: Tournament) -> CandidateScore:
        records = results.matches(tid)
        if len(records) != len(tournament.schedule()):
            raise OptimizeError(f"tournament {tournament.name!r}: {len(records)} of "
                                f"{len(tournament.schedule())} matches stored; --resume")
        me = tournament.challenger.label if tournament.challenger else ""
        sign = [1.0 if r.left_team == me else -1.0 for r in records]
        gd = float(np.mean([s * (r.left_official - r.right_official)
                            for s, r in zip(sign, records, strict=True)]))
        if self.metric_weight == 0:
            return CandidateScore(gd, gd, None, len(records))
        metrics = checkpoints.match_metrics(self.metric, [r.id for r in records])
        fine = []
        for s, r in zip(sign, records, strict=True):
            value = metrics.get(r.id)
            if value is None:  # killed between storing the match and its metric
                value = self.metric_of(r)
                checkpoints.save_match_metric(r.id, self.metric, value)
                if r.replay_path:
                    Path(r.replay_path).unlink(missing_ok=True)
            fine.append(s * value)
        mean = float(np.mean(fine))
        return CandidateScore(gd + self.metric_weight * mean, gd, mean, len(records))

    def metric_of(self, record: MatchRecord) -> float:
        """The metric of a stored match for its *left* side, from its replay."""
        from teamenv.replay import load_replay

        if not record.replay_path or not Path(record.replay_path).is_file():
            raise OptimizeError(f"match {record.id} ({record.pairing}, seed {record.seed}): "
                                f"its replay {record.replay_path!r} is missing, so its "
                                f"{self.metric} cannot be computed; start a new run")
        replay = load_replay(record.replay_path)
        if self.metric == "xg":
            from teamenv.analytics.stats import match_stats

            stats = match_stats(replay)
            return float(stats.left.xg - stats.right.xg)
        return territory(replay)


def territory(replay: Any) -> float:
    """The ball's mean x over a replay in half-lengths, from the left side's view (the left
    side attacks +x, or the way ``attack_sign`` says where sides change at half time)."""
    from teamenv.field import field_preset

    meta = replay.metadata
    half = float(meta["half_length"]) if "half_length" in meta else \
        field_preset(meta["field"]).half_length
    x = replay.ball[:, 0].astype(np.float64) / half
    sign = getattr(replay, "attack_sign", None)
    if sign is not None:
        x = x * sign.astype(np.float64)
    return float(np.mean(np.clip(x, -1.0, 1.0)))


def _record_of(results: ResultStore, tid: int, index: int) -> MatchRecord:
    for record in results.matches(tid):
        if record.idx == index:
            return record
    raise OptimizeError(f"match #{index} of tournament {tid} was not stored")


def _safe(name: str) -> str:
    return "".join(c if c.isalnum() or c in "-_" else "_" for c in name)


def _short(label: str) -> str:
    return label if len(label) <= 24 else label[:21] + "..."
