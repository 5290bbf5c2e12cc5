"""Walk controllers that record the commands they are asked to walk, and a match on a LocalServer
that checks as it plays (league tests)."""

from __future__ import annotations


class RecordingController:
    """A stand-in walk controller (e.g. for the reference network): records each command and
    answers with a marker message instead of motor effectors."""

    def __init__(self, message: str = "(walk)"):
        self.commands: list[tuple[float, ...]] = []
        self.message = message

    def reset(self):
        pass

    def stand(self, perception):
        return "(stand)"

    def step(self, command, perception):
        self.commands.append(tuple(command))
        return self.message


def recording_walker():
    """Our ``WalkerController`` (needs the humanoid extra), recording each command it walks."""
    from teamenv.league.controller import WalkerController

    class RecordingWalker(WalkerController):
        def __init__(self):
            super().__init__()
            self.commands: list[tuple[float, ...]] = []

        def step(self, command, perception, adjust=None):
            self.commands.append(tuple(command))
            return super().step(command, perception, adjust)

    return RecordingWalker()


def play_on_checking_server(monkeypatch, server_class, left: str, right: str, options,
                            seed: int):
    """Play a league match whose ``LocalServer`` is ``server_class`` (a subclass that checks
    every cycle as it goes) and return that one server."""
    from teamenv.league import local_server
    from teamenv.league.match import play_league_match

    servers = []

    def make(*args, **kwargs):
        servers.append(server_class(*args, **kwargs))
        return servers[-1]

    monkeypatch.setattr(local_server, "LocalServer", make)
    play_league_match(left, right, options, seed=seed)
    (server,) = servers
    return server
