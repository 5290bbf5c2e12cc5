"""Walk controllers that record the commands they are asked to walk (league tests)."""

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
