"""The pymunk world: player discs, the ball, goal posts and nets, and the boundary walls."""

from __future__ import annotations

import functools
import math

import numpy as np
import pymunk

try:  # bulk body I/O (pymunk >= 6.5); the per-body path below is the fallback
    import pymunk.batch as _batch
except ImportError:  # pragma: no cover - older pymunk
    _batch = None

from teamenv.config import PhysicsConfig
from teamenv.field import FieldSpec

BALL, PLAYER, POST, WALL = 1, 2, 3, 4


class World:
    """Bodies of one match in world coordinates (metres, radians; origin at the centre spot).

    Players are velocity-controlled discs: each cycle the locomotion model says how far each
    body moves, and pymunk resolves the contacts. The ball rolls freely with a drag model
    applied once per cycle. The number of substeps grows with the ball's speed so a hard kick
    never moves it further than ``max_substep_travel`` in one substep (no tunnelling).
    """

    def __init__(
        self, field: FieldSpec, physics: PhysicsConfig, n_players: int,
        player_radius: float, player_mass: float,
    ) -> None:
        self.field = field
        self.physics = physics
        self.n_players = n_players
        self.player_radius = player_radius
        self.space = pymunk.Space()
        self.space.gravity = (0.0, 0.0)
        self.space.iterations = 10
        # pymunk's default slop (0.1) assumes pixels; in metres it would let the ball sink 10 cm.
        self.space.collision_slop = 0.001
        self.margin = max(physics.world_margin, field.goal_depth + 0.5)
        self.bounds = (field.half_length + self.margin, field.half_width + self.margin)
        self._add_static_geometry()
        self.players: list[pymunk.Body] = []
        self._player_index: dict[pymunk.Body, int] = {}
        self._shape_index: dict[pymunk.Shape, int] = {}
        for i in range(n_players):
            body = pymunk.Body(player_mass, float("inf"))
            shape = pymunk.Circle(body, player_radius)
            shape.collision_type = PLAYER
            shape.elasticity = physics.player_elasticity
            shape.friction = 0.5
            self.space.add(body, shape)
            self.players.append(body)
            self._player_index[body] = i
            self._shape_index[shape] = i
        self.ball = pymunk.Body(physics.ball_mass, pymunk.moment_for_circle(
            physics.ball_mass, 0.0, physics.ball_radius))
        ball_shape = pymunk.Circle(self.ball, physics.ball_radius)
        ball_shape.collision_type = BALL
        ball_shape.elasticity = physics.ball_elasticity
        ball_shape.friction = 0.2
        self.space.add(self.ball, ball_shape)
        self.impacts = np.zeros(n_players)
        self._impacts = [0.0] * n_players  # collision callbacks' running sums (see step)
        self.touches: list[int] = []  # player indices that touched the ball this cycle
        self.space.on_collision(PLAYER, PLAYER, post_solve=self._on_player_impact)
        self.space.on_collision(PLAYER, POST, post_solve=self._on_player_impact)
        self.space.on_collision(BALL, PLAYER, pre_solve=self._on_ball_touch)
        self._launch_table = _launch_table(physics)
        self.stepped = False  # set by the first step (reset builds a new world after that)
        self._poses: np.ndarray | None = None
        self._velocities: np.ndarray | None = None
        self._setup_batch()

    def _setup_batch(self) -> None:
        """Use pymunk's batch API for player I/O when the space lists the players first, in
        order, then the ball (checked here by body id); otherwise read body by body."""
        self._batch = None
        if _batch is None:
            return
        fields = _batch.BodyFields
        buf = _batch.Buffer()
        _batch.get_space_bodies(self.space, fields.BODY_ID, buf)
        ids = np.frombuffer(buf.int_buf(), dtype=np.uintp).tolist()
        expected = [body.id for body in self.players] + [self.ball.id]
        if ids[:len(expected)] != expected:
            return
        self._batch = buf
        self._batch_set = _batch.Buffer()
        # Velocities written each cycle: the players' rows, then the ball's (read from the
        # ball itself, so it keeps its own). The Buffer points at this array's memory.
        self._vel_values = np.zeros((len(ids), 3))
        self._batch_set.set_float_buf(self._vel_values)
        self._players_and_ball = len(ids) == len(expected)
        self._read_fields = fields.POSITION | fields.ANGLE | fields.VELOCITY | \
            fields.ANGULAR_VELOCITY
        self._vel_fields = fields.VELOCITY | fields.ANGULAR_VELOCITY

    # -- copying -------------------------------------------------------------------------
    def __getstate__(self) -> dict:
        # pymunk pickles and copies its space, bodies, shapes and collision handlers; the
        # batch-API buffers are C memory that does not pickle: dropped and made anew
        state = self.__dict__.copy()
        for name in ("_batch", "_batch_set"):
            state.pop(name, None)
        return state

    def __setstate__(self, state: dict) -> None:
        self.__dict__.update(state)
        self._setup_batch()

    # -- geometry --------------------------------------------------------------------------
    def _add_static_geometry(self) -> None:
        f, static = self.field, self.space.static_body
        hx, hy = self.bounds
        shapes: list[pymunk.Shape] = []
        wall_r = 0.05
        corners = [(-hx, -hy), (hx, -hy), (hx, hy), (-hx, hy)]
        for a, b in zip(corners, corners[1:] + corners[:1], strict=True):
            shapes.append(self._static(pymunk.Segment(static, a, b, wall_r), WALL, 0.5))
        for sign in (-1.0, 1.0):
            line_x = sign * f.half_length
            back_x = sign * (f.half_length + f.goal_depth)
            for side in (-1.0, 1.0):
                post = (line_x, side * f.half_goal_width)
                shapes.append(self._static(
                    pymunk.Circle(static, f.goal_post_radius, post), POST, 0.5))
                # Net side wall, from the post to the back of the goal.
                shapes.append(self._static(pymunk.Segment(
                    static, (line_x + sign * f.goal_post_radius, side * f.half_goal_width),
                    (back_x, side * f.half_goal_width), 0.02), WALL, 0.1))
            shapes.append(self._static(pymunk.Segment(
                static, (back_x, -f.half_goal_width), (back_x, f.half_goal_width), 0.02), WALL, 0.1))
        self.space.add(*shapes)

    @staticmethod
    def _static(shape: pymunk.Shape, collision_type: int, elasticity: float) -> pymunk.Shape:
        shape.collision_type = collision_type
        shape.elasticity = elasticity
        shape.friction = 0.3
        return shape

    # -- collision callbacks ---------------------------------------------------------------
    def _on_player_impact(self, arbiter: pymunk.Arbiter, space: pymunk.Space, data: object) -> None:
        impulse = arbiter.total_impulse.length
        index_of, impacts = self._shape_index, self._impacts
        for shape in arbiter.shapes:
            index = index_of.get(shape)
            if index is not None:
                impacts[index] += impulse

    def _on_ball_touch(self, arbiter: pymunk.Arbiter, space: pymunk.Space, data: object) -> None:
        for shape in arbiter.shapes:
            index = self._shape_index.get(shape)
            if index is not None and (not self.touches or self.touches[-1] != index):
                self.touches.append(index)

    # -- state access ----------------------------------------------------------------------
    def _read_players(self) -> None:
        """Poses and velocities of every player in one batch read."""
        buf = self._batch
        buf.clear()
        _batch.get_space_bodies(self.space, self._read_fields, buf)
        data = np.frombuffer(buf.float_buf(), dtype=float).reshape(-1, 6)[:self.n_players]
        poses = data[:, :3].copy()
        poses[:, 2] = wrap_angle(poses[:, 2])
        poses.flags.writeable = False
        velocities = data[:, 3:].copy()
        velocities.flags.writeable = False
        self._poses, self._velocities = poses, velocities

    def player_poses(self) -> np.ndarray:
        """(n, 3) array of x, y, heading (heading wrapped to [-pi, pi)); do not modify it."""
        if self._poses is None and self._batch is not None:
            self._read_players()
        if self._poses is None:
            out = np.array([(*body.position, body.angle) for body in self.players],
                           dtype=float).reshape(self.n_players, 3)
            out[:, 2] = wrap_angle(out[:, 2])
            out.flags.writeable = False
            self._poses = out
        return self._poses

    def player_velocities(self) -> np.ndarray:
        """(n, 3) array of vx, vy (m/s, world frame) and angular velocity (rad/s)."""
        if self._velocities is None and self._batch is not None:
            self._read_players()
        if self._velocities is None:
            out = np.array([(*body.velocity, body.angular_velocity) for body in self.players],
                           dtype=float).reshape(self.n_players, 3)
            out.flags.writeable = False
            self._velocities = out
        return self._velocities

    def _invalidate(self) -> None:
        # Poses and velocities are read several times a cycle; pymunk is asked once.
        self._poses = None
        self._velocities = None

    def ball_state(self) -> np.ndarray:
        """(4,) array: x, y, vx, vy of the ball."""
        (x, y), (vx, vy) = self.ball.position, self.ball.velocity
        return np.array([x, y, vx, vy])

    def place_ball(self, x: float, y: float, vx: float = 0.0, vy: float = 0.0) -> None:
        self.ball.position = (float(x), float(y))
        self.ball.velocity = (float(vx), float(vy))
        self.ball.angular_velocity = 0.0

    def place_player(self, index: int, x: float, y: float, heading: float | None = None) -> None:
        hx, hy = self.bounds
        r = self.player_radius
        body = self.players[index]
        body.position = (float(np.clip(x, -hx + r, hx - r)), float(np.clip(y, -hy + r, hy - r)))
        body.velocity = (0.0, 0.0)
        if heading is not None:
            body.angle = float(heading)
        body.angular_velocity = 0.0
        self._invalidate()

    # -- dynamics --------------------------------------------------------------------------
    def step(self, world_velocity: np.ndarray) -> None:
        """Advance one cycle; players move with ``world_velocity`` (n, 3): vx, vy, omega."""
        dt = self.physics.cycle_s
        self.stepped = True
        # Collision callbacks add to a list of floats (same additions, same order), copied
        # into ``impacts`` after the step.
        self._impacts = [0.0] * self.n_players
        self.touches.clear()
        self._invalidate()
        self._set_player_velocities(world_velocity)
        fastest = max(self.ball.velocity.length, float(np.abs(world_velocity[:, :2]).max(initial=0)))
        substeps = max(1, math.ceil(fastest * dt / self.physics.max_substep_travel))
        h = dt / substeps
        for _ in range(substeps):
            self.space.step(h)
        self.impacts[:] = self._impacts
        self._invalidate()
        self._roll_ball(dt)

    def _set_player_velocities(self, world_velocity: np.ndarray) -> None:
        if self._batch is None:
            for body, (vx, vy, omega) in zip(self.players, world_velocity.tolist(), strict=True):
                body.velocity = (vx, vy)
                body.angular_velocity = omega
            return
        if self._players_and_ball:
            # Every body of the space is written: the players' rows, then the ball's own.
            values, n = self._vel_values, self.n_players
            values[:n] = world_velocity
            ball = self.ball
            values[n, :2] = ball.velocity
            values[n, 2] = ball.angular_velocity
            _batch.set_space_bodies(self.space, self._vel_fields, self._batch_set)
            return
        # Every body of the space is written: read them, replace the players' rows.
        buf = self._batch
        buf.clear()
        _batch.get_space_bodies(self.space, self._vel_fields, buf)
        values = np.frombuffer(buf.float_buf(), dtype=float).reshape(-1, 3).copy()
        values[:self.n_players] = world_velocity
        setter = _batch.Buffer()
        setter.set_float_buf(values)
        _batch.set_space_bodies(self.space, self._vel_fields, setter)

    def _roll_ball(self, dt: float) -> None:
        vx, vy = self.ball.velocity
        speed = math.hypot(vx, vy)
        if speed == 0.0:
            return
        new_speed = rolled_speed(speed, self.physics, dt)
        scale = new_speed / speed
        self.ball.velocity = (vx * scale, vy * scale)
        self.ball.angular_velocity = 0.0

    def kick_ball(self, distance: float, direction: float) -> None:
        """Launch the ball so it rolls ``distance`` metres towards world angle ``direction``."""
        speed = self.launch_speed(distance)
        self.ball.velocity = (speed * math.cos(direction), speed * math.sin(direction))

    def launch_speed(self, distance: float) -> float:
        """Speed (m/s) at which the ball rolls ``distance`` metres before it stops."""
        speeds, distances = self._launch_table
        return float(np.interp(distance, distances, speeds))



