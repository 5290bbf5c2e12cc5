"""One match's simulation: locomotion -> pymunk -> referee -> say channel, 20 ms per cycle."""

from __future__ import annotations

import functools
import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from itertools import chain

import numpy as np

import comms
import locomotion
from teamenv.box_layout import HEARD_DIM
from teamenv.config import PhysicsConfig, RulesConfig
from teamenv.field import FieldSpec
from teamenv.observation_mode import STATE_MODE, ObservationMode
from teamenv.sim.perception import StatePerception
from teamenv.sim.referee import Referee, RefereeEvent
from teamenv.sim.vision import VisionPerception
from teamenv.sim.world import World, wrap_angle


@functools.cache
def _fill_heard():
    """The compiled heard-slot kernel, imported on the first message: importing numba takes a
    few tenths of a second that ``import teamenv`` should not pay."""
    from teamenv.sim.kernels import fill_heard

    return fill_heard


@functools.cache
def _world_velocities():
    """The compiled body -> world velocity kernel (imported on the first step, as above)."""
    from teamenv.sim.kernels import world_velocities

    return world_velocities

#: Phases of a cycle timed by ``Simulation`` (see ``Simulation.phase_s``).
SIM_PHASES = ("beam", "locomotion", "kick", "physics", "referee", "comms", "perception")


@dataclass
class Commands:
    """What every player asks for this cycle (arrays over all 2N players, player order).

    ``walk`` (n,3) body frame (m/s, m/s, rad/s); ``kick_power`` (n,) in [0,1], 0 = no kick;
    ``kick_dir`` (n,) rad body frame; ``beam_request`` (n,) bool; ``beam`` (n,3) x, y, rot in
    the player's team frame; ``say`` n strings ("" = silent).
    """

    walk: np.ndarray
    kick_power: np.ndarray
    kick_dir: np.ndarray
    beam_request: np.ndarray
    beam: np.ndarray
    say: list[str]

    @classmethod
    def idle(cls, n: int) -> Commands:
        return cls(np.zeros((n, 3)), np.zeros(n), np.zeros(n), np.zeros(n, dtype=bool),
                   np.zeros((n, 3)), [""] * n)


@dataclass
class CycleReport:
    """What happened in one cycle, for infos, replays and match summaries."""

    referee: list[RefereeEvent] = field(default_factory=list)
    kicks: list[tuple[int, float, float]] = field(default_factory=list)  # player, dist, world dir
    beams: list[int] = field(default_factory=list)
    beams_refused: list[int] = field(default_factory=list)
    delivery: comms.Delivery | None = None  # the channel's delivery when anybody spoke
    deliveries: comms.Delivery | None = field(default=None, repr=False)  # every cycle's

    @property
    def heard(self) -> list[list[comms.Heard]]:
        """What each listener heard this cycle (built on first access)."""
        return [] if self.deliveries is None else self.deliveries.heard

    @property
    def dropped(self) -> list[comms.Drop]:
        """Every message drop of the cycle (built on first access: it can be long)."""
        return [] if self.delivery is None else self.delivery.dropped


