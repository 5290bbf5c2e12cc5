"""Every agent's ``Perception`` of a LocalServer cycle computed straight from the simulation:
rcsssmj 0.2.1's ``generate_perceptions`` with the same arithmetic, without its objects.

The server builds each agent's perception objects in Python (a sensor looked up by name, a
detection object per seen marker), then we read them (``teamenv.league.local_perception``)
or, on the wire, the text they encode to. ``LocalPerceiver`` does the server's computation
on whole arrays and fills our ``Perception`` directly, with the values the wire text carries,
bit for bit:

* the same NumPy operations in the same order on the same values: degrees, ``trunc2`` /
  ``trunc3`` (``trunc(x * 100) / 100``), all element by element (exact IEEE operations, so
  one array for all agents gives each value what the server's per-agent arrays give); the
  camera transform, ``atan2``, ``asin`` and norm per agent on arrays of the server's own
  shapes and layouts (NumPy's vectorised ``atan2`` may round an element differently
  depending on where it falls in an array);
* the hearing model's random draws (rcsssmj draws from NumPy's global generator, which
  ``LocalServer`` swaps for its own) in the server's order, with the server's expressions;
* the parser's conversions (``local_perception``): floats as the text reads them, degrees
  to radians by the parser's expressions, dicts filled in the wire's order.

Anything the text path would read differently or refuse (a non-finite value, an empty heard
message, a name that is no atom) raises ``Unhandled``; the caller then restores NumPy's
global generator (some draws may have been made) and runs the server's own
``generate_perceptions`` for the cycle, whose text decides (``LocalServer`` does). It mirrors rcsssmj 0.2.1 (``SUPPORTED_RCSSSMJ``); with another
version LocalServer uses rcsssmj's own generation. ``tests/teamenv/league/
test_league_local_perceiver.py`` compares it with the wire text on every cycle of matches.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .local_perception import _ATOM, _PLAYER_RESERVED, _SEE_RESERVED, _game_state, _Unhandled
from .perception import Heard, JointState, Perception, PlayerSighting, Polar, Vision

#: the rcsssmj release whose ``generate_perceptions`` this mirrors
SUPPORTED_RCSSSMJ = "0.2.1"
_RAD = math.pi / 180.0
_radians = math.radians
#: the server's field of view (deg, half-angles)
HALF_HORIZONTAL, HALF_VERTICAL = 60, 60

Unhandled = _Unhandled


def supported() -> bool:
    """Whether the installed rcsssmj is the release this mirrors."""
    from importlib.metadata import version

    return version("rcsssmj") == SUPPORTED_RCSSSMJ


def _trunc2(v: np.ndarray) -> np.ndarray:
    return np.trunc(v * 100) / 100.0


def _trunc3(v: np.ndarray) -> np.ndarray:
    return np.trunc(v * 1000) / 1000.0


def _atom(name: str) -> str:
    if not _ATOM.fullmatch(name):
        raise Unhandled
    return name


class _Plan:
    """Where each agent's values lie in the simulation's arrays (one compiled world)."""

    def __init__(self, sim: Any, agents: list) -> None:
        import mujoco

        model = sim.mj_model
        self.model, self.data = model, sim.mj_data
        self.agents = agents
        kinds = mujoco.mjtSensor
        # vector sensors: the row's list of names and how many values each one reads
        vectors = {kinds.mjSENS_GYRO: ("gyro", 3), kinds.mjSENS_ACCELEROMETER: ("acc", 3),
                   kinds.mjSENS_FRAMEQUAT: ("quat", 4), kinds.mjSENS_FRAMEPOS: ("pos", 3)}
        self.rows: list[dict[str, Any]] = []
        keys = ("jpos", "jvel", "gyro", "acc", "quat", "pos")
        adrs: dict[str, list[int]] = {k: [] for k in keys}
        for agent in agents:
            prefix = agent.agent_id.prefix
            row: dict[str, Any] = {"joint_names": [], "n_jvel": 0, "gyro": [], "acc": [],
                                   "quat": [], "pos": []}
            for spec in agent.spec.sensors:
                name = _atom(spec.name[len(prefix):])
                i = model.sensor(spec.name).id
                adr = int(model.sensor_adr[i])
                if spec.type == kinds.mjSENS_JOINTPOS:
                    row["joint_names"].append(name)
                    adrs["jpos"].append(adr)
                elif spec.type == kinds.mjSENS_JOINTVEL:
                    row["n_jvel"] += 1
                    adrs["jvel"].append(adr)
                elif spec.type in vectors:
                    key, width = vectors[spec.type]
                    row[key].append(name)
                    adrs[key] += range(adr, adr + width)
                elif spec.type == kinds.mjSENS_TOUCH:
                    raise Unhandled      # not on the T1: left to the server's own code
            self.rows.append(row)
        self.jpos, self.jvel, self.gyro, self.acc, self.quat, self.pos = (
            np.array(adrs[k], dtype=np.intp) for k in keys)
        # vision: the world's marks, then every agent's markers, in the server's order
        world = list(sim._world_markers)
        for _, name in world:
            if _atom(name) in _SEE_RESERVED:
                raise Unhandled
        self.n_world = len(world)
        markers = world + [m for agent in agents for m in agent.markers]
        self.marker_sites = np.array([model.site(site).id for site, _ in markers], dtype=np.intp)
        self.marker_names = [name for _, name in markers]
        self.players = []               # (team, unum, first marker index, marker count)
        k = self.n_world
        for agent in agents:
            for _, name in agent.markers:
                if _atom(name) in _PLAYER_RESERVED:
                    raise Unhandled
            self.players.append((_atom(agent.team_name), int(agent.agent_id.player_no), k,
                                 len(agent.markers)))
            k += len(agent.markers)
        #: each marker's player (team, unum, ...), None for the world's marks
        self.marker_owner: list[tuple | None] = [None] * self.n_world
        for entry in self.players:
            self.marker_owner += [entry] * entry[3]
        self.cameras = [model.site(agent.agent_id.prefix + "camera").id for agent in agents]


class LocalPerceiver:
    """``perceive()``: every agent's ``Perception`` of the cycle the simulation is at (what
    ``generate_perceptions`` and the wire would give), by agent object."""

    def __init__(self, sim: Any) -> None:
        self.sim = sim
        self._plan: _Plan | None = None

    def _plan_for(self, agents: list) -> _Plan:
        plan = self._plan
        sim = self.sim
        if (plan is None or plan.model is not sim.mj_model or plan.data is not sim.mj_data
                or len(plan.agents) != len(agents)
                or any(a is not b for a, b in zip(plan.agents, agents, strict=True))):
            plan = self._plan = _Plan(sim, agents)
        return plan

    def perceive(self) -> dict[Any, Perception]:
        """Raises ``Unhandled`` where the wire text must decide (module doc); the caller
        then restores NumPy's global generator and runs the server's own generation."""
        sim = self.sim
        agents = list(sim.sim_agents)
        plan = self._plan_for(agents)
        data = sim.mj_data
        sd = data.sensordata
        gen_vision = sim.frame_id % sim.vision_interval == 0
        now = float(int(data.time * 100) / 100.0)            # trunc2 of the time
        arrays = (_trunc2(np.degrees(sd[plan.jpos])), _trunc2(np.degrees(sd[plan.jvel])),
                  _trunc2(np.degrees(sd[plan.gyro])), _trunc2(sd[plan.acc]),
                  _trunc3(sd[plan.quat]), _trunc3(sd[plan.pos]))
        if not (math.isfinite(now) and all(np.isfinite(a).all() for a in arrays)):
            raise Unhandled
        jpos, jvel, gyro, acc, quat, pos = (a.tolist() for a in arrays)
        game = Perception()
        _game_state(game, sim._generate_game_state_perception())
        if gen_vision:
            obj_pos = np.ascontiguousarray(data.site_xpos[plan.marker_sites].T, dtype=np.float64)
        out: dict[Any, Perception] = {}
        ij = iv = ig = ia = iq = ip = 0
        for agent, row, camera in zip(agents, plan.rows, plan.cameras, strict=True):
            p = Perception(time=now, game=game.game)
            for name in row["quat"]:
                p.orientations[name] = (quat[iq], quat[iq + 1], quat[iq + 2], quat[iq + 3])
                iq += 4
            for name in row["pos"]:
                p.positions[name] = (pos[ip], pos[ip + 1], pos[ip + 2])
                ip += 3
            for name in row["gyro"]:
                p.gyros[name] = (_radians(gyro[ig]), _radians(gyro[ig + 1]),
                                 _radians(gyro[ig + 2]))
                ig += 3
            for name in row["acc"]:
                p.accelerometers[name] = (acc[ia], acc[ia + 1], acc[ia + 2])
                ia += 3
            names = row["joint_names"]
            n = len(names)
            if n:
                joints = p.joints
                for name, a, v in zip(names, jpos[ij:ij + n], jvel[iv:iv + row["n_jvel"]],
                                      strict=False):
                    joints[name] = JointState(a * _RAD, v * _RAD)
            ij += n
            iv += row["n_jvel"]
            self._hear(p, agent, sim._a_data)
            if gen_vision:
                p.vision = self._see(plan, data, camera, obj_pos)
            out[agent] = p
        return out

    @staticmethod
    def _hear(p: Perception, agent: Any, a_data: Any) -> None:
        """rcsssmj's hearing model for one agent, its expressions as they are."""
        a_sensor = a_data.sensors.get(agent.agent_id.prefix + "hear", None)
        if a_sensor is None or not a_sensor.messages:
            return
        prefix = agent.agent_id.prefix
        n_msgs = len(a_sensor.messages)
        other_msg_mask = [not s.startswith(prefix) for s in a_sensor.sources]
        len_limit_msg_mask = [len(msg) <= 10 for msg in a_sensor.messages]
        noise_volumes = a_sensor.volumes[len_limit_msg_mask]
        if len(noise_volumes) <= 3:
            loss_msg_mask = np.full(n_msgs, True)
        else:
            noise_floor = np.sort(noise_volumes)[-3]
            loss_msg_mask = np.random.rand(n_msgs) < np.clip(
                np.log(a_sensor.volumes * (np.e - 1) / noise_floor + 1), 0, 1)
        msg_indices = np.nonzero(loss_msg_mask & other_msg_mask & len_limit_msg_mask)[0]
        azimuths = np.degrees(np.atan2(a_sensor.origins[1, msg_indices],
                                       a_sensor.origins[0, msg_indices])).astype(np.int64)
        _atom(a_sensor.name[len(prefix):])
        heard: list[Heard] = []
        for azimuth, idx in zip(azimuths.tolist(), msg_indices.tolist(), strict=True):
            message = a_sensor.messages[idx]
            if not message:
                raise Unhandled                 # "(az )": the parser refuses it
            heard.append(Heard(_radians(float(azimuth)), bytes(message)))
        p.heard = heard

    @staticmethod
    def _see(plan: _Plan, data: Any, camera: int, obj_pos: np.ndarray) -> Vision:
        """rcsssmj's ideal camera for one agent, on the server's arrays."""
        camera_pos = data.site_xpos[camera].astype(np.float64)
        camera_rot = data.site_xmat[camera].astype(np.float64).reshape((3, 3))
        local_obj_pos = np.matmul(camera_rot.T, obj_pos - camera_pos[:, np.newaxis])
        azimuths = _trunc2(np.degrees(np.atan2(local_obj_pos[1], local_obj_pos[0])))
        distances = np.linalg.norm(local_obj_pos, axis=0)
        elevations = _trunc2(np.degrees(np.asin(local_obj_pos[2] / distances)))
        distances = _trunc2(distances)
        visible = ((azimuths >= -HALF_HORIZONTAL) & (azimuths <= HALF_HORIZONTAL)
                   & (elevations >= -HALF_VERTICAL) & (elevations <= HALF_VERTICAL))
        seen = np.flatnonzero(visible)
        if not (np.isfinite(distances[seen]).all() and np.isfinite(azimuths[seen]).all()
                and np.isfinite(elevations[seen]).all()):
            raise Unhandled
        az, el, d = azimuths.tolist(), elevations.tolist(), distances.tolist()
        names = plan.marker_names
        vision = Vision()
        objects = vision.objects
        seen_list = seen.tolist()
        n_world = plan.n_world
        for i in seen_list:                                   # the marks and the ball
            if i >= n_world:
                break
            objects[names[i]] = Polar(d[i], _radians(az[i]), _radians(el[i]))
        # players with a seen part, in the server's order: the seen indices ascend, and each
        # player's markers lie together in the agents' order
        owner = plan.marker_owner
        player = parts = None
        for i in seen_list:
            if i < n_world:
                continue
            if owner[i] is not player:
                if parts:
                    vision.players.append(PlayerSighting(player[0], player[1], parts))
                player, parts = owner[i], {}
            parts[names[i]] = Polar(d[i], _radians(az[i]), _radians(el[i]))
        if parts:
            vision.players.append(PlayerSighting(player[0], player[1], parts))
        return vision
