"""The team plans with its body's real capabilities: kick distance and spread, aim error,
reach, walking speed and get-up time reach it from the locomotion profile through
``TeamContext.body``, and no strategy module keeps a number of its own."""

from __future__ import annotations

import ast
import json
import math
from pathlib import Path

import numpy as np
import pytest

import teamenv
from locomotion import load_profile
from locomotion.profile import PROFILE_DIR
from strategy.behaviours.kick_choice import best_kick, goal_probability
from teamenv.capabilities import DEFAULT_LOCOMOTION_PROFILE, body_capabilities

from .scenes import world

STRATEGY = Path(__file__).resolve().parents[2] / "strategy"


def short_kick_profile(tmp_path: Path) -> Path:
    """``t1_mj`` with a 1.2 m +- 0.3 m kick (a walk-through kick, like the league client's)."""
    data = json.loads((PROFILE_DIR / "t1_mj.json").read_text())
    data["name"] = "t1_short_kick"
    params = data["parameters"]
    for key, value in (("kick_distance_mean", 1.2), ("kick_distance_std", 0.3),
                       ("kick_distance_min", 0.3), ("kick_distance_max", 2.5)):
        params[key]["value"] = value
    path = tmp_path / "t1_short_kick.json"
    path.write_text(json.dumps(data))
    return path


def test_capabilities_are_the_profiles_numbers():
    for name in ("t1_mj", "t1_league", "nao_simspark"):
        p, body = load_profile(name), body_capabilities(name)
        assert body.profile == name
        assert body.kick_distance_mean_m == p.kick_distance_mean
        assert body.kick_distance_sd_m == p.kick_distance_std
        assert body.kick_aim_sd_rad == pytest.approx(p.kick_direction_std)
        assert body.kick_reach == p.kick_reach and body.getup_s == p.getup_duration
        assert body.kick_duration_s == p.kick_duration
        assert body.walk_low == tuple(p.command_low) and body.walk_high == tuple(p.command_high)
        # the real speed follows the tracking table and never beats the envelope
        assert body.forward_speed(100.0) == p.envelope_vx_forward or \
            body.forward_speed(100.0) <= p.envelope_vx_forward
        assert body.forward_speed(0.0) == 0.0
    # the league client's body (benchmarks/calibrate_t1_league.py): its own kick and walk
    league = body_capabilities("t1_league")
    assert league.kick_distance_mean_m == pytest.approx(5.062)
    assert league.forward_speed(1.2) == pytest.approx(1.068)
    assert league.kick_distance_mean_m < body_capabilities("t1_mj").kick_distance_mean_m


@pytest.mark.parametrize("profile", ["t1_mj", "t1_league"])
def test_the_env_gives_the_team_its_profiles_body(profile):
    env = teamenv.parallel_env(left="full", team_size=2, field="mj7v7",
                               locomotion_profile=profile)
    team = env.teams["left"]
    assert team.context.body == body_capabilities(profile)
    assert team.skills.body is team.context.body
    assert team.skills.kick_distance_m == load_profile(profile).kick_distance_mean
    assert team.skills.run_speed == pytest.approx(
        body_capabilities(profile).forward_speed(team.config.nav_max_speed))
    # both side-steps by default; with nav_side_steps="body" only those the walk makes (the
    # league network's does not step left)
    navigation = team.skills.navigation
    assert (navigation.side_step_left, navigation.side_step_right) == (True, True)
    env.close()
    env = teamenv.parallel_env(left="full", left_config={"nav_side_steps": "body"}, team_size=2,
                               field="mj7v7", locomotion_profile=profile)
    navigation = env.teams["left"].skills.navigation
    assert (navigation.side_step_left, navigation.side_step_right) == (
        (False, True) if profile == "t1_league" else (True, True))
    env.close()


def test_the_league_bridge_derives_its_teams_body_the_same_way():
    from teamenv.league.match import LOCOMOTION_PROFILE, team_context

    context = team_context("left", 7)
    assert context.body == body_capabilities(LOCOMOTION_PROFILE)
    assert context.kick_reach == load_profile(LOCOMOTION_PROFILE).kick_reach


def test_the_default_context_is_the_env_default_profile():
    env = teamenv.parallel_env(left="full", team_size=1)
    assert env.teams["left"].context.body == body_capabilities(DEFAULT_LOCOMOTION_PROFILE)
    env.close()


