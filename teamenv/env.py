# Over 500 lines because the class docstring is the env's API reference (every action and
# observation entry of both modes and formats, rewards, scenarios, infos, timing: ~95 lines)
# and the caller's actions are checked here, next to the API they enter by.
"""The PettingZoo ParallelEnv: a thin shell over ``teamenv.sim.Simulation``.

It checks the caller's arguments and actions, steps the simulation and returns observations,
rewards, terminations and infos. The team plugins that drive whole sides are hosted by
``teamenv.team_host``; rewards come from ``teamenv.rewards`` and infos from ``teamenv.infos``.
"""

from __future__ import annotations

import time
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from pettingzoo import ParallelEnv

import locomotion
from teamenv import spaces as tspaces
from teamenv.actions import ActionParser
from teamenv.capabilities import DEFAULT_LOCOMOTION_PROFILE
from teamenv.config import PerceptionConfig, PhysicsConfig, RulesConfig, build_config
from teamenv.errors import ActionError, ConfigError, value_repr
from teamenv.field import FieldSpec, field_preset
from teamenv.infos import step_infos
from teamenv.lazy import LazyObservations
from teamenv.observation_mode import OBSERVATION_MODES, ObservationMode
from teamenv.rewards import CycleRewards, RewardFn, reward_weights
from teamenv.rewards import RewardInput as RewardInput  # its old home, for reward_fn authors
from teamenv.scenarios import Scenario, ScenarioRun, get_scenario
from teamenv.sim.perception import ObservationRows
from teamenv.sim.simulation import SIM_PHASES, Commands, CycleReport, Simulation
from teamenv.team_host import TeamHost
from teamenv.teams import SIDES, team_context

#: Keys of ``SoccerParallelEnv.timings()``, in the order of a cycle (see its docstring).
TIMING_PHASES = ("actions", "team_left", "team_right", *SIM_PHASES, "other")


def seed_children(seed: int | None) -> list[np.random.SeedSequence]:
    """The generators' seeds of an episode reset with ``seed``, numbered: the env's (physics,
    beams), the left and the right team's, vision's, a scenario's, the say channel's (arrival
    order, loss). The first three are what they were before vision existed; each later one
    has its own, so what a team says never moves the draws of physics, and two teams that
    differ only in talk play the same match."""
    return np.random.SeedSequence(seed).spawn(6)


def _team_seed(seq: np.random.SeedSequence) -> int:
    return int(seq.generate_state(1)[0])


def team_seeds(seed: int | None) -> tuple[int, int]:
    """The seeds ``reset(seed)`` gives the left and the right team."""
    _, left, right, *_ = seed_children(seed)
    return _team_seed(left), _team_seed(right)


