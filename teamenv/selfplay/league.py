"""The self-play league loop: train, snapshot, rate, choose the next opponents; resumable.

A run directory holds::

    league.sqlite          configuration, per generation: opponents, training outcomes, ratings
    ratings.sqlite         every rating match (teamenv.tournament's store), gauntlet gen-g
    snapshots/gen-g.npz    the frozen snapshot of each generation (a policy file)
    learner/gen-g/         the learner's checkpoint after generation g (the last two kept)

Generation 0 is the untrained network. Generation g >= 1:

1. the opponents: the built-in teams and snapshots 0..g-1, each weighted by PFSP
   (``teamenv.selfplay.pfsp``) of the learner's expected score against it — the Bradley–Terry
   ratings after generation g-1, read for snapshot g-1, which is the learner as it is now;
2. the learner, loaded from its checkpoint of generation g-1, trains
   ``steps_per_generation`` agent-decisions against opponents drawn per episode from that mix;
3. its checkpoint and snapshot g are saved, and the generation recorded as trained;
4. snapshot g plays its rating gauntlet (snapshot 0: a round robin with the built-in teams),
   and every team's ratings are refitted and recorded.

Deterministic given the configuration: every seed derives from the run's seed and the
generation (``generation_seed``), the learner always continues from its saved checkpoint (an
uninterrupted run takes exactly the path a resumed one takes), and matches are seeded. A run
killed at any point (kill -9 included) and resumed ends with the same snapshots, opponents and
ratings as one that never stopped: a generation killed in training is trained again from the
same checkpoint; one killed in rating is not retrained (its snapshot's digest is checked) and
its gauntlet resumes from the stored matches.
"""

from __future__ import annotations

import importlib
import shutil
import time
from collections import defaultdict
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from teamenv.errors import ConfigError
from teamenv.match import MatchOptions
from teamenv.selfplay.config import LeagueConfig
from teamenv.selfplay.league_store import LEAGUE_DB, LeagueStore
from teamenv.selfplay.learner import Learner
from teamenv.selfplay.pfsp import OpponentMix, pfsp_probabilities
from teamenv.selfplay.rating import (
    RATINGS_DB,
    expected_score,
    league_ratings,
    play_gauntlet,
    rating_tournament,
)
from teamenv.selfplay.snapshots import SnapshotPool, policy_digest, snapshot_name
from teamenv.tournament.errors import TournamentError
from teamenv.tournament.ratings import Ratings
from teamenv.tournament.spec import TeamSpec, parse_team_spec, validate_specs

LEARNER_DIR = "learner"
#: What each derived seed is for (the third entropy word of ``generation_seed``).
SEED_PURPOSES = ("train", "opponents", "rating")


def generation_seed(seed: int, generation: int, purpose: str) -> int:
    """The seed for ``purpose`` (``SEED_PURPOSES``) in ``generation`` of a run seeded ``seed``
    (a 31-bit int)."""
    state = np.random.SeedSequence([seed, generation, SEED_PURPOSES.index(purpose)])
    return int(state.generate_state(1)[0]) & 0x7FFFFFFF


def make_learner(config: LeagueConfig) -> Learner:
    """The learner ``config.learner`` names: "ppo", "imitation" (PPO warm-started by cloning
    a teacher, ``teamenv.selfplay.imitation``) or ``module:Class``."""
    if config.learner == "ppo":
        from teamenv.selfplay.sb3_learner import PPOLearner

        factory: Callable[..., Any] = PPOLearner
    elif config.learner == "imitation":
        from teamenv.selfplay.imitation import ImitationPPOLearner

        factory = ImitationPPOLearner
    else:
        module, _, name = config.learner.partition(":")
        try:
            factory = getattr(importlib.import_module(module), name)
        except (ImportError, AttributeError, ValueError) as exc:
            raise ConfigError(f"selfplay: learner {config.learner!r}: cannot load it ({exc}); "
                              "give 'ppo', 'imitation' or 'module:Class'") from None
    try:
        return factory(config.training, seed=config.seed, **config.learner_options)
    except TypeError as exc:
        raise ConfigError(f"selfplay: learner {config.learner!r} with options "
                          f"{config.learner_options}: {exc}") from None


def check_builtins(config: LeagueConfig) -> None:
    """Build every built-in opponent once, as a rating match would (``validate_specs``), so
    an unknown team fails before anything is trained."""
    options = MatchOptions(field=config.training.field, team_size=config.training.team_size)
    try:
        validate_specs([parse_team_spec(b) for b in config.builtins], options)
    except TournamentError as exc:
        raise ConfigError(f"selfplay: built-in opponents: {exc}") from None


