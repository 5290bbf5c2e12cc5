"""Record real server messages for the parser tests: ``python -m teamenv.league.record DIR``.

Starts a server, joins two agents of team ``Alpha`` and one of ``Beta``, beams them, has
Alpha 1 say ``hello``, sends a motor command, kicks off, and writes one message of each
interesting kind (an early one with vision, one with players and the ball, with a heard message, after kick-off) to DIR.
"""

from __future__ import annotations

import sys
from pathlib import Path

from . import effectors
from .server import LeagueServer
from .team_client import TeamClient, join_teams


def record(out_dir: Path, cycles: int = 30) -> dict[str, str]:
    """Play ``cycles`` cycles and return the recorded messages by file name."""
    saved: dict[str, str] = {}
    with LeagueServer() as server:
        alpha = TeamClient("127.0.0.1", server.agent_port, "Alpha", (1, 2),
                           check_alive=server.check_alive)
        beta = TeamClient("127.0.0.1", server.agent_port, "Beta", (1,),
                          check_alive=server.check_alive)
        raw: dict[str, str] = {}
        for team in (alpha, beta):
            team.on_message = lambda unum, text, name=team.team: raw.__setitem__(
                f"{name}_{unum}", text)
        try:
            join_teams([alpha, beta])
            for cycle in range(cycles):
                pa, pb = alpha.perceive(), beta.perceive()
                if "first.txt" not in saved and pa[1].vision is not None:
                    saved["first.txt"] = raw["Alpha_1"]     # before kick-off, with vision
                if "vision_players_ball.txt" not in saved and pb[1].vision is not None \
                        and pb[1].vision.players and pb[1].vision.ball is not None:
                    saved["vision_players_ball.txt"] = raw["Beta_1"]
                if "no_vision.txt" not in saved and pa[1].vision is None:
                    saved["no_vision.txt"] = raw["Alpha_1"]
                if "heard.txt" not in saved and pb[1].heard:
                    saved["heard.txt"] = raw["Beta_1"]
                if pa[1].game is not None and pa[1].game.play_mode.startswith("KickOff"):
                    saved.setdefault("kick_off.txt", raw["Alpha_1"])
                acts_a = {1: effectors.beam(-3.0, 1.0, 0.5), 2: effectors.beam(-5.0, -2.0, 0.0)}
                acts_b = {1: effectors.beam(-4.0, 0.0, 3.1)}
                if cycle == 3:
                    acts_a = {1: effectors.say(b"hello")}
                if cycle == 5:
                    acts_a = {2: effectors.message(effectors.motor("he1", 0.2, 0.0, 20.0, 1.0))}
                alpha.act(acts_a if cycle in (0, 3, 5) else None)
                beta.act(acts_b if cycle == 0 else None)
                if cycle == 12:
                    server.monitor.kick_off("Left")
        finally:
            alpha.close()
            beta.close()
    out_dir.mkdir(parents=True, exist_ok=True)
    for name, text in saved.items():
        (out_dir / name).write_text(text + "\n")
    return saved


if __name__ == "__main__":
    got = record(Path(sys.argv[1]) if len(sys.argv) > 1 else Path("league_data"))
    print(sorted(got))