class SoccerParallelEnv(ParallelEnv):
    """N v N humanoid-like robot soccer, 20 ms per step, as a PettingZoo ``ParallelEnv``.

    Agents are ``left_1..left_N`` and ``right_1..right_N`` (uniform numbers). A side named by a
    team plugin (``left="chaser"``) is driven by that team and is not in ``agents``.

    Actions (``action_format="dict"``, the default), per agent; omitted keys take defaults:
        walk (3,) float: vx, vy (m/s), vturn (rad/s), body frame, within the locomotion
            profile's command range; the body does what its walk model allows.
        kick (2,) float: power in [0, 1] (0 = no kick), direction (rad, body frame).
        beam (3,) float: x in [-length/2, 0], y, rot: a pose in the team frame (own half).
        beam_request: 0 or 1. A beam is carried out only in BeforeKickOff and after a goal.
        say: str, at most the channel's length in its legal characters; "" = silent.
    Actions (``action_format="box"``): a float32 vector in [-1, 1]^9:
        [vx, vy, vturn, kick_power, kick_dir, beam_request, beam_x, beam_y, beam_rot];
        walk entries scale to the profile's command range (asymmetric: -1 is full backward),
        kick_power <= 0 means no kick, kick_dir * pi rad, beam_request > 0 beams,
        beam_x -1..1 maps to -length/2..0, beam_y * width/2, beam_rot * pi. No ``say``.

    Observations (``observation_format="dict"``), team frame (every side attacks +x):
        self (7,): x, y, heading, vx, vy, omega, fallen — absolute in the team frame.
        ball (4,): x, y, vx, vy, relative to self in its body frame.
        teammates, opponents (N, 5): x, y (body frame, relative), relative heading, fallen,
            present; row k is uniform number k + 1.
        play_mode: index into ``teamenv.PLAY_MODES``, team-relative (``_Left`` = own team).
        game (4,): game time (s), half, own score, opponent score.
        heard_text: tuple of K messages heard this cycle ("" = empty slot); slot 0 is the
            agent's own message, then teammate(s), then opponent(s).
        heard (K, 4): present, from self, from a teammate, direction (rad, body frame).
    ``observation_format="box"`` concatenates the numeric parts (play mode one-hot), no texts.

    Observations (``observation_mode="vision"``): the league's restricted vision, profile
    ``vision=`` ("simspark": SimSpark's RestrictedVisionPerceptor; "mj": RCSSServerMJ 0.2.1)
    with ``perception=`` overrides (``teamenv.PerceptionConfig``). No own pose; polar
    sightings ``present, distance (m), azimuth (rad, + left), elevation (rad, + up)`` from a
    camera ``camera_height_m`` above the agent looking along its heading (the fixed head),
    team frame, a new look every ``update_period_cycles`` (nothing seen on other cycles). Dict:
        landmarks (K, 4): rows in ``teamenv.landmarks.landmarks(field, kind)`` order.
        ball (4,): present, distance, azimuth, elevation.
        teammates, opponents (N, 4): row k is uniform number k + 1 (own row never present).
        lines (L, 7): present, d1, az1, el1, d2, az2, el2: the field lines of
            ``teamenv.landmarks.field_lines(field)`` clipped to the horizontal cone
            (L = 0 rows when the profile has no lines, as ``mj``).
        vision (2,): fresh (1 on an update cycle), cycles since the last update.
        counts (4,): landmarks, players and lines seen, ball seen (0/1).
        odometry (3,): body-frame dx, dy (m), dpsi (rad) the walk engine believes it made
            this cycle (with its slip and noise).
        gyro (1,): the heading change of this cycle (rad) plus noise.
        body (2,): fallen, head pan (rad; 0: the fixed head).
        play_mode, game, heard_text, heard: as in ``state`` mode.
    ``observation_format="box"``: landmarks, ball, teammates, opponents, lines, vision,
    counts, odometry, gyro, body, play mode one-hot, game, heard, flattened in this order.

    Rewards: +1 to each agent of a team that scores, -1 to the other team. ``reward=`` picks
    weighted terms instead (``teamenv.rewards``: "goal", "ball_progress", "possession", or a
    dict of weights; ``{}`` gives all zeros); ``reward_fn(RewardInput) -> {agent: reward}``
    shapes them last (its ``RewardInput.default`` holds the ``reward=`` result when both are
    given). Episodes terminate at GameOver; ``max_cycles`` truncates.

    ``scenario=`` (``teamenv.scenarios``) starts every episode in a named situation (e.g.
    "empty_goal", "counter_3v2") with its own end: the end condition terminates, its time
    limit truncates, and the last step's infos hold ``end`` (the reason). With no ``field`` or
    ``team_size`` given the scenario's are used; players it leaves off the pitch are benched
    (``benched_agents``: outside the pitch, idle, never in ``agents``).

    ``caller_agents``: agents of a side named by a team that the caller drives instead (they
    are in ``agents``); the team still sees their observations and its actions for them are
    ignored, so a team plays around the caller's player (``teamenv.single_agent``). ``state()`` is a world-frame vector for centralized
    critics. Infos are empty unless something happened to the agent: ``dropped`` (lenient
    drops of its action), ``beam_refused``, ``message_dropped``, ``goal`` (team that scored).

    ``reset()``/``step()`` return plain ``dict`` subclasses that build their values on first
    use: state-mode Dict observations (``LazyObservations``: each agent's dict when first
    looked up) and infos with message drops (``LazyInfos``: the drop lists on first use).
    Their contents are exactly those of an eager build; pickled or copied they are dicts.

    Bad input raises ActionError/MessageError naming agent, field and value when ``strict``
    (the default); ``strict=False`` drops or clips it instead and reports it in infos.

    Timing: ``timings()`` gives the wall-clock seconds spent in each phase of ``reset()`` and
    ``step()`` (``profile_phases=True``, the default; the accounting costs about a dozen
    ``time.perf_counter()`` calls per step). ``profile_phases=False`` turns it off (all 0).
    """

    metadata = {"name": "teamenv_soccer_v0", "render_modes": ["human", "rgb_array"],
                "render_fps": 50, "is_parallelizable": True}

    def __init__(
        self,
        field: str | FieldSpec | None = None,
        team_size: int | None = None,
        left: str | None = None,
        right: str | None = None,
        left_config: Mapping[str, Any] | None = None,
        right_config: Mapping[str, Any] | None = None,
        *,
        rules: RulesConfig | Mapping[str, Any] | None = None,
        physics: PhysicsConfig | Mapping[str, Any] | None = None,
        observation_mode: str = "state",
        vision: str | None = None,
        perception: PerceptionConfig | Mapping[str, Any] | None = None,
        observation_format: str = "dict",
        action_format: str = "dict",
        channel: str = "simspark",
        locomotion_profile: str = DEFAULT_LOCOMOTION_PROFILE,
        strict: bool = True,
        reward_fn: RewardFn | None = None,
        reward: str | Mapping[str, float] | None = None,
        scenario: str | Scenario | None = None,
        caller_agents: Sequence[str] = (),
        max_cycles: int | None = None,
        team_cycle_budget_s: float | None = None,
        render_mode: str | None = None,
        profile_phases: bool = True,
    ) -> None:
        self.scenario = None if scenario is None else get_scenario(scenario)
        if field is None:
            field = "simspark" if self.scenario is None or self.scenario.field is None \
                else self.scenario.field
        self.field = field_preset(field)
        if team_size is None:
            team_size = self.field.default_team_size if self.scenario is None or \
                self.scenario.team_sizes is None else self.scenario.min_team_size()
        self.team_size = team_size
        if not isinstance(self.team_size, (int, np.integer)) or not 1 <= self.team_size <= 11:
            raise ConfigError(f"team_size: must be an int in 1..11, got {team_size!r}")
        self.team_size = int(self.team_size)
        _choice("observation_mode", observation_mode, OBSERVATION_MODES)
        _choice("observation_format", observation_format, ("dict", "box"))
        _choice("action_format", action_format, ("dict", "box"))
        _choice("render_mode", render_mode, (None, *self.metadata["render_modes"]))
        if max_cycles is not None and (not isinstance(max_cycles, int) or max_cycles < 1):
            raise ConfigError(f"max_cycles: must be a positive int or None, got {max_cycles!r}")
        if reward_fn is not None and not callable(reward_fn):
            raise ConfigError(f"reward_fn: must be callable, got {reward_fn!r}")
        self.rules = build_config(RulesConfig, rules)
        self.physics = build_config(PhysicsConfig, physics)
        #: What the agents observe: the one place the env, sim and teams read the mode from.
        self.obs_mode = ObservationMode.build(observation_mode, vision, perception)
        self.observation_format = observation_format
        self.action_format = action_format
        self.strict = strict
        self.reward_fn = reward_fn
        self.reward_weights = reward_weights(reward)
        self.max_cycles = max_cycles
        self.render_mode = render_mode
        try:
            profile = locomotion.load_profile(locomotion_profile)
        except Exception as exc:
            raise ConfigError(f"locomotion_profile: {exc}") from exc
        try:
            self.sim = Simulation(self.field, self.team_size, self.rules, self.physics, profile,
                                  channel, profile_phases=profile_phases,
                                  obs_mode=self.obs_mode)
        except (KeyError, ValueError) as exc:
            raise ConfigError(f"channel: {exc}") from exc
        self.channel_name = channel
        n = self.team_size
        self._scenario_run = None if self.scenario is None else \
            ScenarioRun(self.scenario, self.field, n)
        self._rewards = CycleRewards(self.reward_weights, reward_fn, n,
                                     float(profile.kick_reach), self.physics.cycle_s)
        self._needs_state = self._rewards.needs_state
        self.player_names = [f"{side}_{k + 1}" for side in SIDES for k in range(n)]
        self._row = {name: i for i, name in enumerate(self.player_names)}

        channel_profile = self.sim.channel.profile
        self.parser = ActionParser(self.field, profile.command_low, profile.command_high,
                                   self.sim.channel, action_format, strict)
        act_space, obs_space = self._spaces(profile)

        #: The team plugins of the sides the caller does not drive, and what the env does
        #: with them (``teamenv.team_host``).
        self.team_host = TeamHost(
            {"left": (left, left_config), "right": (right, right_config)},
            lambda side: team_context(side, n, self.field, profile, self.physics,
                                      channel_profile.name, self.obs_mode,
                                      self.rules.double_touch),
            self._row,
            ActionParser(self.field, profile.command_low, profile.command_high,
                         self.sim.channel, "dict", True),
            team_cycle_budget_s, profile_phases)
        benched = set() if self._scenario_run is None else \
            {self.player_names[i] for i in self._scenario_run.benched}
        #: Agents a scenario leaves off the pitch: idle, outside it, never in ``agents``.
        self.benched_agents = [a for a in self.player_names if a in benched]
        self._bench_rows = np.array([self._row[a] for a in self.benched_agents], dtype=np.intp)
        self.caller_agents = self._check_caller_agents(caller_agents, benched)
        self.team_host.leave_to_caller(self.caller_agents)

        self.possible_agents = [a for a in self.player_names if a not in benched and (
            a.split("_")[0] not in self.teams or a in self.caller_agents)]
        self.agents: list[str] = []
        self._episode_over = True
        self._action_spaces = {a: act_space for a in self.possible_agents}
        self._observation_spaces = {a: obs_space for a in self.possible_agents}
        self._state_space = tspaces.state_space(self.sim.state_size())
        self._obs_all: list[Any] = []
        self._renderer: Any = None
        self.last_report = CycleReport()
        self.profile_phases = bool(profile_phases)
        # float() returns 0.0: with profiling off the clock is never read.
        self._clock = time.perf_counter if self.profile_phases else float
        self.reset_timings()

    def _spaces(self, profile: locomotion.Profile) -> tuple[Any, Any]:
        """Every agent's action and observation space, for the env's formats and mode."""
        channel_profile = self.sim.channel.profile
        if self.action_format == "dict":
            act_space = tspaces.dict_action_space(self.field, profile.command_low,
                                                  profile.command_high, channel_profile)
        else:
            act_space = tspaces.box_action_space()
        if self.obs_mode.is_vision:
            layout = self.sim.vision.layout
            obs_space = tspaces.vision_dict_observation_space(layout, channel_profile) \
                if self.observation_format == "dict" \
                else tspaces.vision_box_observation_space(layout)
        elif self.observation_format == "dict":
            obs_space = tspaces.dict_observation_space(self.team_size, self.sim.heard_slots,
                                                       channel_profile)
        else:
            obs_space = tspaces.box_observation_space(self.team_size, self.sim.heard_slots)
        return act_space, obs_space

    # -- the teams (``team_host``) -----------------------------------------------------------
    @property
    def teams(self) -> dict[str, Any]:
        """The team plugins, by side (left first); a side the caller drives has none."""
        return self.team_host.teams

    @property
    def team_agents(self) -> dict[str, list[str]]:
        """The agents of each team's side, by side."""
        return self.team_host.agents

    @property
    def team_time_s(self) -> dict[str, float]:
        """Seconds each team's ``act()`` calls took, by side (not zeroed by
        ``reset_timings``)."""
        return self.team_host.time_s

    @property
    def team_cycle_budget_s(self) -> float | None:
        """A team whose ``act()`` takes longer faults as "too_slow" (None: no budget)."""
        return self.team_host.cycle_budget_s

    @property
    def acting_side(self) -> str | None:
        """The side whose team's ``act()`` runs now, else None (who stalled a match)."""
        return self.team_host.acting_side

    # -- the observation mode (``obs_mode``) ------------------------------------------------
    @property
    def observation_mode(self) -> str:
        """"state" or "vision" (``obs_mode.name``)."""
        return self.obs_mode.name

    @property
    def vision(self) -> str | None:
        """The vision profile's name in ``vision`` mode, else None (``obs_mode.vision``)."""
        return self.obs_mode.vision

    @property
    def perception(self) -> PerceptionConfig | None:
        """The camera of ``vision`` mode, else None (``obs_mode.perception``)."""
        return self.obs_mode.perception

    # -- timing ----------------------------------------------------------------------------
    def timings(self) -> dict[str, float]:
        """Wall-clock seconds spent in each phase since construction or ``reset_timings()``,
        summed over every ``reset()`` and ``step()`` call. Keys (``TIMING_PHASES``, then
        ``total``):

        - ``actions``: validating and converting the caller's and the teams' actions;
        - ``team_left``, ``team_right``: that team plugin's ``act()`` and ``reset()``
          (0 for a side driven by the caller);
        - ``beam``, ``locomotion``, ``kick``, ``physics`` (pymunk world step and body I/O),
          ``referee``, ``comms`` (say channel delivery): the simulation's cycle;
        - ``perception``: building every agent's observation (arrays and dicts);
        - ``other``: the rest of ``reset()``/``step()`` (rewards, infos, state, bookkeeping);
        - ``total``: the whole time inside ``reset()`` and ``step()``; the phases add up to it.

        All values are 0 when the env was made with ``profile_phases=False``.
        """
        out = dict.fromkeys(TIMING_PHASES, 0.0)
        out.update(self._phase_s)
        for phase_s in (self.team_host.phase_s, self.sim.phase_s):
            for phase, seconds in phase_s.items():
                out[phase] += seconds
        out["other"] = max(0.0, self._total_s - sum(out.values()))
        out["total"] = self._total_s
        return out

    def reset_timings(self) -> None:
        """Zero the per-phase accounting of ``timings()`` (``team_time_s`` is kept)."""
        self._phase_s = {"actions": 0.0, "perception": 0.0}
        self._total_s = 0.0
        self.team_host.reset_timings()
        self.sim.reset_timings()

    # -- PettingZoo API --------------------------------------------------------------------
    def observation_space(self, agent: str):
        return self._observation_spaces[self._check_agent(agent)]

    def action_space(self, agent: str):
        return self._action_spaces[self._check_agent(agent)]

    @property
    def state_space(self):
        return self._state_space

    def reset(self, seed: int | None = None, options: dict | None = None):
        """Start a match. ``options`` is accepted for the PettingZoo API and not used: every
        setting of the env is a constructor argument (checked there)."""
        del options
        start = self._clock()
        try:
            return self._reset(seed)
        finally:
            self._total_s += self._clock() - start

    def _reset(self, seed: int | None):
        env_seq, team_left_seq, team_right_seq, vision_seq, scenario_seq, channel_seq = \
            seed_children(seed)
        team_seqs = (team_left_seq, team_right_seq)
        self.np_random = np.random.default_rng(env_seq)
        self.sim.reset(self.np_random, np.random.default_rng(vision_seq),
                       np.random.default_rng(channel_seq))
        if self._scenario_run is not None:
            self._scenario_run.start(self.sim, np.random.default_rng(scenario_seq))
        self.end_reason: str | None = None
        # The k-th team gets the k-th team seed: a lone right team gets the left one.
        self.team_host.reset([_team_seed(seq) for seq in team_seqs[:len(self.teams)]])
        self.agents = list(self.possible_agents)
        self._episode_over = False
        self.last_report = CycleReport()
        self._prev_state = self.sim.global_state() if self._needs_state else None
        self._refresh_observations()
        observations = self._agent_observations()
        infos = {a: {} for a in self.agents}
        return observations, infos

    @property
    def episode_over(self) -> bool:
        """True before the first reset and once the match has terminated or been truncated
        (also when both sides are teams and ``agents`` is always empty)."""
        return self._episode_over

    def step(self, actions: Mapping[str, Any]):
        start = self._clock()
        try:
            return self._step(actions, start)
        finally:
            self._total_s += self._clock() - start

    def _step(self, actions: Mapping[str, Any], start: float):
        clock = self._clock
        if self._episode_over:
            raise ActionError("step() called on a finished episode; call reset() first")
        if not isinstance(actions, Mapping):
            raise ActionError(f"actions: expected a dict keyed by agent name, got {type(actions)}")
        dropped: dict[str, list[str]] = {}
        agent_set = set(self.agents)
        # Exactly one action per agent (the usual case): nothing unknown, nothing missing.
        exact = len(actions) == len(agent_set) and actions.keys() == agent_set
        unknown = [] if exact else [a for a in actions if a not in agent_set]
        if unknown:
            why = ("benched by the scenario" if unknown[0] in self.benched_agents else
                   "driven by a team plugin" if any(
                       isinstance(a, str) and a.split("_")[0] in self.teams for a in unknown)
                   else "not an agent of this env")
            self._agent_problem(unknown[0], f"unknown agent {value_repr(unknown[0])} ({why}); "
                                f"agents are "
                                f"{self.agents[:3]}...", dropped)
        missing = [] if exact else [a for a in self.agents if a not in actions]
        if missing:
            self._agent_problem(missing[0], f"agent {missing[0]!r}: no action given (missing "
                                f"agents: {missing}); lenient mode uses the idle action", dropped)
        cmd = Commands.idle(self.sim.n)
        given = list(self.agents) if exact else [a for a in self.agents if a in actions]
        self.parser.fill(cmd, [self._row[a] for a in given], given, [actions[a] for a in given],
                         dropped)
        self._phase_s["actions"] += clock() - start
        self.team_host.act(cmd)
        if self._bench_rows.size:  # benched players stand still, whoever drives them
            self._idle_rows(cmd, self._bench_rows)

        report = self.sim.step(cmd)
        self.last_report = report
        state = self.sim.global_state() if self._needs_state else None
        self._refresh_observations()

        agents = list(self.agents)
        referee = self.sim.referee
        rewards = self._rewards(agents, report, state, self._prev_state, referee.mode,
                                referee.attack_sign)
        self._prev_state = state
        terminated = self.sim.referee.game_over
        truncated = self.max_cycles is not None and self.sim.cycle >= self.max_cycles
        if self._scenario_run is not None:
            terminated, truncated = self._scenario_end(report, terminated, truncated)
        observations = self._agent_observations()
        terminations = dict.fromkeys(agents, terminated)
        truncations = dict.fromkeys(agents, truncated and not terminated)
        infos = step_infos(agents, report, dropped, self.player_names, referee.mode)
        if self.end_reason is not None and (terminated or truncated):
            for a in agents:
                infos[a]["end"] = self.end_reason
        if terminated or truncated:
            self.agents = []
            self._episode_over = True
        if self.render_mode == "human":
            self.render()
        return observations, rewards, terminations, truncations, infos

    def state(self) -> np.ndarray:
        return self.sim.global_state()

    def render(self):
        if self.render_mode is None:
            import gymnasium

            gymnasium.logger.warn("render() called without a render_mode; set render_mode")
            return None
        if self._renderer is None:
            from teamenv.pygame_renderer import PygameRenderer

            self._renderer = PygameRenderer(self.field, self.team_size, self.render_mode)
        return self._renderer.draw(self.sim)

    def close(self) -> None:
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None

    # -- internals -------------------------------------------------------------------------
    def _check_caller_agents(self, caller_agents: Sequence[str], benched: set[str]) -> list[str]:
        if isinstance(caller_agents, str):
            caller_agents = (caller_agents,)
        out = []
        for agent in caller_agents:
            if agent not in self._row:
                raise ConfigError(f"caller_agents: unknown agent {agent!r}; players are "
                                  f"{self.player_names}")
            if agent.split("_")[0] not in self.teams:
                raise ConfigError(f"caller_agents: {agent!r}: its side is not driven by a team "
                                  "(the caller drives it already); name a team with "
                                  f"{agent.split('_')[0]}=...")
            if agent in benched:
                raise ConfigError(f"caller_agents: {agent!r} is benched by scenario "
                                  f"{self.scenario.name!r} (not on the pitch)")
            if agent not in out:
                out.append(agent)
        return out

    def _check_agent(self, agent: str) -> str:
        if agent not in self._action_spaces:
            raise ActionError(f"unknown agent {agent!r}; possible agents are {self.possible_agents}")
        return agent

    def _agent_problem(self, agent: str, message: str, dropped: dict[str, list[str]]) -> None:
        if self.strict:
            raise ActionError(message)
        import warnings

        warnings.warn(message, RuntimeWarning, stacklevel=3)
        # A key that is no str is no agent: listed under its repr (str() of a huge int raises).
        dropped.setdefault(agent if isinstance(agent, str) else value_repr(agent), []).append(
            message)

    def _refresh_observations(self) -> None:
        flat = self.observation_format == "box"
        if self.obs_mode.is_vision:  # one look per cycle, in the forms needed
            team_obs, flats = self.sim.observation_forms(dicts=bool(self.teams) or not flat,
                                                         flat=flat)
            self._obs_all = flats if flat else team_obs
        elif self.teams and flat:
            team_obs = self.sim.observations(flat=False)
            self._obs_all = self.sim.observations(flat=True)
        else:
            self._obs_all = self.sim.observations(flat=flat, lazy=not flat)
            team_obs = self._obs_all
        self.team_host.observe(team_obs)

    def _agent_observations(self) -> dict[str, Any]:
        t0 = self._clock()
        obs_all = self._obs_all
        if isinstance(obs_all, ObservationRows):  # each agent's dict built on first use
            out = LazyObservations(self.agents, obs_all, self._row)
        else:
            out = {a: obs_all[self._row[a]] for a in self.agents}
        self._phase_s["perception"] += self._clock() - t0
        return out

    def _scenario_end(self, report: CycleReport, terminated: bool,
                      truncated: bool) -> tuple[bool, bool]:
        """The scenario's end condition terminates, its time limit truncates; the reason
        (``end_reason``: a ``teamenv.scenarios.END_CONDITIONS`` name, "time_limit" or
        "max_cycles") goes into every agent's info of the last step."""
        reason = self._scenario_run.end_reason(self.sim, report)
        if reason == "time_limit":
            truncated = True
        elif reason is not None:
            terminated = True
        elif terminated:
            reason = "game_over"
        elif truncated:
            reason = "max_cycles"
        self.end_reason = reason
        return terminated, truncated

    @staticmethod
    def _idle_rows(cmd: Commands, rows: np.ndarray) -> None:
        cmd.walk[rows] = 0.0
        cmd.kick_power[rows] = 0.0
        cmd.beam_request[rows] = False
        for row in rows.tolist():
            cmd.say[row] = ""


def _choice(name: str, value: Any, allowed: tuple) -> None:
    if value not in allowed:
        raise ConfigError(f"{name}: must be one of {list(allowed)}, got {value!r}")


def parallel_env(**kwargs: Any) -> SoccerParallelEnv:
    """Make the ParallelEnv (see ``SoccerParallelEnv`` for every option)."""
    return SoccerParallelEnv(**kwargs)
