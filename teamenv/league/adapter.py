"""Between the league server and our teams: perceptions -> team-frame vision sightings in the
env's ``vision`` vocabulary, and walk/kick/beam/say requests -> effectors.

Observations: the server's marks are renamed to the landmark names of
``teamenv.landmarks.landmarks(field, "mj")`` in the **team frame** (each side attacks +x; for
the right team the world is turned by pi, so its ``l_rlf`` is its ``corner_own_left``); marks
our table lacks (goal-area and penalty-area junctions) are counted in ``dropped_marks``.
Sightings keep the server's polar form (distance m, azimuth and elevation rad), which is what
the env's vision mode reports; players are seen by their ``head`` part.

Requests: ``walk`` (vx, vy m/s, turn rad/s, body frame) goes through a LocomotionController
to motor effectors; ``beam`` (x, y, theta rad, team frame, own half) is sent as is (the server
mirrors the right team); ``say`` is a text of the ``mj`` channel profile (padded base64 of at
most 10 bytes, exactly what our teams produce with ``channel="mj"``), checked by that profile
and sent as its bytes. With ``idle`` (the match sends every joint held at 0), a zero walk
stands still instead of stepping in place: our walker stepping on the spot falls within
~0.5 s on the server, the held stance stands.

**Kicks** (``teamenv.league.kick``): the encoder tracks the ball from the agent's own vision
(``BallTracker``). A kick request (power 0-1, direction rad, body frame) walks the robot into
the kick spot facing the direction (``approach_command``) and, once there with a recent
sighting (``KickMotion.ready``, ``KICK_SIGHTING_MAX_AGE_S``), starts the kick motion; a kick
request holds for ``KICK_LATCH_S`` while the ball is within ``KICK_LATCH_M`` (walk requests
meanwhile go on preparing it);
the motion plays to its end whatever is asked meanwhile (walk and kick requests are ignored,
a beam cancels it). The kick is a kick step of our walker: with our ``WalkerController`` as
the controller it continues the controller's own gait, and the walk goes on from there; with
another controller (e.g. the reference network) the kick's own ``WalkerController`` takes
over the approach within ``KICK_LATCH_M`` of the ball, once the controller has braked the
robot to the approach's pace (``teamenv.league.handover``; with ``KickParams.handover_stop``
once it has stopped and both feet are down), and the controller starts afresh
(``reset()``) when it walks again. Before the ball was ever seen a kick request walks along the kick direction.
``kick=None`` turns kicks off (a kick request is then a walk through the ball, the old
behaviour, kept for comparison).

**Getting up:** ``get_up`` (by default ``teamenv.league.getup.GetUpMotion``; any motion with
``start(perception)``/``step(perception)``/``done``; None: none) is started when the robot is
down (``falls.is_fallen``) and played to its end before anything else (a beam cancels
it); if the robot is still down then, it starts again.
"""

from __future__ import annotations

import base64
import math
from dataclasses import dataclass, field

from comms.profiles import get_profile
from teamenv.landmarks import MJ_MARKS_LEFT, MJ_MARKS_RIGHT

from . import effectors
from .command_ramp import CommandRamp
from .controller import CYCLE_S, LocomotionController, WalkerController
from .errors import LeagueError
from .falls import is_fallen
from .getup import GetUpMotion
from .handover import HandOver
from .kick import LEAGUE_KICK, BallTracker, KickMotion, approach_command
from .perception import Perception, Polar

#: server mark -> our landmark name, for the left and the right team (teamenv.landmarks)
LEFT_MARKS: dict[str, str] = MJ_MARKS_LEFT
RIGHT_MARKS: dict[str, str] = MJ_MARKS_RIGHT


@dataclass
class LeagueObservation:
    """One agent's view in our vocabulary (team frame, radians)."""

    time: float
    play_mode: str
    own_score: int
    their_score: int
    vision_update: bool
    landmarks: dict[str, Polar] = field(default_factory=dict)
    ball: Polar | None = None
    teammates: dict[int, Polar] = field(default_factory=dict)
    opponents: dict[int, Polar] = field(default_factory=dict)
    heard_text: list[tuple[float, str]] = field(default_factory=list)
    dropped_marks: int = 0


def observe(p: Perception, team: str, side: str) -> LeagueObservation:
    """``p`` as seen by a player of ``team`` playing on ``side`` ("left"/"right")."""
    if side not in ("left", "right"):
        raise LeagueError(f"side must be 'left' or 'right', not {side!r}")
    if p.game is None or p.time is None:
        raise LeagueError(f"team {team}: perception without time/GS")
    marks = LEFT_MARKS if side == "left" else RIGHT_MARKS
    own, their = ((p.game.score_left, p.game.score_right) if side == "left"
                  else (p.game.score_right, p.game.score_left))
    obs = LeagueObservation(p.game.time, p.game.play_mode, own, their, p.vision is not None)
    if p.vision is not None:
        for name, polar in p.vision.objects.items():
            if name == "B":
                obs.ball = polar
            elif name in marks:
                obs.landmarks[marks[name]] = polar
            else:
                obs.dropped_marks += 1
        for seen in p.vision.players:
            head = seen.parts.get("head")
            if head is not None:
                (obs.teammates if seen.team == team else obs.opponents)[seen.unum] = head
    for heard in p.heard or ():
        obs.heard_text.append((heard.azimuth, base64.b64encode(heard.payload).decode("ascii")))
    return obs