def test_a_shorter_kick_in_the_profile_changes_the_teams_kick_plan(tmp_path):
    """The same scenes, the same team; only the profile's kick differs. With ``t1_mj``
    (8.92 m) the ball player's pass lands more than 4 m away and its kick at the goal from
    6 m is a shot with a real chance; with a 1.2 m kick no pass is planned beyond 1.2 m and
    the same kick at the goal has no chance (the decision names it ``kick_at_goal``)."""
    plans = {}
    for label, profile in (("long", "t1_mj"), ("short", str(short_kick_profile(tmp_path)))):
        env = teamenv.parallel_env(left="full", team_size=3, field="mj7v7",
                                   locomotion_profile=profile)
        team = env.teams["left"]
        c = team.config
        # in our half, their players back at their goal: a race for possession only
        wm = world(position=(-5.3, 0.0), ball=(-5.0, 0.0), teammates=[(3.0, 8.0), (-20.0, 0)],
                   opponents=[(20.0, 0.0), (20.0, 5.0), (20.0, -5.0)], field="mj7v7",
                   team_size=3)
        pass_choice = best_kick(wm, team.skills.body, team.skills.run_speed,
                                c.kick_possession_weight, 0.0, 0.0)
        # 6 m in front of an open goal, lined up: the team's own decision
        shot = world(position=(21.25, 0.0), ball=(21.5, 0.0), me=1,
                     teammates=[(-25.0, 0.0), (0.0, 5.0)], opponents=[(-10.0, 10.0)],
                     field="mj7v7", team_size=3)
        request = team.players["left_2"].decision.play_ball(shot)
        chance = goal_probability(shot, shot.opponent_goal, 1.0, team.skills.body)
        plans[label] = (pass_choice.shot, float(np.hypot(*(pass_choice.target - wm.ball))),
                        request.behaviour, request.kick is not None, chance)
        env.close()
    long_shot, long_length, long_name, long_kicks, long_chance = plans["long"]
    short_shot, short_length, short_name, short_kicks, short_chance = plans["short"]
    assert not long_shot and not short_shot
    assert short_length <= 1.2 + 1e-9 < 4.0 <= long_length
    assert long_kicks and short_kicks
    assert long_name == "shoot" and long_chance > 0.3
    assert short_name == "kick_at_goal" and short_chance < 1e-6


def _numeric(node: ast.AST) -> bool:
    if isinstance(node, ast.UnaryOp):
        node = node.operand
    return isinstance(node, ast.Constant) and isinstance(node.value, (int, float)) \
        and not isinstance(node.value, bool)


def test_no_strategy_module_defines_a_kick_distance_or_body_speed():
    """A grep with the parser: no name about the kick's distance, spread or aim, or the body's
    get-up or walking speed, is given a number anywhere under strategy/ (module constants,
    class fields, defaults); and no profile's kick numbers appear as literals."""
    body_words = ("kick_mean", "kick_sd", "kick_dist", "kick_distance", "aim_sigma", "aim_sd",
                  "getup", "get_up", "walk_speed", "fallen_penalty_s", "kicker_busy")
    literals = set()
    for name in ("t1_mj", "t1_league", "nao_simspark", "t1_lipm"):
        p = load_profile(name)
        literals |= {round(p.kick_distance_mean, 2), round(p.kick_distance_std, 2),
                     round(p.kick_direction_std, 3)}
    offenders = []
    for path in sorted(STRATEGY.rglob("*.py")):
        tree = ast.parse(path.read_text(), filename=str(path))
        for node in ast.walk(tree):
            targets: list[tuple[str, ast.AST | None]] = []
            if isinstance(node, ast.Assign):
                for t in node.targets:
                    for n in ast.walk(t):
                        if isinstance(n, ast.Name):
                            targets.append((n.id, node.value))
            elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
                targets.append((node.target.id, node.value))
            elif isinstance(node, ast.arguments):
                args = node.posonlyargs + node.args
                for a, d in zip(args[len(args) - len(node.defaults):], node.defaults, strict=True):
                    targets.append((a.arg, d))
                for a, d in zip(node.kwonlyargs, node.kw_defaults, strict=True):
                    targets.append((a.arg, d))
            for name, value in targets:
                if value is None or not any(w in name.lower() for w in body_words):
                    continue
                values = value.elts if isinstance(value, ast.Tuple) else [value]
                if any(_numeric(v) for v in values):
                    offenders.append(f"{path.relative_to(STRATEGY.parent)}:{node.lineno} {name}")
            if isinstance(node, ast.Constant) and isinstance(node.value, float) \
                    and any(math.isclose(node.value, x) for x in literals):
                offenders.append(f"{path.relative_to(STRATEGY.parent)}:{node.lineno} "
                                 f"literal {node.value}")
    assert not offenders, offenders


def test_a_team_asks_for_no_kick_its_body_cannot_start():
    """The league T1 kicks only near its heading (``t1_league``'s ``kick_max_angle``): with
    the ball at its feet and the goal 2 rad off its heading, the team walks round the ball instead of
    asking for the kick, which it asks for with the env's omnidirectional body."""
    from strategy.behaviours.ball import kick_to
    from strategy.behaviours.skills import Skills
    from teamenv.field import field_preset
    from tests.strategy.scenes import world

    heading = 2.0                                          # the goal 2 rad to the right
    wm = world(position=(0.0, 0.0), heading=heading, field="mj7v7",
               ball=(0.3 * math.cos(heading), 0.3 * math.sin(heading)))
    goal = (field_preset("mj7v7").half_length, 0.0)
    league = Skills(field_preset("mj7v7"), body_capabilities("t1_league"), kick_max_angle=3.1)
    env_body = Skills(field_preset("mj7v7"), body_capabilities("t1_mj"), kick_max_angle=3.1)
    assert league.kick_max_angle == load_profile("t1_league").kick_max_angle < 3.1
    assert env_body.kick_max_angle == 3.1              # the strategy's own choice, narrower
    assert kick_to(wm, goal, env_body).kick is not None
    assert kick_to(wm, goal, league).kick is None
