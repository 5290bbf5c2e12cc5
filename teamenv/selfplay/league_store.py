"""The league's own SQLite file (``league.sqlite``): its configuration, what each generation
trained against, and the ratings after each generation.

A generation is written twice, each time in one transaction: when it is trained (its snapshot
file is in place, its learner checkpoint saved) and when it is rated (its gauntlet complete,
the ratings of every team stored). A kill between the two leaves a generation that is trained
and not rated, which a resumed run rates without training it again. The matches themselves
are in ``ratings.sqlite`` (``teamenv.tournament``'s store).
"""

from __future__ import annotations

import json
import sqlite3
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from teamenv.errors import ConfigError
from teamenv.tournament.ratings import Rating, Ratings
from teamenv.tournament.store import immediate_transaction

LEAGUE_DB = "league.sqlite"
FORMAT = "teamenv-selfplay-v1"

_SCHEMA = """
CREATE TABLE IF NOT EXISTS meta (key TEXT PRIMARY KEY, value TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS generations (
    generation INTEGER PRIMARY KEY,
    snapshot TEXT NOT NULL,              -- gen-0003
    digest TEXT NOT NULL,                -- policy_digest of the snapshot file
    opponents TEXT NOT NULL,             -- JSON [{team, p_win, probability}] (empty for 0)
    training TEXT NOT NULL,              -- JSON: steps and per-opponent episode outcomes
    train_wall_s REAL NOT NULL,
    rated INTEGER NOT NULL DEFAULT 0,
    rate_wall_s REAL,
    n_games INTEGER,                     -- matches behind the ratings after this generation
    n_bootstrap INTEGER,
    confidence REAL
);
CREATE TABLE IF NOT EXISTS ratings (     -- every team's ratings after each generation
    generation INTEGER NOT NULL REFERENCES generations(generation),
    method TEXT NOT NULL,                -- bradley_terry | elo
    rank INTEGER NOT NULL,               -- order of Ratings (best first by Bradley-Terry)
    team TEXT NOT NULL,
    rating REAL NOT NULL,
    low REAL NOT NULL,
    high REAL NOT NULL,
    PRIMARY KEY (generation, method, team)
);
"""


@dataclass(frozen=True)
class GenerationRecord:
    """One stored generation (``opponents`` and ``training`` as stored JSON)."""

    generation: int
    snapshot: str
    digest: str
    opponents: list[dict[str, Any]]
    training: dict[str, Any]
    train_wall_s: float
    rated: bool
    rate_wall_s: float | None

    def comparable(self) -> dict[str, Any]:
        """What a deterministic rerun must reproduce (no wall times)."""
        return {"generation": self.generation, "snapshot": self.snapshot,
                "digest": self.digest, "opponents": self.opponents,
                "training": self.training, "rated": self.rated}