@dataclass(frozen=True)
class LeagueSummary:
    """Where a run stands: generations rated, the latest ratings, the run directory."""

    run_dir: Path
    rated: int                 # generations rated (0..rated-1)
    trained_now: int           # generations trained by this call
    ratings: Ratings | None

    def describe(self) -> str:
        lines = [f"self-play league {str(self.run_dir)!r}: {self.rated} generation(s) rated "
                 f"(0 = untrained), {self.trained_now} trained now"]
        if self.ratings is not None:
            lines.append(f"Bradley-Terry ratings (Elo scale, {self.ratings.confidence:.0%} "
                         f"bootstrap interval, {self.ratings.n_games} matches):")
            for team, r in self.ratings.bradley_terry.items():
                lines.append(f"  {team:10s} {r.rating:7.1f}  [{r.low:7.1f}, {r.high:7.1f}]")
        return "\n".join(lines)


class League:
    """One run directory's league (see the module docstring); ``run(generations)``."""

    def __init__(self, run_dir: str | Path, config: LeagueConfig | None = None, *,
                 resume: bool = False, learner: Learner | None = None,
                 backend: str = "process", jobs: int | None = None,
                 log: Callable[[str], None] | None = print) -> None:
        self.run_dir = Path(run_dir).resolve()
        db = self.run_dir / LEAGUE_DB
        stored = None
        if db.is_file():
            with LeagueStore(db) as store:
                stored = store.config()
        if stored is None:
            if resume:
                raise ConfigError(f"selfplay: nothing to resume in {str(self.run_dir)!r} (no "
                                  f"league in {LEAGUE_DB}); start a run without --resume")
            self.config = config or LeagueConfig()
        else:
            stored_config = LeagueConfig.from_json(stored)
            if not resume:
                raise ConfigError(f"selfplay: {str(self.run_dir)!r} holds a league already; "
                                  "continue it with --resume or choose another directory")
            if config is not None and config.to_json() != stored_config.to_json():
                diff = _differences(stored_config.to_json(), config.to_json())
                raise ConfigError(f"selfplay: the configuration differs from the stored one "
                                  f"(key: stored, given) {diff}; resume without changing it")
            self.config = stored_config
        # Everything that can refuse the configuration runs before the run directory is made.
        check_builtins(self.config)
        self.learner = learner if learner is not None else make_learner(self.config)
        self.store = LeagueStore(db)
        if stored is None:
            self.store.set_config(self.config.to_json())
        self.pool = SnapshotPool(self.run_dir, self.config.training)
        self.backend, self.jobs = backend, jobs
        self.log = log or (lambda text: None)
        self.builtins = [parse_team_spec(b) for b in self.config.builtins]

    def close(self) -> None:
        self.store.close()

    def __enter__(self) -> League:
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()

    # -- names -------------------------------------------------------------------------------
    def names(self, generations: int) -> dict[str, str]:
        """Team label -> name for ratings: snapshots 0..generations-1 and the built-ins."""
        out = {b.label: b.label for b in self.builtins}
        out.update({self.pool.spec(g).label: snapshot_name(g) for g in range(generations)})
        return out

    def checkpoint(self, generation: int) -> Path:
        return self.run_dir / LEARNER_DIR / snapshot_name(generation)

    # -- the loop ----------------------------------------------------------------------------
    def run(self, generations: int) -> LeagueSummary:
        """Train and rate until generations 0..``generations`` are rated (``generations``
        trained ones after the untrained snapshot 0)."""
        if isinstance(generations, bool) or not isinstance(generations, int) or generations < 0:
            raise ConfigError(f"selfplay: generations must be an int >= 0, got {generations!r}")
        trained_now = 0
        for g in range(self.store.last_rated() + 1, generations + 1):
            record = self.store.generation(g)
            if record is None:
                self._train(g)
                trained_now += 1
            elif record.digest != _digest_or_none(self.pool, g):
                raise ConfigError(f"selfplay: snapshot {str(self.pool.path(g))!r} is missing or "
                                  f"differs from the one generation {g} recorded; its rating "
                                  "matches would mix two networks (start a new run)")
            self._rate(g)
        last = self.store.last_rated()
        return LeagueSummary(self.run_dir, last + 1, trained_now,
                             self.store.ratings(last) if last >= 0 else None)

    def opponent_mix(self, generation: int) -> tuple[OpponentMix, list[dict[str, Any]]]:
        """The PFSP opponents of ``generation`` (>= 1), and their record (name, p_win,
        probability) for the league database."""
        previous = self.store.ratings(generation - 1)
        if previous is None:
            raise ConfigError(f"selfplay: generation {generation - 1} is not rated yet")
        learner = snapshot_name(generation - 1)
        teams: list[TeamSpec] = [*self.builtins,
                                 *(self.pool.spec(g) for g in range(generation))]
        names = [b.label for b in self.builtins] + [snapshot_name(g) for g in range(generation)]
        p_win = [expected_score(previous, learner, name) for name in names]
        c = self.config
        probs = pfsp_probabilities(p_win, c.pfsp, c.pfsp_exponent, c.latest_share,
                                   latest=len(names) - 1)
        mix = OpponentMix(tuple(teams), tuple(probs),
                          generation_seed(c.seed, generation, "opponents"))
        record = [{"team": n, "p_win": float(p), "probability": float(q)}
                  for n, p, q in zip(names, p_win, probs, strict=True)]
        return mix, record

    def _train(self, g: int) -> None:
        start = time.perf_counter()
        if g == 0:
            weights, opponents, training = self.learner.initial_weights(), [], {"steps": 0}
        else:
            self.learner.load(self.checkpoint(g - 1))
            mix, opponents = self.opponent_mix(g)
            steps = self.config.steps_per_generation
            weights = self.learner.train(steps, mix, generation_seed(self.config.seed, g,
                                                                      "train"))
            training = {"steps": steps, "episodes": _episode_summary(
                getattr(self.learner, "last_episodes", None), self.names(g))}
        self._save_checkpoint(g)
        digest = self.pool.write(g, weights)
        wall = time.perf_counter() - start
        self.store.record_trained(g, snapshot_name(g), digest, opponents, training, wall)
        if opponents:
            mix_text = ", ".join(f"{o['team']} {o['probability']:.2f}" for o in opponents)
            self.log(f"generation {g}: trained {training['steps']} agent-decisions in "
                     f"{wall:.1f} s; opponents drawn with {mix_text}")
        else:
            self.log(f"generation 0: the untrained network saved as {snapshot_name(0)}")

    def _save_checkpoint(self, g: int) -> None:
        """The learner's state after generation ``g``: saved to a temporary directory and
        renamed into place; checkpoints older than ``g - 1`` removed."""
        final = self.checkpoint(g)
        temporary = final.with_name(final.name + ".tmp")
        shutil.rmtree(temporary, ignore_errors=True)
        temporary.mkdir(parents=True)
        self.learner.save(temporary)
        shutil.rmtree(final, ignore_errors=True)
        temporary.rename(final)
        for old in final.parent.glob("gen-*"):
            if old.name < snapshot_name(max(0, g - 1)) and old.is_dir():
                shutil.rmtree(old, ignore_errors=True)

    def _rate(self, g: int) -> None:
        start = time.perf_counter()
        c = self.config
        recent = range(max(0, g - c.rating.recent), g)
        tournament = rating_tournament(g, self.pool.spec(g), self.builtins,
                                       [self.pool.spec(k) for k in recent], c.training.field,
                                       c.training.team_size, c.rating,
                                       generation_seed(c.seed, g, "rating"))
        play_gauntlet(self.run_dir / RATINGS_DB, tournament, self.backend, self.jobs)
        ratings = league_ratings(self.run_dir / RATINGS_DB, g, self.names(g + 1),
                                 c.rating.n_bootstrap, c.seed)
        wall = time.perf_counter() - start
        self.store.record_rated(g, ratings, wall)
        r = ratings.bradley_terry[snapshot_name(g)]
        self.log(f"generation {g}: rated in {wall:.1f} s ({len(tournament.schedule())} "
                 f"matches): Bradley-Terry {r.rating:.0f} [{r.low:.0f}, {r.high:.0f}]")


