"""SQLite results store: tournament definitions, every match with its goals, resume queries.

One file, standard-library ``sqlite3``, WAL journal, ``synchronous=FULL``. Only the parent
process writes; each finished match (row + goals) is one transaction, so a match is either
stored whole or not at all, whatever kills the process. ``UNIQUE(tournament_id, pairing, seed,
swapped)`` makes a second write of the same match a no-op: a resumed run can never count a
match twice.
"""

from __future__ import annotations

import json
import sqlite3
import time
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from teamenv.match import Goal, MatchResult
from teamenv.tournament.errors import StoreError
from teamenv.tournament.schedule import MatchTask, Tournament

SCHEMA_VERSION = 1

_SCHEMA = """
CREATE TABLE IF NOT EXISTS meta (key TEXT PRIMARY KEY, value TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS tournaments (
    id INTEGER PRIMARY KEY,
    name TEXT NOT NULL UNIQUE,
    definition TEXT NOT NULL,            -- Tournament.to_json()
    definition_hash TEXT NOT NULL,
    n_matches INTEGER NOT NULL,          -- scheduled matches
    created_utc TEXT NOT NULL
);
CREATE TABLE IF NOT EXISTS teams (
    tournament_id INTEGER NOT NULL REFERENCES tournaments(id),
    label TEXT NOT NULL,                 -- canonical spec, e.g. chaser:all_chase=true
    name TEXT NOT NULL,                  -- registered name or module:Class
    config TEXT NOT NULL,                -- JSON overrides
    version TEXT NOT NULL,               -- team version when the tournament was created
    PRIMARY KEY (tournament_id, label)
);
CREATE TABLE IF NOT EXISTS matches (
    id INTEGER PRIMARY KEY,
    tournament_id INTEGER NOT NULL REFERENCES tournaments(id),
    idx INTEGER NOT NULL,                -- position in schedule order
    round INTEGER NOT NULL,
    pairing TEXT NOT NULL,               -- "A vs B" in schedule order
    seed INTEGER NOT NULL,
    swapped INTEGER NOT NULL,            -- 1 when B played on the left
    match_key TEXT NOT NULL,
    left_team TEXT NOT NULL,
    right_team TEXT NOT NULL,
    left_score INTEGER NOT NULL,         -- goals actually scored
    right_score INTEGER NOT NULL,
    left_official INTEGER NOT NULL,      -- the score that counts (forfeits: 0-3)
    right_official INTEGER NOT NULL,
    forfeit_side TEXT,
    forfeit_reason TEXT,                 -- raised / invalid_action / too_slow / stalled
    forfeit_detail TEXT,
    forfeit_time_s REAL,
    cycles INTEGER NOT NULL,
    wall_s REAL NOT NULL,                -- seconds of wall time the match took in its worker
    left_version TEXT NOT NULL,
    right_version TEXT NOT NULL,
    left_team_time_s REAL NOT NULL,      -- seconds spent in each team's act()
    right_team_time_s REAL NOT NULL,
    replay_path TEXT,
    finished_utc TEXT NOT NULL,
    UNIQUE (tournament_id, pairing, seed, swapped),
    UNIQUE (tournament_id, idx)
);
CREATE TABLE IF NOT EXISTS goals (
    match_id INTEGER NOT NULL REFERENCES matches(id),
    n INTEGER NOT NULL,
    time_s REAL NOT NULL,                -- game time of the goal (s)
    side TEXT NOT NULL,                  -- side credited
    scorer_side TEXT,
    scorer_unum INTEGER,
    PRIMARY KEY (match_id, n)
);
CREATE TABLE IF NOT EXISTS team_stats (    -- per-team match statistics (teamenv.analytics);
    match_id INTEGER NOT NULL REFERENCES matches(id),  -- added after schema 1 was released:
    side TEXT NOT NULL,                    -- IF NOT EXISTS creates it in older databases
    team TEXT NOT NULL,
    goals INTEGER NOT NULL,
    xg REAL NOT NULL,
    shots INTEGER NOT NULL,
    possession_pct REAL NOT NULL,
    stats TEXT NOT NULL,                   -- TeamStats as JSON (MatchStats.to_json()'s team)
    PRIMARY KEY (match_id, side)
);
CREATE TABLE IF NOT EXISTS failures (      -- matches that could not be played (worker died);
    id INTEGER PRIMARY KEY,                -- not results: resume plays them again
    tournament_id INTEGER NOT NULL REFERENCES tournaments(id),
    idx INTEGER NOT NULL,
    error TEXT NOT NULL,
    time_utc TEXT NOT NULL
);
"""

