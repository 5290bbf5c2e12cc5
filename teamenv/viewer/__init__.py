"""The web replay viewer: ``teamenv view REPLAY|TOURNAMENT.sqlite`` serves a local page that
plays replays on a canvas (stdlib ``http.server``, static files shipped with the package).

Modules: ``sources`` (a replay file or a tournament database), ``payload`` (a replay in the
page's compact form), ``server`` (the HTTP routes), ``cli`` (``teamenv view``), ``static/``
(the page). Imports only teamenv's replay, field, config and tournament store (and
``teamenv.analytics`` when installed); never ``strategy``. Importing this package imports
nothing heavy.
"""
