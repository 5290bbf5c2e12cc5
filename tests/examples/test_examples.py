"""Each RL example in examples/ runs its --smoke setting to completion and leaves a loadable model and a return curve."""

from __future__ import annotations

import csv
import importlib
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

pytestmark = pytest.mark.rl
ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"


def run_example(script: str, *args: str) -> str:
    """Runs ``examples/<script> --smoke <args>``; returns its stdout (fails with its output)."""
    done = subprocess.run([sys.executable, str(EXAMPLES / script), "--smoke", *args],
                          capture_output=True, text=True, timeout=540)
    assert done.returncode == 0, f"{script} failed:\n{done.stdout}\n{done.stderr}"
    return done.stdout


def example_module(name: str):
    """Imports ``examples/<name>.py`` (the examples import each other as top-level modules)."""
    sys.path.insert(0, str(EXAMPLES))
    try:
        return importlib.import_module(name)
    finally:
        sys.path.remove(str(EXAMPLES))


def curve_rows(path: Path) -> list[dict[str, str]]:
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    assert rows, f"{path} has no rows"
    for row in rows:
        assert np.isfinite(float(row["mean_episode_return"])), row
    return rows


def test_sb3_supersuit_ppo_trains_and_saves_a_loadable_model(tmp_path):
    pytest.importorskip("stable_baselines3", reason="needs the rl extra: pip install -e '.[rl]'")
    from stable_baselines3 import PPO

    stdout = run_example("sb3_supersuit_ppo.py", "--out", str(tmp_path))
    assert "mean episode return" in stdout
    rows = curve_rows(tmp_path / "returns.csv")
    assert int(rows[-1]["agent_steps"]) == 512
    model = PPO.load(tmp_path / "model.zip", device="cpu")
    env = example_module("soccer_task").make_env(team_size=2, max_cycles=64)
    obs, _ = env.reset(seed=1)
    action, _ = model.predict(obs["left_1"], deterministic=True)
    assert action.shape == env.action_space("left_1").shape
    env.step({a: np.clip(model.predict(obs[a], deterministic=True)[0], -1, 1)
              for a in env.agents})


def test_cleanrl_ppo_trains_and_saves_its_weights(tmp_path):
    torch = pytest.importorskip("torch", reason="needs the rl extra: pip install -e '.[rl]'")
    stdout = run_example("cleanrl_ppo.py", "--out", str(tmp_path))
    assert "mean episode return" in stdout
    rows = curve_rows(tmp_path / "returns.csv")
    assert int(rows[-1]["agent_steps"]) == 2 * 64 * 2  # two rollouts of 64 steps, 2 learners
    weights = torch.load(tmp_path / "agent.pt", weights_only=True)
    assert weights["actor_mean.0.weight"].shape[1] == 60  # the 2 v 2 box observation
    assert weights["actor_mean.4.weight"].shape[0] == 9  # the box action


def test_rllib_multiagent_trains_one_policy_per_team(tmp_path):
    pytest.importorskip("ray.rllib", reason="needs the rl extra: pip install -e '.[rl]'")
    stdout = run_example("rllib_multiagent.py", "--out", str(tmp_path), "--policies",
                         "per-team")
    assert stdout.count("iteration ") >= 2
    rows = curve_rows(tmp_path / "returns.csv")
    assert len(rows) == 2
    assert [k for k in rows[0] if k.startswith("return_")] == ["return_left_team",
                                                                "return_right_team"]
    saved = tmp_path / "checkpoint" / "learner_group" / "learner" / "rl_module"
    assert {"left_team", "right_team"} <= {p.name for p in saved.iterdir()}


def test_rllib_policy_mapping_shares_or_splits_by_team():
    policy_mapping = example_module("rllib_multiagent").policy_mapping
    agents = ["left_1", "left_2", "right_1", "right_2"]
    assert {policy_mapping("shared")(a, None) for a in agents} == {"shared"}
    assert [policy_mapping("per-team")(a, None) for a in agents] == [
        "left_team", "left_team", "right_team", "right_team"]


@pytest.mark.parametrize("scenario", ["keep_away", "one_v_goalie"])
def test_train_scenario_policy_exports_a_policy_the_policy_team_plays(tmp_path, scenario):
    pytest.importorskip("stable_baselines3", reason="needs the rl extra: pip install -e '.[rl]'")
    from teamenv.policy_team import load_policy

    paths = {name: tmp_path / name for name in ("policy.npz", "report.json", "curve.png")}
    stdout = run_example("train_scenario_policy.py", "--scenario", scenario,
                         "--policy", str(paths["policy.npz"]),
                         "--report", str(paths["report.json"]), "--plot", str(paths["curve.png"]))
    assert "learned" in stdout and "chaser" in stdout
    report = json.loads(paths["report.json"].read_text())
    for result in (report["learned"], *report["baselines"].values()):
        assert result["episodes"] == 2 and sum(result["ends"].values()) == 2
        low, high = result["win_rate_95ci_wilson"]
        assert 0.0 <= low <= result["win_rate"] <= high <= 1.0
    assert report["evaluation_seeds"][0] >= 100_000  # held-out seeds, never trained on
    assert report["scenario"] == scenario
    assert set(report["baselines"]) == {"chaser", "untrained", "random"} | \
        ({"reference"} if scenario == "keep_away" else set())
    policy = load_policy(paths["policy.npz"])
    assert policy(np.zeros((3, policy.observation_size), np.float32)).shape == (3, 9)
    # keep_away's file carries the reflexes it was trained with; one_v_goalie's has none
    assert (policy.walk_to_ball, policy.action_repeat) == \
        ((True, 5) if scenario == "keep_away" else (False, 1))
    assert paths["curve.png"].read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_smoke_runs_never_write_over_the_committed_policy_and_figure():
    paths = example_module("train_scenario_policy").output_paths
    committed = paths("keep_away", smoke=False)
    assert committed == (Path("examples/policies/keep_away.npz"),
                         Path("examples/policies/keep_away.json"),
                         Path("docs/rl_learning_curve_keep_away.png"))
    smoke = paths("keep_away", smoke=True)
    assert all(p.parts[0] == "runs" for p in smoke) and not set(smoke) & set(committed)
    assert paths("keep_away", smoke=True, policy=Path("x.npz"))[0] == Path("x.npz")
    ignored = (ROOT / ".gitignore").read_text().splitlines()
    assert "/runs/" in ignored
