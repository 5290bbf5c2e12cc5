"""A kick from the reference network's approach on LocalServer with ``handover_stop``
(teamenv.league.handover): the network stops near the ball, and the kick's walker takes over
at rest on both feet, so the robot kicks and stays up where taking over the network's gait
fell (docs/league.md, *A hand-over that stops first*)."""

from __future__ import annotations

import pytest

pytestmark = pytest.mark.humanoid


def test_a_network_approach_stops_then_hands_over_on_both_feet_and_kicks_upright(monkeypatch):
    pytest.importorskip("rcsssmj")
    pytest.importorskip("mujoco")
    from teamenv.league import handover
    from teamenv.league.controller import CYCLE_S
    from teamenv.league.feet import feet_down
    from teamenv.league.kick import LEAGUE_KICK
    from teamenv.league.kick_trial import BALL, kick_trial
    from teamenv.league.network_walk import NetworkWalkController

    seen = {"stop": 0, "feet_down_at_hand_over": None}
    ready = handover.HandOver.ready

    def spy_brake(self, target):
        seen["stop"] += 1
        return handover.HandOver._ramp_stop(self, target)

    def spy_ready(self):
        now = ready.fget(self)
        if now and seen["feet_down_at_hand_over"] is None:
            seen["feet_down_at_hand_over"] = feet_down(self._perception)
        return now

    monkeypatch.setattr(handover.HandOver, "_ramp_stop", handover.HandOver.brake, raising=False)
    monkeypatch.setattr(handover.HandOver, "brake", spy_brake)
    monkeypatch.setattr(handover.HandOver, "ready", property(spy_ready))
    # the start of tuning trial 4054, rounded: taking over the network's gait there fell 1.0 s
    # after the hand-over, before the kick
    start = (BALL[0] - 1.2, BALL[1] - 0.45, -0.03)
    r = kick_trial(start, -0.05, walker=NetworkWalkController(), settle_s=1.0, seed=4054,
                   params=LEAGUE_KICK.with_(handover_stop=True))
    assert seen["stop"] >= round(handover.HANDOVER_STOP_S / CYCLE_S)   # stopped first
    assert seen["feet_down_at_hand_over"] is True
    assert r.kicked and r.strike_ball_x is not None
    assert r.upright and not r.fell_during
    assert r.travel >= 2.0
