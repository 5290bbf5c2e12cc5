"""Our kick-offs in league matches on LocalServer: double-touch fouls and how far the ball went.

    python benchmarks/league_kickoff_fouls.py --seeds 100340:100346 --seconds 40

Plays ``--left`` v ``--right`` (7 v 7 unless ``--team-size``, ``LocalServer``, the league's
default walk, no command ramp) for every seed and reads the server's own referee as it rules
(rcsssmj's ``SoccerReferee``, which ``LocalServer`` runs in this process): every foul it
logs (``_log_foul``: the agent and the foul, ``DOUBLE_TOUCH`` being the taker's second touch
more than 1 s after its first before anyone else touched the ball), and every kick-off of the
left team (``KickOff_Left`` until the ball is touched): when the first touch came, the ball's
place ``--after`` seconds later, and whether a double-touch foul by the left team followed
within ``--after`` s (the foul that gave the opponents a free kick after every kick-off before
the taker was beamed to its kick stance). Prints one line per match and the totals;
``--json`` writes them.
"""

from __future__ import annotations

import argparse
import json
import time
from contextlib import contextmanager
from pathlib import Path


@contextmanager
def _watching(record: dict):
    """Record the referee's fouls and the left team's kick-offs while a match plays."""
    from rcsssmj.games.soccer.sim.soccer_referee import SoccerReferee

    log_foul, check = SoccerReferee._log_foul, SoccerReferee._check_fouls
    state = {"mode": None}

    def logged(self, agent, foul):
        record["fouls"].append({"time_s": round(float(self.game.game_state.sim_time), 2),
                                "team": "left" if agent.team_id == 0 else "right",
                                "unum": int(agent.player_no),
                                "foul": getattr(foul, "name", str(foul))})
        return log_foul(self, agent, foul)

    def checked(self, *args, **kwargs):
        now = float(self.game.game_state.sim_time)
        mode = getattr(self.game.game_state.play_mode, "name", "")
        ball = [round(float(v), 2) for v in self.game.ball.xpos[:2]]
        if state["mode"] == "KICK_OFF_LEFT" and mode != "KICK_OFF_LEFT":
            record["kick_offs"].append({"touched_s": round(now, 2), "ball_after": None})
        for k in record["kick_offs"]:
            if k["ball_after"] is None and now >= k["touched_s"] + record["after_s"]:
                k["ball_after"] = ball
        state["mode"] = mode
        return check(self, *args, **kwargs)

    SoccerReferee._log_foul, SoccerReferee._check_fouls = logged, checked
    try:
        yield
    finally:
        SoccerReferee._log_foul, SoccerReferee._check_fouls = log_foul, check


def play(left: str, right: str, seed: int, seconds: float, team_size: int,
         after_s: float) -> dict:
    from teamenv.league.match import LeagueMatchOptions, play_league_match

    record: dict = {"fouls": [], "kick_offs": [], "after_s": after_s}
    start = time.process_time()
    with _watching(record):
        result = play_league_match(left, right, LeagueMatchOptions(
            team_size=team_size, game_s=seconds, server="local", ramp=False), seed=seed)
    for k in record["kick_offs"]:
        # a double-touch foul by the left team within after_s of the kick-off's first touch
        k["foul"] = any(f["foul"] == "DOUBLE_TOUCH" and f["team"] == "left"
                        and k["touched_s"] <= f["time_s"] <= k["touched_s"] + after_s
                        for f in record["fouls"])
    return {"seed": seed, "left": left, "right": right, "seconds": seconds,
            "score": list(result.score), "fouls": record["fouls"],
            "kick_offs": record["kick_offs"], "cpu_s": round(time.process_time() - start, 1)}


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--left", default="full")
    parser.add_argument("--right", default="static")
    parser.add_argument("--seeds", default="100340:100346", help="START:STOP (half-open)")
    parser.add_argument("--seconds", type=float, default=40.0)
    parser.add_argument("--team-size", type=int, default=7)
    parser.add_argument("--after", type=float, default=5.0,
                        help="seconds after a kick-off's first touch that are its own")
    parser.add_argument("--json", type=Path, default=None)
    args = parser.parse_args(argv)
    first, stop = (int(v) for v in args.seeds.split(":"))
    matches = []
    for seed in range(first, stop):
        m = play(args.left, args.right, seed, args.seconds, args.team_size, args.after)
        matches.append(m)
        shown = ", ".join(
            f"touched {k['touched_s']} s, ball {k['ball_after']} after {args.after:g} s"
            + (", DOUBLE-TOUCH FOUL" if k["foul"] else "") for k in m["kick_offs"])
        print(f"seed {seed}: score {m['score']}, kick-offs: {shown or 'none taken'}; fouls "
              f"{[(f['time_s'], f['team'], f['unum'], f['foul']) for f in m['fouls']]}, "
              f"{m['cpu_s']} CPU s", flush=True)
    kick_offs = [k for m in matches for k in m["kick_offs"]]
    fouled = sum(k["foul"] for k in kick_offs)
    far = [k for k in kick_offs if k["ball_after"] is not None and not k["foul"]
           and abs(k["ball_after"][0]) >= 1.0]
    print(f"{len(matches)} matches, {len(kick_offs)} kick-offs of {args.left}: {fouled} "
          f"double-touch fouls, {len(far)} sent the ball >= 1 m along the pitch; goals "
          f"{sum(sum(m['score']) for m in matches)}")
    if args.json:
        args.json.write_text(json.dumps({"matches": matches}, indent=1) + "\n")


if __name__ == "__main__":
    main()
