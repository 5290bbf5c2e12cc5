"""A league run's configuration: everything that changes its snapshots, opponents or ratings.

Stored in the run's ``league.sqlite`` when the run starts; a resumed run must use the same
(``--resume`` with no options takes it from there). How many generations to run is not part
of it: generation g depends only on the generations before it, so a run can be extended.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from teamenv.config import build_config
from teamenv.errors import ConfigError
from teamenv.selfplay.pfsp import check_weighting
from teamenv.selfplay.rating import RatingSetup
from teamenv.selfplay.training_setup import TrainingSetup
from teamenv.tournament.spec import parse_team_spec

#: Built-in opponents of the default league: the ball chaser, a team whose players hold fixed
#: spots in their own half (an easy first opponent) and the full strategy team.
DEFAULT_BUILTINS = ("chaser", "static", "full")


@dataclass(frozen=True)
class LeagueConfig:
    """A self-play league.

    Args:
        seed: the run's seed: every generation's training seed, opponent draws and rating
            tournament seed derive from it (``numpy.random.SeedSequence``).
        steps_per_generation: agent-decisions the learner trains per generation (a snapshot
            is taken after each).
        builtins: built-in opponents (team specs), in the pool from the start and in every
            rating gauntlet.
        pfsp, pfsp_exponent, latest_share: the opponent weighting
            (``teamenv.selfplay.pfsp``).
        training: ``TrainingSetup``; rating: ``RatingSetup``.
        learner: "ppo" (``teamenv.selfplay.sb3_learner.PPOLearner``, Stable-Baselines3) or
            ``module:Class`` (called as ``Class(training_setup, seed=seed, **learner_options)``).
        learner_options: keyword options of the learner (JSON scalars).
    """

    seed: int = 0
    steps_per_generation: int = 20_000
    builtins: tuple[str, ...] = DEFAULT_BUILTINS
    pfsp: str = "hard"
    pfsp_exponent: float = 2.0
    latest_share: float = 0.0
    training: TrainingSetup = field(default_factory=TrainingSetup)
    rating: RatingSetup = field(default_factory=RatingSetup)
    learner: str = "ppo"
    learner_options: Mapping[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if isinstance(self.seed, bool) or not isinstance(self.seed, int) or self.seed < 0:
            raise ConfigError(f"selfplay: seed must be an int >= 0, got {self.seed!r}")
        if isinstance(self.steps_per_generation, bool) or \
                not isinstance(self.steps_per_generation, int) or self.steps_per_generation < 1:
            raise ConfigError(f"selfplay: steps_per_generation must be an int >= 1, got "
                              f"{self.steps_per_generation!r}")
        builtins = tuple(self.builtins)
        if not builtins:
            raise ConfigError("selfplay: at least one built-in opponent is needed (the rating "
                              "scale is anchored on them)")
        labels = [parse_team_spec(b).label for b in builtins]
        if len(set(labels)) != len(labels):
            raise ConfigError(f"selfplay: built-in opponents named twice: {labels}")
        object.__setattr__(self, "builtins", tuple(labels))
        check_weighting(self.pfsp, self.pfsp_exponent)
        if not (isinstance(self.latest_share, (int, float)) and
                math.isfinite(self.latest_share) and 0.0 <= self.latest_share <= 1.0):
            raise ConfigError(f"selfplay: latest_share must be in [0, 1], got "
                              f"{self.latest_share!r}")
        if not isinstance(self.training, TrainingSetup):
            raise ConfigError(f"selfplay: training must be a TrainingSetup, got "
                              f"{self.training!r}")
        if not isinstance(self.rating, RatingSetup):
            raise ConfigError(f"selfplay: rating must be a RatingSetup, got {self.rating!r}")
        if not isinstance(self.learner, str) or not self.learner:
            raise ConfigError(f"selfplay: learner must be 'ppo' or 'module:Class', got "
                              f"{self.learner!r}")
        options = dict(self.learner_options)
        for key, value in options.items():
            if not isinstance(key, str) or (value is not None and
                                            not isinstance(value, (bool, int, float, str))):
                raise ConfigError(f"selfplay: learner option {key!r}={value!r}: keys are names, "
                                  "values JSON scalars")
        object.__setattr__(self, "learner_options", options)

    def to_json(self) -> dict[str, Any]:
        return {"seed": self.seed, "steps_per_generation": self.steps_per_generation,
                "builtins": list(self.builtins), "pfsp": self.pfsp,
                "pfsp_exponent": self.pfsp_exponent, "latest_share": self.latest_share,
                "training": self.training.to_json(), "rating": self.rating.to_json(),
                "learner": self.learner, "learner_options": dict(self.learner_options)}

    @classmethod
    def from_json(cls, data: Mapping[str, Any]) -> LeagueConfig:
        values = dict(data)
        if "training" in values:
            values["training"] = TrainingSetup.from_json(values["training"])
        if "rating" in values:
            values["rating"] = build_config(RatingSetup, values["rating"], section="rating")
        if "builtins" in values:
            values["builtins"] = tuple(values["builtins"])
        return build_config(cls, values, section="selfplay")