@functools.lru_cache(maxsize=16)
def _launch_table(physics: PhysicsConfig) -> tuple[np.ndarray, np.ndarray]:
    """(speeds, roll distances) for ``World.launch_speed``; one per physics config (read-only)."""
    speeds = np.linspace(0.0, physics.ball_max_speed, 241)
    distances = np.array([roll_distance(s, physics) for s in speeds])
    speeds.flags.writeable = distances.flags.writeable = False
    return speeds, distances


def rolled_speed(speed: float, physics: PhysicsConfig, dt: float) -> float:
    """Ball speed after one cycle of rolling drag, capped at ``ball_max_speed``."""
    speed = min(speed, physics.ball_max_speed)
    return max(0.0, speed * math.exp(-physics.ball_linear_drag * dt) - physics.ball_rolling_decel * dt)


def roll_distance(speed: float, physics: PhysicsConfig) -> float:
    """Distance (m) a free ball launched at ``speed`` rolls under the per-cycle drag model."""
    dt, total = physics.cycle_s, 0.0
    speed = min(speed, physics.ball_max_speed)
    while speed > 0.0:
        total += speed * dt
        speed = rolled_speed(speed, physics, dt)
    return total


def wrap_angle(angle: np.ndarray | float) -> np.ndarray | float:
    """Wrap radians to [-pi, pi)."""
    return (np.asarray(angle) + np.pi) % (2 * np.pi) - np.pi
