"""The league's pool of frozen snapshots: one ``teamenv-mlp-v1`` policy file per generation.

``snapshots/gen-0000.npz`` is the untrained network, ``gen-0001.npz`` the learner after the
first generation, and so on. Each file holds the network with the action setup folded into
its output layer and the reflexes (kick gate, walk to the ball, action repeat) as entries, so
it plays exactly as the learner acted — through the ``policy`` team for a raw-row file
(``policy:path=...``), through ``teamenv.selfplay.egocentric_team`` for one that reads
egocentric slots, through ``teamenv.selfplay.option_policy_team`` for one that scores an
option team's options (``SnapshotPool.spec`` gives the right one). A file is written to a
temporary name and renamed into place, so a kill leaves either the whole file or none.
"""

from __future__ import annotations

import hashlib
import os
from pathlib import Path

import numpy as np

from teamenv.input_files import read_npz
from teamenv.policy_team import PolicyFileError, save_mlp_policy
from teamenv.selfplay.egocentric_team import (
    TEAM_SPEC_NAME,
    add_egocentric_slots,
    add_option_team,
)
from teamenv.selfplay.learner import PolicyWeights
from teamenv.selfplay.option_policy_team import OPTION_POLICY_SPEC_NAME
from teamenv.selfplay.training_setup import TrainingSetup, kick_gate_m
from teamenv.tournament.spec import TeamSpec, parse_team_spec

SNAPSHOT_DIR = "snapshots"


def snapshot_name(generation: int) -> str:
    """``gen-0003``: the snapshot of ``generation``, its name in ratings and reports."""
    return f"gen-{generation:04d}"


def fold_actions(weights: PolicyWeights, setup: TrainingSetup) -> list[tuple[np.ndarray,
                                                                                np.ndarray]]:
    """The layers with the output layer mapped to the env's 9 Box entries: learned entry k
    is ``fixed + scale_k * output_k``, the others ``fixed`` (the policy file clips to
    [-1, 1] afterwards, as the training env does)."""
    a = setup.actions
    layers = [(np.asarray(w, np.float32), np.asarray(b, np.float32)) for w, b in weights.layers]
    w_out, b_out = layers[-1]
    if w_out.shape[1] != a.size:
        raise PolicyFileError(f"snapshot: the network gives {w_out.shape[1]} outputs, the "
                              f"action setup learns {a.size} entries {list(a.learned)}")
    learned, scale = np.array(a.learned), np.array(a.scale, dtype=np.float32)
    w_full = np.zeros((w_out.shape[0], len(a.fixed)), np.float32)
    w_full[:, learned] = w_out * scale
    b_full = np.array(a.fixed, dtype=np.float32)
    b_full[learned] += b_out * scale
    layers[-1] = (w_full, b_full)
    return layers


def policy_digest(path: str | Path) -> str:
    """A hash of a policy file's arrays (names, dtypes, shapes, bytes), not of its zip
    container: two writes of the same network have the same digest."""
    arrays = read_npz(path, f"snapshot {str(path)!r}", PolicyFileError)
    digest = hashlib.sha256()
    for key in sorted(arrays):
        value = np.ascontiguousarray(arrays[key])
        digest.update(f"{key}|{value.dtype.str}|{value.shape}|".encode())
        digest.update(value.tobytes())
    return digest.hexdigest()


class SnapshotPool:
    """The snapshot files of one league run (``run_dir/snapshots``)."""

    def __init__(self, run_dir: str | Path, setup: TrainingSetup) -> None:
        self.directory = Path(run_dir).resolve() / SNAPSHOT_DIR
        self.setup = setup

    def path(self, generation: int) -> Path:
        return self.directory / f"{snapshot_name(generation)}.npz"

    def exists(self, generation: int) -> bool:
        return self.path(generation).is_file()

    def write(self, generation: int, weights: PolicyWeights) -> str:
        """Write the snapshot of ``generation`` (atomically); its ``policy_digest``."""
        s = self.setup
        self.directory.mkdir(parents=True, exist_ok=True)
        final = self.path(generation)
        temporary = final.with_name(final.name + ".tmp")
        save_mlp_policy(
            temporary, fold_actions(weights, s), activation=weights.activation,
            output_activation=weights.output_activation, observation_mode="state",
            obs_mean=weights.obs_mean, obs_std=weights.obs_std, obs_clip=weights.obs_clip,
            team_size=s.team_size,
            kick_gate_m=kick_gate_m() if s.actions.kick_gate else None,
            walk_to_ball=s.actions.walk_to_ball, action_repeat=s.actions.action_repeat)
        if s.observation == "egocentric":
            add_egocentric_slots(temporary, s.teammate_slots, s.opponent_slots, s.ball_race,
                                 s.game_state)
        if s.option_team:
            add_option_team(temporary, parse_team_spec(s.option_team).label, s.actions.size)
        with temporary.open("rb") as fh:
            os.fsync(fh.fileno())
        os.replace(temporary, final)
        _fsync_directory(self.directory)
        return policy_digest(final)

    def spec(self, generation: int) -> TeamSpec:
        """The team spec that plays the snapshot of ``generation`` (absolute path: tournament
        workers and training envs find it from any working directory)."""
        if self.setup.option_team:
            return TeamSpec.of(OPTION_POLICY_SPEC_NAME, {"path": str(self.path(generation))})
        if self.setup.observation == "egocentric":
            return TeamSpec.of(TEAM_SPEC_NAME, {"path": str(self.path(generation))})
        return TeamSpec.of("policy", {"path": str(self.path(generation))})


def _fsync_directory(directory: Path) -> None:
    """Make a rename in ``directory`` durable (a no-op where directories cannot be opened)."""
    try:
        fd = os.open(directory, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    finally:
        os.close(fd)
