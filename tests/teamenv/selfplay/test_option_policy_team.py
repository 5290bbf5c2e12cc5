"""Policy files that score an option team's options, played by
teamenv.selfplay.option_policy_team: files that do not fit are refused with the reason; the
policy team refuses an option file and names the team that plays it. (A snapshot playing the
options its scores rank: test_option_training.py.)"""

from __future__ import annotations

import numpy as np
import pytest

import teamenv
from strategy.decision.field_player import OPTIONS
from teamenv.egocentric import EgocentricObservation
from teamenv.policy_team import PolicyFileError, save_mlp_policy
from teamenv.selfplay.egocentric_team import add_egocentric_slots, add_option_team
from teamenv.selfplay.option_policy_team import OPTION_POLICY_SPEC_NAME


def _option_file(path, scores: np.ndarray, count: int = len(OPTIONS), team="full_options"):
    """A policy file whose network ignores its input and outputs ``scores`` (first Box
    entries) for every row: egocentric slots 4 + 5 (5 v 5), marked for ``team``."""
    size = EgocentricObservation(5, 4, 4, 5).size
    w = np.zeros((size, 9), np.float32)
    b = np.zeros(9, np.float32)
    b[:len(scores)] = scores
    save_mlp_policy(path, [(w, b)], activation="identity", output_activation="identity",
                    action_repeat=5)
    add_egocentric_slots(path, 4, 5)
    if team is not None:
        add_option_team(path, team, count)
    return path


def _env(left: str, path):
    env = teamenv.parallel_env(field="mj7v7", team_size=5, left=left, right="chaser",
                               left_config={"path": str(path)})
    env.reset(seed=11)
    return env


def test_files_that_do_not_fit_are_refused_with_the_reason(tmp_path):
    plain = _option_file(tmp_path / "plain.npz", np.zeros(3), team=None)
    with pytest.raises(Exception, match="its outputs are Box actions"):
        _env(OPTION_POLICY_SPEC_NAME, plain)
    four = _option_file(tmp_path / "four.npz", np.zeros(4), count=4)
    with pytest.raises(Exception, match="scores 4 options; team 'full_options' has 3"):
        _env(OPTION_POLICY_SPEC_NAME, four)
    chaser = _option_file(tmp_path / "chaser.npz", np.zeros(3), team="chaser")
    with pytest.raises(Exception, match="team 'chaser' takes no options"):
        _env(OPTION_POLICY_SPEC_NAME, chaser)
    options = _option_file(tmp_path / "options.npz", np.zeros(3))
    for team in ("policy", "teamenv.selfplay.egocentric_team:EgocentricPolicyTeam"):
        with pytest.raises(Exception, match="scores 3 options for the 'full_options' team.*"
                                            "play it with teamenv.selfplay.option_policy_team"):
            _env(team, options)
    with pytest.raises(PolicyFileError, match="'path'.*is required"):
        teamenv.parallel_env(field="mj7v7", team_size=5, left=OPTION_POLICY_SPEC_NAME,
                             right="chaser").reset(seed=0)
