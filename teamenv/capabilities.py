"""What a team's body can do, as the team plans with it: one value derived from the
locomotion profile.

The env moves, kicks and topples its players by the locomotion profile
(``locomotion.Profile``); a team that plans passes, races and shots needs the same numbers.
``body_capabilities(profile)`` is the one place they are taken from the profile: the env's
``TeamContext`` carries the result as ``context.body`` (and the league bridge builds its
``TeamContext`` through the same function), so no team keeps a private copy of a kick
distance or a walking speed.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import numpy as np

#: The locomotion profile the env plays when none is named (the league's T1, measured on
#: RCSSServerMJ with its reference walking network).
DEFAULT_LOCOMOTION_PROFILE = "t1_mj"

Table = tuple[tuple[float, ...], tuple[float, ...]]


@dataclass(frozen=True)
class BodyCapabilities:
    """A body's capabilities as a team plans with them (SI units: m, s, rad).

    Attributes:
        profile: the locomotion profile's name.
        walk_low, walk_high: the walk command range (vx, vy m/s, vturn rad/s).
        tracking_vx, tracking_vy, tracking_turn: (commanded, achieved) tables: what the body
            really does for a command (interpolated between the rows).
        walk_forward_m_s, walk_backward_m_s, walk_side_m_s, turn_rad_s: the fastest walk
            forward, backward, sideways and turn (the envelope).
        kick_reach: body centre to ball centre distance at which a kick connects.
        kick_distance_mean_m, kick_distance_sd_m: ball travel of a full-power kick (mean,
            standard deviation); ``kick_distance_min_m`` / ``kick_distance_max_m`` truncate it.
            A kick of power p travels p times that.
        kick_aim_sd_rad: standard deviation of the kick direction about the aim.
        kick_prep_s: from the kick request to foot-ball contact.
        kick_duration_s: the whole kick, request to standing again (the kicker is busy).
        kick_max_angle_rad: the largest angle between the heading and a kick's direction
            that the body kicks from where it stands (pi: any direction); a kick aimed
            further off does not start (the body must turn, or walk round the ball, first).
        fall_s: from losing balance to lying on the ground.
        getup_s: from lying to standing again.
        body_radius: the body's 2D collision disc.
    """

    profile: str
    walk_low: tuple[float, float, float]
    walk_high: tuple[float, float, float]
    tracking_vx: Table
    tracking_vy: Table
    tracking_turn: Table
    walk_forward_m_s: float
    walk_backward_m_s: float
    walk_side_m_s: float
    turn_rad_s: float
    kick_reach: float
    kick_distance_mean_m: float
    kick_distance_sd_m: float
    kick_distance_min_m: float
    kick_distance_max_m: float
    kick_aim_sd_rad: float
    kick_prep_s: float
    kick_duration_s: float
    kick_max_angle_rad: float
    fall_s: float
    getup_s: float
    body_radius: float

    def forward_speed(self, command: float) -> float:
        """The forward speed (m/s) the body really walks when asked for ``command`` m/s
        (the profile's tracking table, capped by the envelope)."""
        return _tracked(self.tracking_vx, command, -self.walk_backward_m_s,
                        self.walk_forward_m_s)

    def side_speed(self, command: float) -> float:
        """The sideways speed (m/s, + left) the body really walks when asked for ``command``
        m/s (the profile's tracking table, capped by the envelope). A humanoid's side-step
        may be one-sided: the league's reference network walks right but not left."""
        return _tracked(self.tracking_vy, command, -self.walk_side_m_s, self.walk_side_m_s)


def _tracked(table: Table, command: float, low: float, high: float) -> float:
    """What a tracking table's axis achieves for ``command``, within [low, high]."""
    xp, fp = table
    return min(max(float(np.interp(float(command), xp, fp)), low), high)


def body_capabilities(profile: Any) -> BodyCapabilities:
    """The capabilities of locomotion ``profile`` (a ``locomotion.Profile``, or the name or
    path of one: ``"t1_league"``)."""
    if isinstance(profile, str):
        return _named(profile)
    p = profile

    def table(axis: int) -> Table:
        xp, fp = p.tracking[axis]
        return tuple(float(v) for v in xp), tuple(float(v) for v in fp)

    return BodyCapabilities(
        profile=str(p.name),
        walk_low=tuple(float(v) for v in p.command_low),  # type: ignore[arg-type]
        walk_high=tuple(float(v) for v in p.command_high),  # type: ignore[arg-type]
        tracking_vx=table(0), tracking_vy=table(1), tracking_turn=table(2),
        walk_forward_m_s=float(p.envelope_vx_forward),
        walk_backward_m_s=float(p.envelope_vx_backward),
        walk_side_m_s=float(p.envelope_vy), turn_rad_s=float(p.envelope_turn),
        kick_reach=float(p.kick_reach),
        kick_distance_mean_m=float(p.kick_distance_mean),
        kick_distance_sd_m=float(p.kick_distance_std),
        kick_distance_min_m=float(p.kick_distance_min),
        kick_distance_max_m=float(p.kick_distance_max),
        kick_aim_sd_rad=float(p.kick_direction_std),
        kick_prep_s=float(p.kick_prep_time), kick_duration_s=float(p.kick_duration),
        kick_max_angle_rad=float(p.kick_max_angle),
        fall_s=float(p.fall_duration), getup_s=float(p.getup_duration),
        body_radius=float(p.body_radius),
    )


@lru_cache(maxsize=16)
def _named(name: str) -> BodyCapabilities:
    from locomotion import load_profile

    return body_capabilities(load_profile(name))


def default_body() -> BodyCapabilities:
    """The capabilities of the env's default profile (``DEFAULT_LOCOMOTION_PROFILE``)."""
    return _named(DEFAULT_LOCOMOTION_PROFILE)