@dataclass(frozen=True)
class Request:
    """What a player asks for this cycle: walk (vx m/s, vy m/s, turn rad/s), an optional kick
    (power 0-1, direction rad, body frame), beam (x m, y m, theta rad), and a say text."""

    walk: tuple[float, float, float] = (0.0, 0.0, 0.0)
    kick: tuple[float, float] | None = None
    beam: tuple[float, float, float] | None = None
    say: str | None = None


#: walk speed of a kick as a walk through the ball (m/s; ``kick=None``, or the ball never seen)
KICK_WALK_SPEED = 0.4
#: a kick request holds for this long (s) while the ball stays within ``KICK_LATCH_M`` (m): a
#: team asks to kick when the ball is within its reach (the profile's ``kick_reach``, 0.35 m
#: for the T1) and walks at it otherwise, so its requests flicker while the approach steps
#: back to the kick spot (~0.43 m ahead) and its walks would push the ball away; meanwhile
#: the encoder goes on preparing the last kick asked for
KICK_LATCH_S = 3.0
KICK_LATCH_M = 1.0
#: a sighting older than this (s) does not start a kick (the ball may have moved); the ball
#: at the kick spot is below the level camera's view, so the last sighting is from ~0.55 m
KICK_SIGHTING_MAX_AGE_S = 3.0
#: with an older sighting the approach steps back (m/s, body frame) until the ball is in view
#: again: at the kick spot the ball lies below the level camera's view, and a team that keeps
#: asking to kick would otherwise keep the robot there, never starting the kick
SIGHT_AGAIN_COMMAND = (-0.15, 0.0, 0.0)