_MATCH_COLUMNS = (
    "id", "idx", "round", "pairing", "seed", "swapped", "match_key", "left_team", "right_team",
    "left_score", "right_score", "left_official", "right_official", "forfeit_side",
    "forfeit_reason", "forfeit_detail", "forfeit_time_s", "cycles", "wall_s", "left_version",
    "right_version", "left_team_time_s", "right_team_time_s", "replay_path", "finished_utc",
)



@contextmanager
def immediate_transaction(conn: sqlite3.Connection) -> Iterator[sqlite3.Connection]:
    """``BEGIN IMMEDIATE`` (the write lock up front, so concurrent writers wait instead of
    failing mid-transaction), then ``COMMIT``, or ``ROLLBACK`` when the block raises."""
    conn.execute("BEGIN IMMEDIATE")
    try:
        yield conn
    except BaseException:
        conn.execute("ROLLBACK")
        raise
    conn.execute("COMMIT")

@dataclass(frozen=True)
class MatchRecord:
    """One stored match (scores in goals; times in seconds; ``goals`` in order)."""

    id: int
    idx: int
    round: int
    pairing: str
    seed: int
    swapped: bool
    match_key: str
    left_team: str
    right_team: str
    left_score: int
    right_score: int
    left_official: int
    right_official: int
    forfeit_side: str | None
    forfeit_reason: str | None
    forfeit_detail: str | None
    forfeit_time_s: float | None
    cycles: int
    wall_s: float
    left_version: str
    right_version: str
    left_team_time_s: float
    right_team_time_s: float
    replay_path: str | None
    finished_utc: str
    goals: tuple[Goal, ...] = ()

    def comparable(self) -> dict[str, Any]:
        """The fields that a deterministic replay of the match must reproduce (no timings,
        ids or paths): for comparing two runs of the same tournament."""
        skip = {"id", "wall_s", "left_team_time_s", "right_team_time_s", "finished_utc",
                "replay_path", "forfeit_detail"}
        out = {k: getattr(self, k) for k in _MATCH_COLUMNS if k not in skip}
        out["goals"] = [(round(g.time_s, 6), g.side, g.scorer_side, g.scorer_unum)
                        for g in self.goals]
        return out


def _utc() -> str:
    return time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())


