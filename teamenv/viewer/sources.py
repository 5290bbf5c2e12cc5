"""What the viewer shows: one replay file, or the matches of a tournament database.

A source lists its matches (``matches()``) and gives the replay of one (``replay(match_id)``).
Replays are loaded once and kept (a full 11 v 11 replay is ~10 MB in memory); a tournament
match whose replay file is gone is played again from its seed (``match_replay``), which checks
the score against the database.
"""

from __future__ import annotations

import sqlite3
import threading
from collections import OrderedDict
from pathlib import Path
from typing import Any

from teamenv.errors import TeamEnvError
from teamenv.replay import Replay, load_replay
from teamenv.viewer.errors import ViewerError

_SQLITE_MAGIC = b"SQLite format 3\x00"
#: Replays kept in memory at once (the least recently opened is dropped first).
CACHED_REPLAYS = 4


def read_replay(path: str | Path) -> Replay:
    """Load a replay file and check that its arrays agree with each other; a file that is
    missing, truncated, not a replay or inconsistent raises ViewerError (status 422)."""
    try:
        replay = load_replay(path)
    except TeamEnvError as exc:
        raise ViewerError(str(exc)) from exc
    except Exception as exc:  # noqa: BLE001 - any reader failure of a damaged file
        raise ViewerError(f"replay {str(path)!r}: not a readable teamenv replay file "
                          f"({type(exc).__name__}: {exc})") from exc
    _check_shapes(replay, path)
    return replay


def _check_shapes(replay: Replay, path: str | Path) -> None:
    cycles = len(replay.time_s)
    expected = {"ball": (cycles, 4), "play_mode": (cycles,), "score": (cycles, 2)}
    for name, shape in expected.items():
        if getattr(replay, name).shape != shape:
            raise ViewerError(f"replay {str(path)!r}: field {name!r} has shape "
                              f"{getattr(replay, name).shape}, expected {shape} "
                              f"({cycles} cycles)")
    players = replay.players
    if players.ndim != 3 or players.shape[0] != cycles or players.shape[2] != 3 or \
            players.shape[1] % 2 or players.shape[1] == 0:
        raise ViewerError(f"replay {str(path)!r}: field 'players' has shape {players.shape}, "
                          f"expected ({cycles}, 2N, 3)")
    if cycles == 0:
        raise ViewerError(f"replay {str(path)!r}: holds no cycles")
    if "field" not in replay.metadata:
        raise ViewerError(f"replay {str(path)!r}: metadata has no 'field'")


class ViewerSource:
    """Base of the two sources: a cache of loaded replays by match id."""

    kind = "none"

    def __init__(self, path: Path) -> None:
        self.path = path
        self._cache: OrderedDict[int, Replay] = OrderedDict()
        self._lock = threading.Lock()

    def matches(self) -> list[dict[str, Any]]:
        """Every match that can be opened: ``id``, ``label`` and what is known of it."""
        raise NotImplementedError

    def default_match(self) -> int | None:
        """The match the page opens first (None: let the user pick)."""
        raise NotImplementedError

    def _load(self, match_id: int) -> Replay:
        raise NotImplementedError

    def replay(self, match_id: int) -> Replay:
        """The replay of ``match_id`` (ViewerError 404 for an unknown id, 422 unreadable)."""
        with self._lock:  # one load at a time: two requests for one replay load it once
            if match_id in self._cache:
                self._cache.move_to_end(match_id)
                return self._cache[match_id]
            replay = self._load(match_id)
            self._cache[match_id] = replay
            while len(self._cache) > CACHED_REPLAYS:
                self._cache.popitem(last=False)
            return replay

    def describe(self) -> dict[str, Any]:
        return {"kind": self.kind, "path": str(self.path), "default_match": self.default_match()}


class ReplayFileSource(ViewerSource):
    """One replay file: a single match with id 0 (loaded and checked when opened)."""

    kind = "replay"

    def __init__(self, path: Path) -> None:
        super().__init__(path)
        self.replay(0)

    def matches(self) -> list[dict[str, Any]]:
        meta = self.replay(0).metadata
        score = (meta.get("result") or {}).get("score")
        return [{"id": 0, "label": f"{meta.get('left', 'left')} vs {meta.get('right', 'right')}",
                 "left": meta.get("left"), "right": meta.get("right"), "seed": meta.get("seed"),
                 "score": score, "replay": "recorded", "tournament": None}]

    def default_match(self) -> int | None:
        return 0

    def _load(self, match_id: int) -> Replay:
        if match_id != 0:
            raise ViewerError(f"match {match_id}: this viewer shows one replay file "
                              f"({str(self.path)!r}), whose match id is 0", status=404)
        return read_replay(self.path)


class TournamentSource(ViewerSource):
    """A tournament database: every stored match of every tournament in it."""

    kind = "tournament"

    def __init__(self, path: Path) -> None:
        super().__init__(path)
        _require_tournament_tables(path)
        self.matches()  # a database that cannot be read fails here, before serving

    def _store(self) -> Any:
        from teamenv.tournament.store import ResultStore

        try:
            return ResultStore(self.path)
        except TeamEnvError as exc:
            raise ViewerError(str(exc)) from exc

    def matches(self) -> list[dict[str, Any]]:
        out = []
        with self._store() as store:
            for name in store.tournament_names():
                tid, _ = store.get_tournament(name)
                for rec in store.matches(tid):
                    recorded = bool(rec.replay_path) and Path(rec.replay_path).is_file()
                    out.append({
                        "id": rec.id, "label": f"{rec.left_team} vs {rec.right_team}",
                        "tournament": name, "left": rec.left_team, "right": rec.right_team,
                        "seed": rec.seed, "round": rec.round,
                        "score": [rec.left_score, rec.right_score],
                        "forfeit": rec.forfeit_reason, "cycles": rec.cycles,
                        "replay": "recorded" if recorded else "played again from its seed"})
        return out

    def default_match(self) -> int | None:
        return None

    def _load(self, match_id: int) -> Replay:
        from teamenv.tournament.replays import match_replay

        try:
            path = match_replay(self.path, match_id)
        except TeamEnvError as exc:
            status = 404 if "no match with id" in str(exc) else 422
            raise ViewerError(str(exc), status=status) from exc
        return read_replay(path)


def _require_tournament_tables(path: Path) -> None:
    """Refuse an SQLite file that is not a teamenv results database, reading it read-only
    (ResultStore would add its tables to any database it opens)."""
    try:
        conn = sqlite3.connect(f"{path.resolve().as_uri()}?mode=ro", uri=True)
        try:
            names = {r[0] for r in conn.execute("SELECT name FROM sqlite_master "
                                                "WHERE type='table'")}
        finally:
            conn.close()
    except sqlite3.DatabaseError as exc:
        raise ViewerError(f"database {str(path)!r}: cannot be read ({exc})") from exc
    missing = {"tournaments", "matches"} - names
    if missing:
        raise ViewerError(f"database {str(path)!r}: not a teamenv tournament database (no "
                          f"table {', '.join(sorted(missing))})")


def open_source(path: str | Path) -> ViewerSource:
    """A replay file (.npz) or a tournament database (SQLite), told apart by their first bytes;
    a missing or unreadable path raises ViewerError."""
    path = Path(path)
    if not path.is_file():
        raise ViewerError(f"{str(path)!r}: no such file (give a replay .npz or a tournament "
                          f".sqlite database)", status=404)
    with open(path, "rb") as fh:
        head = fh.read(len(_SQLITE_MAGIC))
    if head == _SQLITE_MAGIC:
        return TournamentSource(path)
    return ReplayFileSource(path)
