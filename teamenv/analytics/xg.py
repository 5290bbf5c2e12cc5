"""Expected goals: the probability that a kick on frame scores, from where it was taken.

The model is a logistic regression

    P(goal) = 1 / (1 + exp(-(b0 + b1 * distance + b2 * angle + b3 * blockers)))

over ``distance`` (metres from the kick spot to the centre of the goal), ``angle`` (radians,
the opening angle between the posts seen from the kick spot) and ``blockers`` (opponents
inside the triangle spanned by the kick spot and the two posts when the kick was taken). It
rates every kick on frame (``MatchEvents.attempts``; far ones get a probability near 0).
The shipped coefficients (``xg_model.json`` beside this file) were fitted with scikit-learn's
``LogisticRegression`` on kicks from seeded simulated matches; the file says how
(``benchmarks/xg_fit.py`` rebuilds it).
"""

from __future__ import annotations

import json
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from paramkit.checks import check_fields, invalid
from teamenv.errors import ConfigError

FEATURES = ("distance_m", "angle_rad", "blockers")
MODEL_PATH = Path(__file__).with_name("xg_model.json")


@dataclass(frozen=True)
class XGModel:
    """Logistic expected-goals model: ``intercept`` and one coefficient per ``FEATURES``."""

    intercept: float
    coefficients: tuple[float, ...]
    fitted: dict[str, Any] = field(default_factory=dict)  # how the coefficients were made

    def __post_init__(self) -> None:
        check_fields(self, ConfigError)
        if len(self.coefficients) != len(FEATURES):
            raise invalid(self, "coefficients", f"one per feature {list(FEATURES)}", ConfigError)

    def probability(self, features: np.ndarray) -> np.ndarray:
        """P(goal) for each row of ``features`` (k, 3): distance m, angle rad, blockers."""
        x = np.asarray(features, dtype=float).reshape(-1, len(FEATURES))
        z = self.intercept + x @ np.asarray(self.coefficients)
        return 1.0 / (1.0 + np.exp(-z))

    def to_json(self) -> dict[str, Any]:
        return {"model": "logistic", "features": list(FEATURES), "intercept": self.intercept,
                "coefficients": dict(zip(FEATURES, self.coefficients, strict=True)),
                "fitted": self.fitted}

    @classmethod
    def from_json(cls, data: dict[str, Any], source: str = "xG model") -> XGModel:
        try:
            if data.get("model") != "logistic" or list(data["features"]) != list(FEATURES):
                raise ConfigError(f"{source}: expected a logistic model over {list(FEATURES)}, "
                                  f"got model {data.get('model')!r} over "
                                  f"{data.get('features')!r}")
            coefs = tuple(float(data["coefficients"][f]) for f in FEATURES)
            return cls(float(data["intercept"]), coefs, dict(data.get("fitted", {})))
        except (KeyError, TypeError, ValueError, AttributeError) as exc:
            raise ConfigError(f"{source}: malformed xG model ({type(exc).__name__}: {exc})") \
                from exc

    @classmethod
    def load(cls, path: str | Path | None = None) -> XGModel:
        """The model in ``path`` (default: the shipped ``xg_model.json``)."""
        path = Path(path) if path is not None else MODEL_PATH
        try:
            data = json.loads(path.read_text())
        except (OSError, json.JSONDecodeError) as exc:
            raise ConfigError(f"xG model {str(path)!r}: cannot read it ({exc})") from exc
        return cls.from_json(data, f"xG model {str(path)!r}")

    def save(self, path: str | Path) -> Path:
        path = Path(path)
        path.write_text(json.dumps(self.to_json(), indent=2) + "\n")
        return path


def kick_features(kicks: Iterable[Any]) -> np.ndarray:
    """(k, 3) features of ``Kick``s: distance to the goal's centre, opening angle, blockers."""
    rows = [(k.goal_distance, k.goal_angle, k.blockers) for k in kicks]
    return np.asarray(rows, dtype=float).reshape(-1, len(FEATURES))


def fit_xg(features: np.ndarray, scored: Sequence[bool], *, c: float = 1.0,
           fitted: dict[str, Any] | None = None) -> XGModel:
    """Fit the model with scikit-learn's L2-regularised ``LogisticRegression`` (``C=c``,
    lbfgs) on ``features`` (k, 3) and whether each attempt scored."""
    from sklearn.linear_model import LogisticRegression

    x = np.asarray(features, dtype=float).reshape(-1, len(FEATURES))
    y = np.asarray(scored, dtype=bool)
    if len(x) != len(y):
        raise ConfigError(f"fit_xg: {len(x)} feature rows but {len(y)} outcomes")
    if y.all() or not y.any():
        raise ConfigError(f"fit_xg: need attempts that scored and that did not "
                          f"({int(y.sum())} of {len(y)} scored)")
    model = LogisticRegression(C=c, solver="lbfgs", max_iter=1000).fit(x, y)
    info = dict(fitted or {})
    info.update(attempts=int(len(y)), goals=int(y.sum()), C=c,
                library=f"scikit-learn LogisticRegression (lbfgs, L2, C={c})")
    return XGModel(float(model.intercept_[0]), tuple(float(v) for v in model.coef_[0]), info)