def run_league(run_dir: str | Path, generations: int, config: LeagueConfig | None = None, *,
               resume: bool = False, learner: Learner | None = None,
               backend: str = "process", jobs: int | None = None,
               log: Callable[[str], None] | None = print) -> LeagueSummary:
    """Run (or resume) the league in ``run_dir`` until ``generations`` are trained and every
    snapshot 0..``generations`` is rated (see ``League``)."""
    with League(run_dir, config, resume=resume, learner=learner, backend=backend, jobs=jobs,
                log=log) as league:
        return league.run(generations)


def _digest_or_none(pool: SnapshotPool, generation: int) -> str | None:
    return policy_digest(pool.path(generation)) if pool.exists(generation) else None


def _episode_summary(episodes, names: dict[str, str]) -> dict[str, dict[str, float]]:
    """Per opponent (by name): episodes, wins, draws, losses, goals for and against, and the
    mean episode return (shaping included: the signal the learner had when goals are rare)."""
    out: dict[str, dict[str, float]] = defaultdict(lambda: dict.fromkeys(
        ("episodes", "wins", "draws", "losses", "goals_for", "goals_against"), 0))
    returns: dict[str, list[float]] = defaultdict(list)
    for e in episodes or ():
        name = names.get(e.opponent, e.opponent)
        row = out[name]
        row["episodes"] += 1
        row["wins" if e.goals_for > e.goals_against else
            "losses" if e.goals_for < e.goals_against else "draws"] += 1
        row["goals_for"] += e.goals_for
        row["goals_against"] += e.goals_against
        returns[name].append(e.ret)
    for name, values in returns.items():
        out[name]["mean_return"] = round(float(np.mean(values)), 6)
    return {k: out[k] for k in sorted(out)}


def _differences(stored: dict, given: dict, prefix: str = "") -> dict[str, tuple]:
    out: dict[str, tuple] = {}
    for key in sorted(set(stored) | set(given)):
        a, b = stored.get(key), given.get(key)
        if isinstance(a, dict) and isinstance(b, dict):
            out.update(_differences(a, b, f"{prefix}{key}."))
        elif a != b:
            out[prefix + key] = (a, b)
    return out
