"""An optimization run's checkpoints, in the same SQLite file as its tournaments' matches.

Tables (created on first use, beside the tournament store's):
  optimize_runs          one row per run: its name and JSON definition (what resume compares);
  optimize_generations   one row per generation, written *when it is asked*: the candidates
                         (unit vectors) and, once every candidate is scored, the scores and
                         the distribution after ``tell``;
  optimize_match_metrics the finer fitness metric of each stored match (by match id, metric).

Every write is one transaction (WAL, ``synchronous=FULL``), so a killed run finds either the
generation it was playing (its stored matches are kept by the tournament store) or the last
finished one, and continues exactly where it stopped.
"""

from __future__ import annotations

import json
import sqlite3
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from teamenv.errors import TeamEnvError

_SCHEMA = """
CREATE TABLE IF NOT EXISTS optimize_runs (
    id INTEGER PRIMARY KEY,
    name TEXT NOT NULL UNIQUE,
    definition TEXT NOT NULL,
    created_utc TEXT NOT NULL
);
CREATE TABLE IF NOT EXISTS optimize_generations (
    run_id INTEGER NOT NULL REFERENCES optimize_runs(id),
    generation INTEGER NOT NULL,
    candidates TEXT NOT NULL,
    asked_utc TEXT NOT NULL,
    scores TEXT,
    mean TEXT,
    sigma REAL,
    wall_s REAL,
    told_utc TEXT,
    PRIMARY KEY (run_id, generation)
);
CREATE TABLE IF NOT EXISTS optimize_match_metrics (
    match_id INTEGER NOT NULL,
    metric TEXT NOT NULL,
    value REAL NOT NULL,
    PRIMARY KEY (match_id, metric)
);
"""


class OptimizeError(TeamEnvError):
    """An optimization run cannot go on as asked (definition changed, matches failed...)."""


@dataclass(frozen=True)
class Generation:
    """One stored generation: candidates (unit vectors), their scores (None until told) and
    the search distribution after ``tell`` (``mean`` unit vector, step size ``sigma``)."""

    generation: int
    candidates: list[list[float]]
    scores: list[dict[str, Any]] | None
    mean: list[float] | None
    sigma: float | None
    wall_s: float | None

    @property
    def told(self) -> bool:
        return self.scores is not None


def _utc() -> str:
    return time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())


class CheckpointStore:
    """Runs and generations of ``teamenv optimize`` in the SQLite file ``path``."""

    def __init__(self, path: str | Path) -> None:
        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self.conn = sqlite3.connect(str(self.path), timeout=60.0, isolation_level=None)
        self.conn.execute("PRAGMA journal_mode=WAL")
        self.conn.execute("PRAGMA synchronous=FULL")
        self.conn.executescript(_SCHEMA)

    def close(self) -> None:
        self.conn.close()

    def __enter__(self) -> CheckpointStore:
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()

    def run_names(self) -> list[str]:
        return [r[0] for r in self.conn.execute("SELECT name FROM optimize_runs ORDER BY id")]

    def find_run(self, name: str) -> tuple[int, dict[str, Any]] | None:
        row = self.conn.execute("SELECT id, definition FROM optimize_runs WHERE name = ?",
                                (name,)).fetchone()
        return None if row is None else (row[0], json.loads(row[1]))

    def create_run(self, name: str, definition: dict[str, Any]) -> int:
        cur = self.conn.execute(
            "INSERT INTO optimize_runs (name, definition, created_utc) VALUES (?, ?, ?)",
            (name, json.dumps(definition, sort_keys=True), _utc()))
        return int(cur.lastrowid)

    def generations(self, run_id: int) -> list[Generation]:
        rows = self.conn.execute(
            "SELECT generation, candidates, scores, mean, sigma, wall_s FROM "
            "optimize_generations WHERE run_id = ? ORDER BY generation", (run_id,)).fetchall()
        return [Generation(g, json.loads(c), json.loads(s) if s else None,
                           json.loads(m) if m else None, sigma, wall)
                for g, c, s, m, sigma, wall in rows]

    def save_asked(self, run_id: int, generation: int, candidates: list[list[float]]) -> None:
        """Checkpoint a generation as soon as it is asked: its candidates."""
        self.conn.execute(
            "INSERT INTO optimize_generations (run_id, generation, candidates, asked_utc) "
            "VALUES (?, ?, ?, ?)", (run_id, generation, json.dumps(candidates), _utc()))

    def save_told(self, run_id: int, generation: int, scores: list[dict[str, Any]],
                  mean: list[float], sigma: float, wall_s: float) -> None:
        """Store a generation's scores and the distribution after ``tell``."""
        self.conn.execute(
            "UPDATE optimize_generations SET scores = ?, mean = ?, sigma = ?, wall_s = ?, "
            "told_utc = ? WHERE run_id = ? AND generation = ?",
            (json.dumps(scores), json.dumps(mean), float(sigma), float(wall_s), _utc(), run_id,
             generation))

    def match_metrics(self, metric: str, match_ids: list[int]) -> dict[int, float]:
        """Stored value of ``metric`` for each of ``match_ids`` that has one."""
        out: dict[int, float] = {}
        for start in range(0, len(match_ids), 500):
            chunk = match_ids[start:start + 500]
            marks = ",".join("?" * len(chunk))
            out.update(self.conn.execute(
                f"SELECT match_id, value FROM optimize_match_metrics WHERE metric = ? AND "
                f"match_id IN ({marks})", [metric, *chunk]).fetchall())
        return out

    def save_match_metric(self, match_id: int, metric: str, value: float) -> None:
        self.conn.execute("INSERT OR REPLACE INTO optimize_match_metrics (match_id, metric, "
                          "value) VALUES (?, ?, ?)", (match_id, metric, float(value)))
