"""A team for the league kick test: the chaser, beamed next to the centre spot before kick-off,
so a short match reaches the ball (team size 1's home pose is in front of its own goal)."""

from __future__ import annotations

import numpy as np

from strategy.teams.chaser import ChaserTeam
from teamenv import PlayMode

#: team frame (x, y, heading): 0.9 m behind the centre spot, a little to the left
NEAR_CENTRE = (-0.9, 0.1, 0.0)


class NearChaserTeam(ChaserTeam):
    def act(self, observations):
        views = self.beliefs.update(observations)
        return {agent: {"beam": np.array(NEAR_CENTRE), "beam_request": 1, "walk": np.zeros(3)}
                if view.play_mode == PlayMode.BeforeKickOff else self._decide(view)
                for agent, view in views.items()}