class ResultStore:
    """The results database of one or more tournaments (a single SQLite file).

    ``synchronous``: "FULL" (default; a commit survives power loss) or "NORMAL" (survives any
    process crash, faster on slow disks).
    """

    def __init__(self, path: str | Path, synchronous: str = "FULL") -> None:
        if synchronous not in ("FULL", "NORMAL", "OFF"):
            raise StoreError(f"store synchronous: {synchronous!r}; choose FULL, NORMAL or OFF")
        self.path = Path(path)
        if self.path.parent and not self.path.parent.exists():
            self.path.parent.mkdir(parents=True, exist_ok=True)
        try:
            self.conn = sqlite3.connect(str(self.path), timeout=30.0, isolation_level=None)
            self.conn.execute("PRAGMA journal_mode=WAL")
            self.conn.execute(f"PRAGMA synchronous={synchronous}")
            self.conn.execute("PRAGMA foreign_keys=ON")
            self.conn.executescript(_SCHEMA)  # idempotent (IF NOT EXISTS)
            with immediate_transaction(self.conn):
                row = self.conn.execute("SELECT value FROM meta WHERE key='schema'").fetchone()
                if row is None:
                    self.conn.execute("INSERT INTO meta VALUES ('schema', ?)",
                                      (str(SCHEMA_VERSION),))
                elif int(row[0]) != SCHEMA_VERSION:
                    raise StoreError(f"database {str(self.path)!r}: schema version {row[0]}, "
                                     f"this teamenv reads version {SCHEMA_VERSION}")
        except sqlite3.DatabaseError as exc:
            raise StoreError(f"database {str(self.path)!r}: {exc}") from exc

    # -- lifecycle -------------------------------------------------------------------------
    def close(self) -> None:
        self.conn.close()

    def __enter__(self) -> ResultStore:
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()

    # -- tournaments -----------------------------------------------------------------------
    def tournament_names(self) -> list[str]:
        return [r[0] for r in self.conn.execute("SELECT name FROM tournaments ORDER BY id")]

    def find_tournament(self, name: str | None) -> tuple[int, Tournament] | None:
        """The stored (id, definition) of ``name`` (or of the only tournament when None)."""
        if name is None:
            names = self.tournament_names()
            if not names:
                return None
            if len(names) != 1:
                raise StoreError(f"database {str(self.path)!r} holds {len(names)} tournaments "
                                 f"{names}; name one")
            name = names[0]
        row = self.conn.execute("SELECT id, definition FROM tournaments WHERE name=?",
                                (name,)).fetchone()
        if row is None:
            return None
        return int(row[0]), Tournament.from_json(json.loads(row[1]))

    def get_tournament(self, name: str | None) -> tuple[int, Tournament]:
        found = self.find_tournament(name)
        if found is None:
            raise StoreError(f"database {str(self.path)!r}: no tournament {name!r}; it holds "
                             f"{self.tournament_names()}")
        return found

    def create_tournament(self, tournament: Tournament, versions: dict[str, str]) -> int:
        """Store a new tournament definition and its teams' versions; return its id."""
        with immediate_transaction(self.conn) as conn:
            try:
                cur = conn.execute(
                    "INSERT INTO tournaments (name, definition, definition_hash, n_matches, "
                    "created_utc) VALUES (?, ?, ?, ?, ?)",
                    (tournament.name, json.dumps(tournament.to_json(), sort_keys=True),
                     tournament.definition_hash(), len(tournament.schedule()), _utc()))
            except sqlite3.IntegrityError:
                raise StoreError(f"database {str(self.path)!r}: tournament {tournament.name!r} "
                                 "already exists; resume it (--resume) or choose another "
                                 "name") from None
            tid = int(cur.lastrowid)
            for spec in tournament.all_teams:
                conn.execute("INSERT INTO teams VALUES (?, ?, ?, ?, ?)",
                             (tid, spec.label, spec.name, json.dumps(spec.config_dict),
                              versions.get(spec.label, "unknown")))
        return tid

    def team_versions(self, tournament_id: int) -> dict[str, str]:
        rows = self.conn.execute("SELECT label, version FROM teams WHERE tournament_id=?",
                                 (tournament_id,))
        return {label: version for label, version in rows}

    # -- matches ---------------------------------------------------------------------------
    def completed_indices(self, tournament_id: int) -> set[int]:
        """Schedule indices of the matches already stored (what a resume skips)."""
        rows = self.conn.execute("SELECT idx FROM matches WHERE tournament_id=?", (tournament_id,))
        return {int(r[0]) for r in rows}

    def count_matches(self, tournament_id: int) -> int:
        return int(self.conn.execute("SELECT COUNT(*) FROM matches WHERE tournament_id=?",
                                     (tournament_id,)).fetchone()[0])

    def record_match(self, tournament_id: int, task: MatchTask, result: MatchResult) -> bool:
        """Write one finished match and its goals in one transaction.

        Returns False (and writes nothing) when the match is already stored.
        """
        if self._has_match(tournament_id, task):
            return False
        try:
            return self._insert_match(tournament_id, task, result)
        except sqlite3.IntegrityError as exc:
            if self._has_match(tournament_id, task):  # another writer stored it meanwhile
                return False
            raise StoreError(f"database {str(self.path)!r}: cannot store match "
                             f"#{task.index} ({task.pairing}, seed {task.seed}): {exc}") from exc

    def _insert_match(self, tournament_id: int, task: MatchTask, result: MatchResult) -> bool:
        fo = result.forfeit
        official = result.official_score
        with immediate_transaction(self.conn) as conn:
            cur = conn.execute(
                "INSERT INTO matches (tournament_id, idx, round, pairing, seed, "
                "swapped, match_key, left_team, right_team, left_score, right_score, "
                "left_official, right_official, forfeit_side, forfeit_reason, forfeit_detail, "
                "forfeit_time_s, cycles, wall_s, left_version, right_version, left_team_time_s, "
                "right_team_time_s, replay_path, finished_utc) "
                "VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)",
                (tournament_id, task.index, task.round, task.pairing, task.seed,
                 int(task.swapped), task.key, task.left.label, task.right.label,
                 int(result.score[0]), int(result.score[1]), int(official[0]), int(official[1]),
                 fo.side if fo else None, fo.reason if fo else None, fo.detail if fo else None,
                 fo.time_s if fo else None, int(result.cycles), float(result.wall_s),
                 result.team_versions[0], result.team_versions[1],
                 float(result.team_time_s[0]), float(result.team_time_s[1]), task.replay_path,
                 _utc()))
            match_id = cur.lastrowid
            conn.executemany(
                "INSERT INTO goals VALUES (?, ?, ?, ?, ?, ?)",
                [(match_id, n, float(g.time_s), g.side, g.scorer_side, g.scorer_unum)
                 for n, g in enumerate(result.goals)])
        return True

    def _has_match(self, tournament_id: int, task: MatchTask) -> bool:
        row = self.conn.execute(
            "SELECT 1 FROM matches WHERE tournament_id=? AND ((pairing=? AND seed=? AND "
            "swapped=?) OR idx=?)",
            (tournament_id, task.pairing, task.seed, int(task.swapped), task.index)).fetchone()
        return row is not None

    def record_failure(self, tournament_id: int, task: MatchTask, error: str) -> None:
        """Note a match that could not be played (it is not a result; resume retries it)."""
        with immediate_transaction(self.conn) as conn:
            conn.execute("INSERT INTO failures (tournament_id, idx, error, time_utc) "
                         "VALUES (?, ?, ?, ?)", (tournament_id, task.index, error, _utc()))

    def record_team_stats(self, tournament_id: int, index: int, stats: Any) -> bool:
        """Store both sides' ``MatchStats`` of the stored match at schedule ``index``; False
        when that match is not stored or its statistics already are."""
        row = self.conn.execute("SELECT id FROM matches WHERE tournament_id=? AND idx=?",
                                (tournament_id, index)).fetchone()
        if row is None:
            return False
        teams = stats.to_json()["teams"]
        with immediate_transaction(self.conn) as conn:
            cur = conn.executemany(
                "INSERT OR IGNORE INTO team_stats VALUES (?, ?, ?, ?, ?, ?, ?, ?)",
                [(int(row[0]), side, t["team"], int(t["goals"]), float(t["xg"]),
                  int(t["shots"]), float(t["possession_pct"]), json.dumps(t))
                 for side, t in teams.items()])
        return cur.rowcount > 0

    def team_stats(self, tournament_id: int) -> dict[int, dict[str, dict[str, Any]]]:
        """Stored per-team statistics by match id, then side (TeamStats JSON)."""
        rows = self.conn.execute(
            "SELECT s.match_id, s.side, s.stats FROM team_stats s JOIN matches m ON "
            "m.id=s.match_id WHERE m.tournament_id=? ORDER BY m.idx", (tournament_id,))
        out: dict[int, dict[str, dict[str, Any]]] = {}
        for mid, side, text in rows:
            out.setdefault(int(mid), {})[side] = json.loads(text)
        return out

    def failures(self, tournament_id: int) -> list[tuple[int, str]]:
        """(schedule index, error) of failures whose match is still missing."""
        rows = self.conn.execute(
            "SELECT f.idx, f.error FROM failures f WHERE f.tournament_id=? AND NOT EXISTS "
            "(SELECT 1 FROM matches m WHERE m.tournament_id=f.tournament_id AND m.idx=f.idx) "
            "ORDER BY f.id", (tournament_id,))
        return [(int(i), str(e)) for i, e in rows]

    def matches(self, tournament_id: int) -> list[MatchRecord]:
        """Every stored match of a tournament in schedule order, with its goals."""
        return list(self._iter_matches("m.tournament_id=?", (tournament_id,)))

    def match(self, match_id: int) -> MatchRecord:
        found = list(self._iter_matches("m.id=?", (match_id,)))
        if not found:
            raise StoreError(f"database {str(self.path)!r}: no match with id {match_id}")
        return found[0]

    def match_tournament(self, match_id: int) -> Tournament:
        row = self.conn.execute("SELECT t.definition FROM matches m JOIN tournaments t ON "
                                "t.id=m.tournament_id WHERE m.id=?", (match_id,)).fetchone()
        if row is None:
            raise StoreError(f"database {str(self.path)!r}: no match with id {match_id}")
        return Tournament.from_json(json.loads(row[0]))

    def _iter_matches(self, where: str, params: tuple) -> Iterator[MatchRecord]:
        cols = ", ".join(f"m.{c}" for c in _MATCH_COLUMNS)
        rows = self.conn.execute(f"SELECT {cols} FROM matches m WHERE {where} ORDER BY m.idx",
                                 params).fetchall()
        goals: dict[int, list[Goal]] = {}
        for mid, t, side, sside, unum in self.conn.execute(
                f"SELECT g.match_id, g.time_s, g.side, g.scorer_side, g.scorer_unum FROM goals g "
                f"JOIN matches m ON m.id=g.match_id WHERE {where} ORDER BY g.match_id, g.n",
                params):
            goals.setdefault(mid, []).append(Goal(t, side, sside, unum))
        for r in rows:
            values = dict(zip(_MATCH_COLUMNS, r, strict=True))
            values["swapped"] = bool(values["swapped"])
            yield MatchRecord(**values, goals=tuple(goals.get(values["id"], ())))
