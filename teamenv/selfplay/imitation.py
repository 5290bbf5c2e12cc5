"""A warm-started PPO learner: behaviour cloning and DAgger from a scripted teacher, then PPO
in the league (needs the ``rl`` extra).

Why. PPO from a random network did not reach a goal in the demo run's budget (no snapshot of
12 generations scored; ``docs/selfplay.md``): goals are the reward, and a network that cannot
yet walk to the ball and kick it towards the goal never sees one. AlphaStar (Vinyals et al.
2019) starts its league from a network trained by supervised learning on demonstrations; this
learner does the same with a built-in team as the demonstrator.

``ImitationPPOLearner`` is ``PPOLearner`` (``teamenv.selfplay.sb3_learner``: SB3 PPO, the same
network, observations, actions and snapshots) with one change: its first ``train`` call
clones the teacher instead of running PPO, and every later call is plain PPO from there.

The clone (``clone``): ``dagger_rounds`` + 1 rounds of ``steps / (dagger_rounds + 1)``
agent-decisions each in ``TeacherBatchEnv`` (the league's training env with the teacher
watching: the same episodes, opponents drawn from the same PFSP mix). Round 0 plays the
teacher's own actions (behaviour cloning); round r >= 1 plays the network trained on rounds
0..r-1 and records what the teacher would have done in the states the network reaches
(DAgger, Ross, Gordon and Bagnell 2011: the learner is taught to recover from its own
mistakes, which plain cloning never shows it). After each round the actor's mean network is
fitted to all labels so far (squared error in the network's output space, Adam, ``bc_epochs``
passes in minibatches of ``bc_batch``) with the observation normalisation set to the
statistics of the data. The kick entries count only where the kick gate is open (``label_mask``):
elsewhere the env never plays them, and the teacher's "no kick" far from the ball would make
the regression average a step — a feeble kick at the ball (the first clone's: box power
0.0-0.2 where the teacher kicked at 1, and it never scored). The critic is then fitted to the discounted returns of the last
round's episodes (normalised as PPO will normalise them), so that PPO's first advantages are
not measured against an untrained value.

Deterministic: every draw comes from generators seeded by the call's seed (the env episodes,
the minibatch order, torch's initial state via SB3's ``set_random_seed``); torch runs on one
thread. ``save``/``load`` add a flag to PPOLearner's checkpoint (whether the clone is done).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from teamenv.box_layout import KICK_DIRECTION, KICK_POWER, WALK, StateLayout
from teamenv.errors import ConfigError
from teamenv.selfplay.learner import PolicyWeights
from teamenv.selfplay.pfsp import OpponentMix
from teamenv.selfplay.sb3_learner import PPOLearner, _sb3
from teamenv.selfplay.teacher_env import TeacherBatchEnv, parse_teacher
from teamenv.selfplay.training_setup import TrainingSetup

STATE_FILE = "imitation.json"
#: The ball's (rel_x, rel_y) columns: the same in the env's state row and in egocentric slots.
_BALL = StateLayout(0, 0).offsets["ball"][0]
BALL_XY = slice(_BALL, _BALL + 2)


class ImitationPPOLearner(PPOLearner):
    """PPO warm-started by cloning ``teacher`` (module docstring).

    Args (beyond ``PPOLearner``'s):
        teacher: the demonstrator's team spec (``chaser``, ``chaser:all_chase=true``, ...;
            None: ``chaser``); with an option team (``TrainingSetup.option_team``) its own
            rule, which chooses the options it is taught (naming another team is an error).
        dagger_rounds: rounds played by the network after the teacher's own (0: plain
            behaviour cloning).
        bc_epochs, bc_batch, bc_learning_rate: the supervised fit after each round.
        bc_log_std: the Gaussian's log standard deviation after cloning (PPO's exploration
            starts from it).
        value_epochs: passes of the critic's fit to the last round's returns.
    """

    def __init__(self, setup: TrainingSetup, seed: int = 0, teacher: str | None = None,
                 dagger_rounds: int = 2, bc_epochs: int = 30, bc_batch: int = 256,
                 bc_learning_rate: float = 1e-3, bc_log_std: float = -1.5,
                 value_epochs: int = 10, **ppo_options) -> None:
        if setup.option_team:  # the option team's own rule demonstrates its options
            if teacher not in (None, setup.option_team):
                raise ConfigError(f"imitation: with option_team {setup.option_team!r} the "
                                  f"teacher is that team's own rule; got teacher {teacher!r}")
            teacher = setup.option_team
        self.teacher = parse_teacher("chaser" if teacher is None else teacher, setup)
        for name, value in (("dagger_rounds", dagger_rounds), ("bc_epochs", bc_epochs),
                            ("bc_batch", bc_batch), ("value_epochs", value_epochs)):
            if isinstance(value, bool) or not isinstance(value, int) or value < (
                    0 if name in ("dagger_rounds", "value_epochs") else 1):
                raise ConfigError(f"imitation: {name} must be an int >= "
                                  f"{0 if name in ('dagger_rounds', 'value_epochs') else 1}, "
                                  f"got {value!r}")
        if not (isinstance(bc_learning_rate, (int, float)) and bc_learning_rate > 0):
            raise ConfigError(f"imitation: bc_learning_rate must be > 0, got "
                              f"{bc_learning_rate!r}")
        super().__init__(setup, seed=seed, **ppo_options)
        self.dagger_rounds, self.bc_epochs, self.bc_batch = dagger_rounds, bc_epochs, bc_batch
        self.bc_learning_rate, self.bc_log_std = float(bc_learning_rate), float(bc_log_std)
        self.value_epochs = value_epochs
        self.copies = self.batch.copies
        self.cloned = False
        self.clone_log: list[dict] = []

    # -- the league's interface ----------------------------------------------------------
    def train(self, steps: int, opponents: OpponentMix, seed: int) -> PolicyWeights:
        if self.cloned:
            return super().train(steps, opponents, seed)
        self.clone(steps, opponents, seed)
        self.cloned = True
        return self.weights()

    def save(self, directory: Path) -> None:
        super().save(directory)
        (Path(directory) / STATE_FILE).write_text(json.dumps(
            {"cloned": self.cloned, "clone_log": self.clone_log}))

    def load(self, directory: Path) -> None:
        super().load(directory)
        state = json.loads((Path(directory) / STATE_FILE).read_text())
        self.cloned, self.clone_log = bool(state["cloned"]), list(state["clone_log"])

    # -- cloning ---------------------------------------------------------------------------
    def clone(self, steps: int, opponents: OpponentMix, seed: int) -> None:
        """Behaviour cloning and DAgger for ``steps`` agent-decisions in all (see the module
        docstring); ``last_episodes`` and ``clone_log`` say how it went."""
        _, torch = _sb3()
        self.model.set_random_seed(seed)
        rounds = self.dagger_rounds + 1
        env = TeacherBatchEnv(self.setup, opponents, self.teacher, copies=self.copies,
                              seed=seed)
        per_round = max(1, -(-steps // (rounds * env.n_slots)))  # decisions per slot
        rng = np.random.default_rng(np.random.SeedSequence([seed, 1]))
        observations: list[np.ndarray] = []
        labels: list[np.ndarray] = []
        eligible: list[np.ndarray] = []  # option mode: who could be given an option
        episodes: list = []
        try:
            obs = env.reset()
            for r in range(rounds):
                obs_r, labels_r, rewards, dones, eligible_r = [], [], [], [], []
                agreement = []
                for _ in range(per_round):
                    obs_r.append(obs)
                    if env.option_count:  # the rule's choice is known after its first cycle
                        action = None if r == 0 else self.act(obs)
                        obs_next, reward, done, _ = env.step(action)
                        target = env.option_labels()
                        eligible_r.append(env.eligible_slots())
                        if r > 0:  # the share of decisions whose option differs
                            agreement.append(float(np.mean(
                                env.played_options() != target.argmax(axis=1))))
                    else:
                        target = env.teacher_outputs()
                        action = target if r == 0 else self.act(obs)
                        if r > 0:  # on the entries that count (label_mask)
                            mask = self.label_mask(obs, env.gate_m)
                            error = (mask * np.abs(action - target)).sum()
                            agreement.append(error / max(mask.sum(), 1.0))
                        obs_next, reward, done, _ = env.step(action)
                    labels_r.append(target)
                    obs = obs_next
                    rewards.append(reward)
                    dones.append(done)
                observations.append(np.concatenate(obs_r))
                labels.append(np.concatenate(labels_r))
                if eligible_r:
                    eligible.append(np.concatenate(eligible_r))
                x, y = np.concatenate(observations), np.concatenate(labels)
                loss = self._fit_actor(x, y, self.label_mask(x, env.gate_m), rng, torch,
                                       np.concatenate(eligible) if eligible else None,
                                       env.ranked_options)
                self.clone_log.append({
                    "round": r, "played_by": "teacher" if r == 0 else "network",
                    "samples": int(len(x)), "bc_loss": loss,
                    ("option_disagreement_when_played" if env.option_count else
                     "mean_abs_error_when_played"): float(np.mean(agreement)) if agreement
                    else None,
                    "goals_for": int(sum(e.goals_for for e in env.episodes)),
                    "goals_against": int(sum(e.goals_against for e in env.episodes))})
                if r == rounds - 1:
                    self._fit_critic(np.stack(obs_r), np.stack(rewards), np.stack(dones), rng,
                                     torch)
            episodes = list(env.episodes)
        finally:
            env.close()
        self.last_episodes = episodes
        self.model.num_timesteps += steps

    def _normalize(self, x: np.ndarray) -> np.ndarray:
        return self.vec_env.normalize_obs(x).astype(np.float32)

    def label_mask(self, x: np.ndarray, gate_m: float | None) -> np.ndarray:
        """Which label entries count (n, action_size): a kick entry only where the kick gate
        is open (the ball within ``gate_m`` at the decision: anywhere else the env never sees
        the network's kick, and the teacher's "no kick" there would teach the network to
        average a step, a feeble kick at the ball), a walk entry unless the walk is a reflex."""
        a = self.setup.actions
        mask = np.ones((len(x), len(a.learned)), dtype=np.float32)
        if gate_m is not None:
            ball = x[:, BALL_XY]
            open_ = np.hypot(ball[:, 0], ball[:, 1]) <= gate_m
            for k, entry in enumerate(a.learned):
                if entry in (KICK_POWER, KICK_DIRECTION):
                    mask[:, k] = open_
                elif a.walk_to_ball and WALK.start <= entry < WALK.stop:
                    mask[:, k] = 0.0
        return mask

    def _fit_actor(self, x: np.ndarray, y: np.ndarray, mask: np.ndarray,
                   rng: np.random.Generator, torch, eligible: np.ndarray | None = None,
                   ranked: tuple[int, ...] = ()) -> float:
        """Observation statistics from ``x``, then the actor's mean to ``y`` (squared error
        over the entries ``mask`` keeps); the final epoch's mean loss per kept entry.

        With an option team (``eligible``: which rows could be given an option) the rows
        come in teams (``team_size`` consecutive rows: one decision of one env copy) and the
        loss adds, per team and option the team ranks (``ranked``, in order: e.g. the ball,
        then the cover), the cross-entropy of the rule's choice among the eligible players'
        scores for it (``RANK_SCALE`` x the scores as logits; each choice leaves the
        eligible): the team's choice ranks the scores (``options_from_scores``), so
        the fit is taught the ranking, not only each player's own label. Cloning with the
        squared error alone picked the rule's ball player in 84 % of open-play cycles of
        its own play (94 % of the rule's)."""
        rms = self.vec_env.obs_rms
        rms.mean = x.mean(axis=0).astype(np.float64)
        rms.var = x.var(axis=0).astype(np.float64)
        rms.count = float(len(x))
        policy = self.model.policy
        params = [*policy.mlp_extractor.policy_net.parameters(),
                  *policy.action_net.parameters()]
        optimiser = torch.optim.Adam(params, lr=self.bc_learning_rate)
        inputs = torch.as_tensor(self._normalize(x))
        targets = torch.as_tensor(y, dtype=torch.float32)
        weights = torch.as_tensor(mask, dtype=torch.float32)
        loss_value = float("nan")
        size = self.setup.team_size if eligible is not None else 1
        teams = len(x) // size
        free = None if eligible is None else torch.as_tensor(eligible.astype(bool))
        for _ in range(self.bc_epochs):
            order = rng.permutation(teams)
            total, kept = 0.0, 0.0
            for start in range(0, teams, max(1, self.bc_batch // size)):
                chosen = order[start:start + max(1, self.bc_batch // size)]
                idx = torch.as_tensor((chosen[:, None] * size + np.arange(size)).ravel())
                latent = policy.mlp_extractor.forward_actor(
                    policy.extract_features(inputs[idx], policy.pi_features_extractor))
                w = weights[idx]
                out = policy.action_net(latent)
                squared = w * (out - targets[idx]) ** 2
                loss = squared.sum() / w.sum().clamp(min=1.0)
                if free is not None and ranked:
                    loss = loss + _ranking_loss(out, targets[idx], free[idx], size, ranked,
                                                torch)
                optimiser.zero_grad()
                loss.backward()
                optimiser.step()
                total, kept = total + squared.sum().item(), kept + w.sum().item()
            loss_value = total / max(kept, 1.0)
        with torch.no_grad():
            policy.log_std.fill_(self.bc_log_std)
        return loss_value

    def _fit_critic(self, obs: np.ndarray, rewards: np.ndarray, dones: np.ndarray,
                    rng: np.random.Generator, torch) -> None:
        """The critic to the discounted returns (``obs``: (T, n_slots, size); rewards and
        dones (T, n_slots)) of the last round, rewards scaled as VecNormalize will scale
        them; the last unfinished stretch of each slot is left out (no return known)."""
        if self.value_epochs == 0:
            return
        gamma = self.setup.gamma
        steps, slots = rewards.shape
        returns = np.zeros_like(rewards, dtype=np.float64)
        known = np.zeros_like(dones)
        running, ended = np.zeros(slots), np.zeros(slots, dtype=bool)
        for t in range(steps - 1, -1, -1):
            ended = ended | dones[t]
            running = rewards[t] + gamma * running * ~dones[t]
            returns[t], known[t] = running, ended
        if not known.any():
            return
        # VecNormalize divides rewards by the std of the discounted return
        scale = float(np.sqrt(returns[known].var() + self.vec_env.epsilon))
        self.vec_env.ret_rms.mean = 0.0
        self.vec_env.ret_rms.var = scale ** 2
        self.vec_env.ret_rms.count = float(known.sum())
        x = torch.as_tensor(self._normalize(obs[known]))
        target = torch.as_tensor((returns[known] / scale).astype(np.float32))
        policy = self.model.policy
        params = [*policy.mlp_extractor.value_net.parameters(), *policy.value_net.parameters()]
        optimiser = torch.optim.Adam(params, lr=self.bc_learning_rate)
        for _ in range(self.value_epochs):
            order = rng.permutation(len(x))
            for start in range(0, len(x), self.bc_batch):
                idx = torch.as_tensor(order[start:start + self.bc_batch])
                latent = policy.mlp_extractor.forward_critic(
                    policy.extract_features(x[idx], policy.vf_features_extractor))
                loss = torch.nn.functional.mse_loss(policy.value_net(latent).squeeze(-1),
                                                    target[idx])
                optimiser.zero_grad()
                loss.backward()
                optimiser.step()


#: Logits per unit of an option score in the ranking loss (scores are taught as +-0.5, so
#: the rule's choice leads the others by about 5 nats).
RANK_SCALE = 5.0


def _ranking_loss(out, targets, eligible, size: int, ranked: tuple[int, ...], torch):
    """Sum over the ``ranked`` options of the mean cross-entropy, over the teams of a
    minibatch where the rule chose one eligible player for it, of that player among the
    eligible players' scores (those chosen for earlier options left out)
    (``ImitationPPOLearner._fit_actor``)."""
    scores = out.reshape(-1, size, out.shape[1])
    chosen = targets.reshape(-1, size, targets.shape[1]).argmax(dim=2)
    free = eligible.reshape(-1, size).clone()
    losses = []
    for option in ranked:
        target = (chosen == option) & free
        valid = target.sum(dim=1) == 1
        if valid.any():
            logits = (RANK_SCALE * scores[:, :, option]).masked_fill(~free, float("-inf"))
            picked = target[valid].float().argmax(dim=1)
            losses.append(torch.nn.functional.cross_entropy(logits[valid], picked))
        free = free & ~target
    return sum(losses) if losses else out.sum() * 0.0
