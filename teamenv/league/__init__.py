"""Our strategies as clients of the league's server (RCSSServerMJ 0.2.1, ``rcsssmj``).

Layers, each importing only those listed before it: ``errors``, ``framing`` (4-byte big-endian
length prefix), ``sexp`` (S-expression tokenizer), ``perception`` (every perceptor the server
sends, parsed into dataclasses), ``effectors`` (init, beam, motors, say, syn), ``server`` (the
server as a child process with clean shutdown), ``connection`` (one agent's socket, the monitor
port), ``team_client`` (the sync-mode loop for all agents of a team), ``adapter`` (perceptions
-> team-frame sightings, requests -> effectors), ``observation`` (perceptions -> the env's
``vision``-mode observation), ``match`` (the team plugins on the server) and ``cli``.

Must not import ``strategy`` (teams are found through the entry points, as everywhere in
teamenv); the MuJoCo walker of ``locomotion.humanoid`` is imported only where it is used.
"""

from __future__ import annotations

from .errors import LeagueError, ProtocolError, ServerDiedError, UnknownPerceptorError

__all__ = ["LeagueError", "ProtocolError", "ServerDiedError", "UnknownPerceptorError"]
