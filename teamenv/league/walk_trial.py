"""One T1 walking a command schedule on the league server, for tuning and testing controllers.

``walk_trial`` beams one agent to ``start`` (the left team's frame), lets it stand for
``stand_s`` with the controller's standing targets, then asks the controller for
``command_fn(t)`` (vx m/s, vy m/s, turn rad/s; t = seconds since walking began) every cycle,
and records the torso pose from the server's ``pos``/``quat`` until ``seconds`` have passed or
the robot is down (torso tilted past 60 degrees or lower than 0.4 m, the observation's fall
test). The plant is ``LocalServer`` (rcsssmj in this process, fast) by default, or the real
``rcssservermj`` with ``real_server=True``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from .controller import CYCLE_S, LocomotionController, torso_pose
from .falls import is_fallen
from .perception import Perception

Command = tuple[float, float, float]


@dataclass(frozen=True)
class WalkTrial:
    """``times`` (k,) s since walking began; ``poses`` (k, 3) world x, y, yaw; ``fell``;
    ``upright_s``: walking time before the fall (``seconds`` if it never fell)."""

    times: np.ndarray
    poses: np.ndarray
    fell: bool
    upright_s: float


def walk_trial(controller: LocomotionController, command_fn: Callable[[float], Command],
               seconds: float, stand_s: float = 0.6, start: Command = (-5.0, 0.0, 0.0),
               real_server: bool = False) -> WalkTrial:
    from . import effectors

    stand_cycles = round(stand_s / CYCLE_S)
    walk_cycles = round(seconds / CYCLE_S)
    times: list[float] = []
    poses: list[tuple[float, float, float]] = []

    def run(first: Perception, cycle: Callable[[str], Perception],
            kick_off: Callable[[], None]) -> bool:
        controller.reset()
        p = cycle(effectors.message(effectors.beam(*start), controller.stand(first)))
        kick_off()  # after the beam: the server beams only before kick-off
        for _ in range(stand_cycles):
            p = cycle(controller.stand(p))
        for k in range(walk_cycles):
            times.append(k * CYCLE_S)
            poses.append(torso_pose(p))
            if is_fallen(p):
                return True
            p = cycle(controller.step(command_fn(k * CYCLE_S), p))
        return False

    if real_server:
        from .server import LeagueServer
        from .team_client import TeamClient

        with LeagueServer() as server, TeamClient("127.0.0.1", server.agent_port, "Walker", (1,),
                                                  check_alive=server.check_alive) as team:
            team.join()

            def cycle(msg: str) -> Perception:
                team.act({1: msg})
                return team.perceive()[1]

            fell = run(team.perceive()[1], cycle, lambda: server.monitor.kick_off("Left"))
    else:
        from .local_server import LocalServer

        local = LocalServer()
        first = local.join("Walker", 1)
        fell = run(first, lambda msg: local.cycle({("Walker", 1): msg})[("Walker", 1)],
                   lambda: local.kick_off("Left"))
    return WalkTrial(np.array(times), np.array(poses).reshape(-1, 3), fell,
                     times[-1] if fell else seconds)
