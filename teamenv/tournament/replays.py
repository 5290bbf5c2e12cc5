"""Replays of stored tournament matches: reuse the recorded file or replay from seed and teams."""

from __future__ import annotations

import tempfile
from dataclasses import replace
from pathlib import Path

from teamenv.tournament.backends import execute_task
from teamenv.tournament.errors import StoreError
from teamenv.tournament.store import ResultStore


def match_replay(db: str | Path, match_id: int, replay_out: str | Path | None = None,
                 verify: bool = True) -> Path:
    """The replay file (.npz) of stored match ``match_id``.

    Uses the replay recorded with the match when it still exists; otherwise plays the match
    again from its seed, teams and options (matches are deterministic) into ``replay_out``
    (default: a temporary file) and, with ``verify``, checks that the score and goals equal the
    stored ones (a StoreError says when they do not: a team changed since).
    """
    with ResultStore(db) as store:
        record = store.match(match_id)
        tournament = store.match_tournament(match_id)
    if record.replay_path and Path(record.replay_path).is_file() and replay_out is None:
        return Path(record.replay_path)
    schedule = tournament.schedule()
    if not 0 <= record.idx < len(schedule):
        raise StoreError(f"match {match_id}: schedule index {record.idx} is not in the "
                         f"definition of tournament {tournament.name!r}")
    if replay_out is None:
        replay_out = Path(tempfile.mkdtemp(prefix="teamenv-replay-")) / f"match-{match_id}.npz"
    task = replace(schedule[record.idx], replay_path=str(replay_out))
    result = execute_task(task)
    if verify:
        again = (tuple(result.score), [(round(g.time_s, 6), g.side) for g in result.goals])
        stored = ((record.left_score, record.right_score),
                  [(round(g.time_s, 6), g.side) for g in record.goals])
        if again != stored:
            raise StoreError(f"match {match_id} ({record.left_team} vs {record.right_team}, seed "
                             f"{record.seed}): replaying it gave {again}, the database holds "
                             f"{stored}; a team or teamenv changed since (stored versions "
                             f"{record.left_version!r}, {record.right_version!r})")
    return Path(replay_out)


def render_match(db: str | Path, match_id: int, out_path: str | Path, fps: int = 10,
                 every: int = 5, verify: bool = True) -> Path:
    """Render stored match ``match_id`` to a GIF/MP4 (needs the ``render`` extra)."""
    from teamenv.render import render_replay_gif

    replay = match_replay(db, match_id, verify=verify)
    return render_replay_gif(replay, out_path, fps=fps, every=every)