class LeagueStore:
    """``league.sqlite`` of one run directory."""

    def __init__(self, path: str | Path) -> None:
        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        try:
            self.conn = sqlite3.connect(str(self.path), timeout=30.0, isolation_level=None)
            self.conn.execute("PRAGMA journal_mode=WAL")
            self.conn.execute("PRAGMA synchronous=FULL")
            self.conn.executescript(_SCHEMA)
        except sqlite3.DatabaseError as exc:
            raise ConfigError(f"league database {str(self.path)!r}: {exc}") from exc
        stored = self._meta("format")
        if stored is not None and stored != FORMAT:
            raise ConfigError(f"league database {str(self.path)!r}: format {stored!r}, this "
                              f"teamenv reads {FORMAT!r}")

    def close(self) -> None:
        self.conn.close()

    def __enter__(self) -> LeagueStore:
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()

    # -- configuration -----------------------------------------------------------------------
    def _meta(self, key: str) -> str | None:
        row = self.conn.execute("SELECT value FROM meta WHERE key=?", (key,)).fetchone()
        return None if row is None else str(row[0])

    def config(self) -> dict[str, Any] | None:
        """The stored configuration (JSON), None for a new file."""
        text = self._meta("config")
        return None if text is None else json.loads(text)

    def set_config(self, config: Mapping[str, Any]) -> None:
        with immediate_transaction(self.conn):
            self.conn.execute("INSERT INTO meta VALUES ('format', ?)", (FORMAT,))
            self.conn.execute("INSERT INTO meta VALUES ('config', ?)",
                              (json.dumps(config, sort_keys=True),))

    # -- generations -------------------------------------------------------------------------
    def generations(self) -> list[GenerationRecord]:
        rows = self.conn.execute(
            "SELECT generation, snapshot, digest, opponents, training, train_wall_s, rated, "
            "rate_wall_s FROM generations ORDER BY generation")
        return [GenerationRecord(int(g), s, d, json.loads(o), json.loads(t), float(w),
                                 bool(r), None if rw is None else float(rw))
                for g, s, d, o, t, w, r, rw in rows]

    def generation(self, generation: int) -> GenerationRecord | None:
        return next((r for r in self.generations() if r.generation == generation), None)

    def record_trained(self, generation: int, snapshot: str, digest: str,
                       opponents: list[dict[str, Any]], training: dict[str, Any],
                       train_wall_s: float) -> None:
        """Generation ``generation`` is trained (replaces an earlier unrated record of it)."""
        with immediate_transaction(self.conn):
            self.conn.execute("DELETE FROM ratings WHERE generation=?", (generation,))
            self.conn.execute("DELETE FROM generations WHERE generation=?", (generation,))
            self.conn.execute(
                "INSERT INTO generations (generation, snapshot, digest, opponents, training, "
                "train_wall_s) VALUES (?, ?, ?, ?, ?, ?)",
                (generation, snapshot, digest, json.dumps(opponents, sort_keys=True),
                 json.dumps(training, sort_keys=True), float(train_wall_s)))

    def record_rated(self, generation: int, ratings: Ratings, rate_wall_s: float) -> None:
        """Generation ``generation`` is rated: every team's ratings after it."""
        with immediate_transaction(self.conn):
            updated = self.conn.execute(
                "UPDATE generations SET rated=1, rate_wall_s=?, n_games=?, n_bootstrap=?, "
                "confidence=? WHERE generation=?",
                (float(rate_wall_s), ratings.n_games, ratings.n_bootstrap, ratings.confidence,
                 generation)).rowcount
            if updated != 1:
                raise ConfigError(f"league database: generation {generation} was never "
                                  "recorded as trained")
            self.conn.execute("DELETE FROM ratings WHERE generation=?", (generation,))
            for method, table in (("bradley_terry", ratings.bradley_terry),
                                  ("elo", ratings.elo)):
                for rank, (team, r) in enumerate(table.items()):
                    self.conn.execute("INSERT INTO ratings VALUES (?, ?, ?, ?, ?, ?, ?)",
                                      (generation, method, rank, team, r.rating, r.low, r.high))

    def ratings(self, generation: int) -> Ratings | None:
        """The ratings stored after ``generation`` (None when it is not rated)."""
        row = self.conn.execute(
            "SELECT n_games, n_bootstrap, confidence FROM generations WHERE generation=? AND "
            "rated=1", (generation,)).fetchone()
        if row is None:
            return None
        tables: dict[str, dict[str, Rating]] = {"bradley_terry": {}, "elo": {}}
        for method, team, rating, low, high in self.conn.execute(
                "SELECT method, team, rating, low, high FROM ratings WHERE generation=? "
                "ORDER BY method, rank", (generation,)):
            tables[method][team] = Rating(team, rating, low, high)
        return Ratings(elo=tables["elo"], bradley_terry=tables["bradley_terry"],
                       n_games=int(row[0]), n_bootstrap=int(row[1]), confidence=float(row[2]))

    def last_rated(self) -> int:
        """The last generation rated with every one before it rated too (-1: none)."""
        last = -1
        for record in self.generations():
            if record.generation != last + 1 or not record.rated:
                break
            last = record.generation
        return last