class RequestEncoder:
    """Requests -> one cycle's effector message for one agent, through its controller, its
    kick motion and (optionally) its get-up motion."""

    def __init__(self, controller: LocomotionController, who: str, channel: str = "mj",
                 stand_when_idle: bool = True, kick: KickMotion | None | str = "default",
                 get_up: GetUpMotion | None | str = "default",
                 ramp: CommandRamp | None = None) -> None:
        self.controller = controller
        #: the controller's walks (the team's and the kick approach's) go through this ramp
        #: (``command_ramp``; None: as asked), inside the controller's envelope; it restarts
        #: from standing when the controller does (after a beam, a motion or the kick's walker)
        self.ramp = ramp
        self.who = who
        #: a zero walk without a kick sends the controller's standing targets (which resets
        #: its walk, so a later walk starts afresh) instead of walking on the spot
        self.stand_when_idle = stand_when_idle
        #: the kick motion (None: kicks are walks through the ball); by default a kick step of
        #: the controller's own gait when it is our walker, else of a walker of its own
        if kick == "default":
            kick = KickMotion(controller if isinstance(controller, WalkerController) else
                              WalkerController(stand_s=HandOver(LEAGUE_KICK.handover_stop).stand_s))
        self.kick = kick
        self._walking: LocomotionController | None = controller   # the walk that stepped last
        #: the get-up motion run when the robot is down (None: lying robots get the request)
        self.get_up = GetUpMotion() if get_up == "default" else get_up
        self.ball = BallTracker()
        #: near the ball the controller brakes before the kick's walker takes over
        self.handover = HandOver(stop=kick is not None and kick.params.handover_stop)
        self._motion = None   # the kick or get-up now playing
        self._latch = None    # (power, world heading, seconds left) of the last kick request
        self.profile = get_profile(channel)
        if not self.profile.base64_payload:
            raise LeagueError(f"{self.who}: the league server needs the 'mj' channel, not {channel!r}")

    @property
    def kicking(self) -> bool:
        return self._motion is not None and self._motion is self.kick

    def _walk_through(self, direction: float) -> tuple[float, float, float]:
        return (KICK_WALK_SPEED * math.cos(direction), 0.0, direction / 0.5)

    def _latched_kick(self, request: Request, perception: Perception):
        """The kick to prepare this cycle: the request's, or (for ``KICK_LATCH_S`` after one)
        the last one, its direction kept in the world frame while the robot turns."""
        from .controller import torso_pose

        if request.kick is not None:
            power, direction = request.kick
            if self.kick is not None:
                self._latch = (power, torso_pose(perception)[2] + direction, KICK_LATCH_S)
            return request.kick
        ball = self.ball.body
        if (self.kick is None or self._latch is None or self._latch[2] <= 0.0
                or ball is None or math.hypot(*ball) > KICK_LATCH_M):
            self._latch = None
            return None
        yaw = torso_pose(perception)[2]
        power, heading, left = self._latch
        self._latch = (power, heading, left - CYCLE_S)
        return power, math.remainder(heading - yaw, 2 * math.pi)

    def _body(self, request: Request, perception: Perception) -> str:
        """This cycle's motor message."""
        if self._motion is self.kick and self.get_up is not None and is_fallen(perception):
            self._motion = None               # down during a kick: get up instead
        if self._motion is not None:
            message = self._motion.step(perception)
            if self._motion.done:
                self._motion = None
            return message
        if self.get_up is not None and is_fallen(perception):
            self.get_up.start(perception)
            self._motion, self._walking = self.get_up, None
            if self.ramp is not None:
                self.ramp.reset()
            return self._body(request, perception)
        walk = request.walk
        kick = self._latched_kick(request, perception)
        if kick is not None:
            power, direction = kick
            ball = self.ball.body
            if self.kick is None or ball is None:
                walk = self._walk_through(direction)
            elif (self.kick.ready(ball, direction, self._walking is self.kick.walker)
                  and self.ball.age_s <= KICK_SIGHTING_MAX_AGE_S):
                walker = self.kick.walker if self.kick.shares_walker else None
                if walker is not None and self._walking is not walker:
                    walker.reset()    # its gait starts here (the kick waits for its steps)
                self.kick.start(perception, direction, min(max(power, 0.0), 1.0), ball=ball)
                self._motion, self._walking = self.kick, walker
                self._latch = None        # this kick is played: the request is answered
                if self.ramp is not None:
                    self.ramp.reset()     # the controller starts afresh after the kick
                return self._body(request, perception)
            else:
                # near the ball the kick's own walker walks the approach, so the kick goes on
                # in its gait (the controller, if it is another walk, hands over here)
                begun = self.kick.walker is not self.controller and (
                    self._walking is self.kick.walker or self.handover.braking)
                near = self.kick.shares_walker and self.handover.near(
                    math.hypot(*ball), KICK_LATCH_M, begun)
                command = approach_command(ball, direction, self.kick.params)
                if self.ball.age_s > KICK_SIGHTING_MAX_AGE_S:
                    command = SIGHT_AGAIN_COMMAND
                if not near:
                    return self._walk(self._ramped(command), perception)
                if self._walking is not self.kick.walker and not self.handover.ready:
                    # slow down on the controller first: the kick's walker starts from rest
                    return self._step(self.controller, self.handover.brake(command), perception)
                if self.ramp is not None:
                    self.ramp.reset()     # the controller starts afresh after the hand-over
                return self._step(self.kick.walker, command, perception)
        walk = self._ramped(walk)
        if self.stand_when_idle and kick is None and not any(walk):
            self._walking = self.controller
            self.handover.walked((0.0, 0.0, 0.0))
            return self.controller.stand(perception)
        return self._walk(walk, perception)

    def _walk(self, command, perception: Perception) -> str:
        """One cycle of the controller walking ``command`` (what a hand-over brakes from)."""
        message = self._step(self.controller, command, perception)
        self.handover.walked(command)
        return message

    def _ramped(self, command):
        """``command`` inside the controller's envelope, through the ramp (if any)."""
        if self.ramp is None:
            return command
        envelope = getattr(self.controller, "envelope", None)
        return self.ramp(command if envelope is None else envelope.limit(command))

    def _step(self, walker: LocomotionController, command, perception: Perception) -> str:
        """One walk cycle of ``walker``, which starts afresh when another walk (or a motion)
        stepped last."""
        if self._walking is not walker:
            walker.reset()
            if walker is self.controller:
                self.handover.reset()     # its walk starts from rest
            self._walking = walker
        return walker.step(command, perception)

    def encode(self, request: Request, perception: Perception) -> str:
        parts: list[str] = []
        self.ball.update(perception)
        self.handover.update(perception)
        if request.beam is not None:
            # every motor is commanded every cycle (an uncommanded one lets rcsssmj zero
            # every robot's controls, see docs/league.md): a beam comes with the stance
            self._motion = self._latch = None
            self._walking = self.controller
            if self.ramp is not None:
                self.ramp.reset()
            parts += [effectors.beam(*request.beam), self.controller.stand(perception)]
        else:
            parts.append(self._body(request, perception))
        if request.say:
            reason = self.profile.check_message(request.say)
            if reason is not None:
                raise LeagueError(f"{self.who}: say {request.say!r} breaks the mj channel: {reason}")
            parts.append(effectors.say(base64.b64decode(request.say, validate=True)))
        return effectors.message(*parts)
