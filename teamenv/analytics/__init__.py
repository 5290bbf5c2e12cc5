"""Match analytics from replays: events (kicks, passes, shots, possession), expected goals,
per-team statistics, figures and an HTML report.

Imports numpy (and scikit-learn only to fit the xG model, matplotlib only for figures) and
``teamenv.replay``; it must not import ``strategy``, the env or the simulation: everything it
knows comes from a replay file.
"""

from __future__ import annotations

from teamenv.analytics.stats import MatchStats, TeamStats, match_stats, replay_stats

__all__ = ["MatchStats", "TeamStats", "match_stats", "replay_stats"]
