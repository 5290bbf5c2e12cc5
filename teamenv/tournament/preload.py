"""Imported by the process pool's fork server only, once, before it forks any worker: loads
teamenv's match code and the teams named (as a JSON list) in ``$TEAMENV_TOURNAMENT_TEAMS``, so
every worker forked from the server starts with them imported. A team that fails to load here
is skipped (its matches report it); nothing here can take the server down."""

from __future__ import annotations

import json
import os

from teamenv.tournament.backends import PRELOAD_ENV, warm_up

try:
    _names = tuple(json.loads(os.environ.get(PRELOAD_ENV) or "[]"))
except (ValueError, TypeError):
    _names = ()
warm_up(_names)