class Simulation:
    """The whole world of one match, stepped by arrays of commands. No RL API here.

    ``phase_s`` accumulates the wall-clock seconds spent in each phase of ``SIM_PHASES``
    (``perception`` is ``observations()``, true state or vision) since construction or
    ``reset_timings()``; with ``profile_phases=False`` the clock is not read and every entry
    stays 0.

    ``obs_mode``: what the agents observe (``teamenv.observation_mode``). In ``vision`` mode
    ``self.vision`` (a ``VisionPerception`` of its camera) builds the observations,
    ``odometry`` (n, 3) is the walk engine's body-frame displacement of the last cycle
    (``Bodies.step``'s ``odometry``) and ``turn`` (n,) the true heading change of its physics
    step (beams and referee placements are teleports a gyro does not feel); both are 0 after
    reset and stay 0 in state mode.
    """

    def __init__(self, field_spec: FieldSpec, team_size: int, rules: RulesConfig,
                 physics: PhysicsConfig, profile: locomotion.Profile, channel: str,
                 profile_phases: bool = True, obs_mode: ObservationMode = STATE_MODE) -> None:
        self.field, self.team_size, self.rules, self.physics = field_spec, team_size, rules, physics
        self.n = 2 * team_size
        self.profile = profile
        self.bodies = locomotion.Bodies(profile, self.n)
        self.world = self._new_world()
        self.referee = Referee(field_spec, rules, team_size, physics.cycle_s,
                               profile.body_radius, physics.ball_radius)
        self.team_of = np.repeat([0, 1], team_size)
        self.channel = comms.make_channel(channel, self.n, self.team_of)
        self.heard_slots = int(self.channel.profile.max_heard)
        self.perception = StatePerception(team_size, self.heard_slots)
        self.obs_mode = obs_mode
        self.vision = VisionPerception(
            field_spec, team_size, self.heard_slots, obs_mode.perception, profile.body_radius,
            physics.ball_radius) if obs_mode.is_vision else None
        self.odometry = np.zeros((self.n, 3))
        self.turn = np.zeros(self.n)
        self.cycle = 0
        self.rng = np.random.default_rng(0)
        self.channel_rng = np.random.default_rng(0)
        self._kernels_ready = False
        self._clear_heard()
        self.profile_phases = bool(profile_phases)
        # float() returns 0.0: with profiling off every phase adds 0 and the clock is not read.
        self._clock = time.perf_counter if self.profile_phases else float
        self.phase_s = dict.fromkeys(SIM_PHASES, 0.0)

    def _new_world(self) -> World:
        return World(self.field, self.physics, self.n, self.profile.body_radius,
                     self.profile.mass)

    def reset_timings(self) -> None:
        """Zero the per-phase wall-clock accounting."""
        self.phase_s = dict.fromkeys(SIM_PHASES, 0.0)

    def reset(self, rng: np.random.Generator,
              vision_rng: np.random.Generator | None = None,
              channel_rng: np.random.Generator | None = None) -> None:
        """Start a new match with the env's generator; ``vision_rng`` is vision's own (noise,
        calibration) and ``channel_rng`` the say channel's (arrival order, loss), each spawned
        from ``rng`` when not given, so that sightings and messages never shift the draws of
        physics and beams."""
        self.rng = rng
        self.cycle = 0
        self.odometry = np.zeros((self.n, 3))
        self.turn = np.zeros(self.n)
        if self.obs_mode.is_vision:
            self.vision.reset(rng.spawn(1)[0] if vision_rng is None else vision_rng)
        self.channel_rng = rng.spawn(1)[0] if channel_rng is None else channel_rng
        self.bodies.reset()
        self.referee.reset()
        self.channel.reset()
        if not self._kernels_ready:
            self._prepare_kernels()
        if self.world.stepped:
            # pymunk keeps contacts and its spatial index across steps: a reused space would
            # make reset(seed) differ from a fresh env's first episode in the last bits
            self.world = self._new_world()
        self.referee.place_for_start(self.world)
        self.world.impacts[:] = 0.0
        self._clear_heard()

    def _prepare_kernels(self) -> None:
        """Compile the cycle's numba kernels (or load them from numba's disk cache) at the
        first reset, with the array types a cycle hands them, on throwaway data: a cold
        compile takes seconds, and a match's stall watchdog interrupts a cycle that runs over
        its limit (an interrupted compile also leaves numba without the function). Draws from
        no generator of the match's and changes nothing of its state."""
        self._kernels_ready = True
        n = self.n
        self.bodies.prepare()
        poses = self.world.player_poses()  # read-only, as every cycle's
        _world_velocities()(np.zeros((n, 3)), poses, self.physics.cycle_s, np.empty((n, 3)))
        profile = self.channel.profile
        text = "AA==" if profile.base64_payload else profile.charset[0]
        channel = comms.Channel(profile, n, self.team_of)
        channel.deliver_texts([text] * n, poses[:, :2], poses[:, 2], np.random.default_rng(0))
        _fill_heard()(np.zeros(1, dtype=np.intp), np.zeros(1, dtype=bool),
                      np.zeros(1, dtype=bool), np.zeros(1),
                      np.zeros((n, self.heard_slots, HEARD_DIM)), np.empty(1, dtype=np.intp))

    def _clear_heard(self) -> None:
        # What each listener heard this cycle, in slot order (0 self, 1 teammate, 2 opponent
        # for simspark): texts per listener and (n, K, 4) present, self, teammate, direction.
        self._no_texts = ("",) * self.heard_slots
        self._listener_ids = np.arange(self.n)
        self._heard_texts = [self._no_texts] * self.n
        self._heard_info = np.zeros((self.n, self.heard_slots, HEARD_DIM))
        self._heard_any = False

    # -- the cycle -------------------------------------------------------------------------
    def step(self, cmd: Commands) -> CycleReport:
        clock, acc = self._clock, self.phase_s
        t0 = clock()
        report = CycleReport()
        dt = self.physics.cycle_s
        poses = self.world.player_poses()
        self._beam(cmd, poses, report)
        if report.beams:
            poses = self.world.player_poses()
        t1 = clock()
        acc["beam"] += t1 - t0

        kick_request = cmd.kick_power > 0.0
        res = self.bodies.step(cmd.walk, kick_request, cmd.kick_power, cmd.kick_dir,
                               self.world.impacts.copy(), self.rng, dt=dt)
        velocity = np.empty((self.n, 3))
        _world_velocities()(res.delta_pose, poses, dt, velocity)
        t2 = clock()
        acc["locomotion"] += t2 - t1

        touchers = self._kick(res, poses, report)
        t3 = clock()
        acc["kick"] += t3 - t2
        self.world.step(velocity)
        touchers.extend(self.world.touches)
        if self.obs_mode.is_vision:
            self.odometry = np.asarray(res.odometry, dtype=float)
            self.turn = wrap_angle(self.world.player_poses()[:, 2] - poses[:, 2])
        t4 = clock()
        acc["physics"] += t4 - t3

        report.referee = self.referee.update(self.world, touchers)
        t5 = clock()
        acc["referee"] += t5 - t4
        self._deliver(cmd.say, report)
        self.cycle += 1
        acc["comms"] += clock() - t5
        return report

    def _beam(self, cmd: Commands, poses: np.ndarray, report: CycleReport) -> None:
        requested = np.flatnonzero(cmd.beam_request)
        if requested.size == 0:
            return
        if not self.referee.beam_allowed:
            report.beams_refused.extend(int(i) for i in requested)
            return
        noise_xy, noise_rot = self.rules.beam_noise_xy, self.rules.beam_noise_rot
        for i in requested:
            sign = self.referee.attack_sign[int(self.team_of[i])]
            bx, by, rot = cmd.beam[i]
            x = sign * (bx + self.rng.normal(0.0, noise_xy)) if noise_xy else sign * bx
            y = sign * (by + self.rng.normal(0.0, noise_xy)) if noise_xy else sign * by
            heading = rot + (0.0 if sign > 0 else math.pi)
            if noise_rot:
                heading += self.rng.normal(0.0, noise_rot)
            self.world.place_player(int(i), x, y, float(wrap_angle(heading)))
            report.beams.append(int(i))

    def _kick(self, res: locomotion.StepResult, poses: np.ndarray, report: CycleReport) -> list[int]:
        kickers = np.flatnonzero(res.kick_now)
        if kickers.size == 0:
            return []
        ball = self.world.ball_state()
        dist = np.hypot(ball[0] - poses[kickers, 0], ball[1] - poses[kickers, 1])
        in_reach = dist <= self.profile.kick_reach
        if not in_reach.any():
            return []
        # When several players kick at once, the one closest to the ball gets it.
        winner = int(kickers[in_reach][np.argmin(dist[in_reach])])
        direction = float(wrap_angle(poses[winner, 2] + res.kick_direction[winner]))
        distance = float(res.kick_distance[winner])
        self.world.kick_ball(distance, direction)
        report.kicks.append((winner, distance, direction))
        return [winner]

    def _deliver(self, say: Sequence[str], report: CycleReport) -> None:
        """Hand this cycle's messages to the channel (every cycle: hearing capacities refill
        there) and fill each listener's heard slots: own message first, then teammates', then
        opponents' (stable, so each class keeps the channel's order)."""
        if self._heard_any:
            self._heard_texts = [self._no_texts] * self.n
            self._heard_info.fill(0.0)
            self._heard_any = False
        poses = self.world.player_poses()
        if any(say):
            # = deliver([Utterance(i, text, 100.0) for each non-empty text]), less work
            delivery = self.channel.deliver_texts(say, poses[:, :2], poses[:, 2],
                                                 self.channel_rng)
        else:
            delivery = self.channel.deliver((), poses[:, :2], poses[:, 2], self.channel_rng)
            report.deliveries = delivery
            return
        report.deliveries = delivery
        report.delivery = delivery
        pairs = delivery.pairs
        if pairs is None:  # built from the Heard lists (a delivery without arrays)
            heard = delivery.heard
            counts = list(map(len, heard))
            if not sum(counts):
                return
            _, texts, direction, is_self, teammate = zip(*chain.from_iterable(heard), strict=True)
            listener = np.repeat(self._listener_ids, counts)
            is_self_a = np.array(is_self, dtype=bool)
            mate_a = np.array(teammate, dtype=bool)
            direction_a = np.array(direction, dtype=float)
            texts_a = np.array(texts, dtype=object)
        else:
            listener, _, texts_a, direction_a, is_self_a, mate_a = pairs
            if not listener.size:
                return
        total = len(listener)
        if pairs is None or not delivery.grouped:
            # Sort each listener's pairs by slot class (self, teammate, opponent), stable,
            # and keep the first heard_slots (the channel's own order need not be that).
            # (listener, message) pairs come sorted by listener: rank within a listener =
            # the distance to the listener's first pair.
            slot = np.arange(total) - np.searchsorted(listener, listener)
            rank = np.where(is_self_a, 0, np.where(mate_a, 1, 2))
            order = np.lexsort((rank, listener))
            fits = slot < self.heard_slots
            keep = order[fits]
            if keep.size < total:
                listener = listener[fits]
            is_self_a, mate_a = is_self_a[keep], mate_a[keep]
            direction_a, texts_a = direction_a[keep], texts_a[keep]
        # else: already in slot order, at most max_heard (= heard_slots) per listener
        slot = np.empty(len(listener), dtype=np.intp)
        _fill_heard()(listener, is_self_a, mate_a, direction_a, self._heard_info, slot)
        table = np.full((self.n, self.heard_slots), "", dtype=object)
        table[listener, slot] = texts_a
        self._heard_texts = list(map(tuple, table.tolist()))
        self._heard_any = True

    # -- observations ----------------------------------------------------------------------
    def fallen(self) -> np.ndarray:
        return np.asarray(self.bodies.fallen, dtype=float)

    def observations(self, flat: bool = False, lazy: bool = False) -> Sequence:
        """Every agent's observation (player order): Dict form, or flat rows when ``flat``.
        In vision mode each call is a new look (noise drawn anew): use
        ``observation_forms()`` for both forms of one look. ``lazy`` (state mode, Dict form):
        a sequence whose dicts are built on first access (``perception.ObservationRows``)."""
        if self.obs_mode.is_vision:
            dicts, rows = self.observation_forms(dicts=not flat, flat=flat)
            return rows if flat else dicts
        t0 = self._clock()
        ref = self.referee
        out = self.perception.observe(
            self.world.player_poses(), self.world.player_velocities(), self.world.ball_state(),
            self.fallen(), ref.mode, ref.time_s, ref.half, ref.score, ref.attack_sign,
            self._heard_info, self._heard_texts, flat=flat, lazy=lazy)
        self.phase_s["perception"] += self._clock() - t0
        return out

    def observation_forms(self, dicts: bool = True, flat: bool = True) -> tuple[list, list]:
        """One look, in both forms: (Dict observations, flat rows); a form not asked for is
        an empty list. Vision mode only."""
        if not self.obs_mode.is_vision:
            raise RuntimeError("observation_forms() is for vision mode")
        t0 = self._clock()
        ref, vision = self.referee, self.vision
        frame = vision.observe(
            self.cycle, self.world.player_poses(), self.world.ball_state(), self.fallen(),
            self.odometry, self.turn, ref.mode, ref.time_s, ref.half, ref.score,
            ref.attack_sign, self._heard_info, self._heard_texts)
        out = (vision.as_dicts(frame) if dicts else [], vision.as_flat(frame) if flat else [])
        self.phase_s["perception"] += self._clock() - t0
        return out

    def global_state(self) -> np.ndarray:
        """World-frame state for centralized critics: ball (4), then per player x, y, heading,
        vx, vy, omega, fallen, then play mode, time, half, score left, score right."""
        ref = self.referee
        players = np.concatenate([self.world.player_poses(), self.world.player_velocities(),
                                  self.fallen()[:, None]], axis=1)
        tail = np.array([int(ref.mode), ref.time_s, ref.half, ref.score[0], ref.score[1]])
        return np.concatenate([self.world.ball_state(), players.ravel(), tail]).astype(np.float32)

    def state_size(self) -> int:
        return 4 + self.n * 7 + 5
