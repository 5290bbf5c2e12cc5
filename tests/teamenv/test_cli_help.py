"""The command line documents itself: ``--version``, a help text for every argument of every
command, and a top-level description that lists every command."""

from __future__ import annotations

import argparse
import importlib.metadata

import pytest

import teamenv
from teamenv.cli import build_parser, main


def _walk(parser: argparse.ArgumentParser, path: tuple[str, ...] = ("teamenv",)):
    """(command path, action, help of the command) for every argument in the tree."""
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            helps = {choice.dest: choice.help for choice in action._choices_actions}
            for name, child in action.choices.items():
                yield (*path, name), None, helps.get(name)
                yield from _walk(child, (*path, name))
        else:
            yield path, action, None


def test_every_command_and_argument_has_help():
    missing = []
    commands = 0
    for path, action, command_help in _walk(build_parser()):
        if action is None:
            commands += 1
            if not command_help:
                missing.append(" ".join(path))
        elif not action.help or action.help == argparse.SUPPRESS:
            missing.append(f"{' '.join(path)} {'/'.join(action.option_strings) or action.dest}")
    assert commands >= 15  # match, render, ..., tournament run/table/..., optimize
    assert not missing, f"arguments without help: {missing}"


def test_top_level_description_lists_every_command():
    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    text = parser.format_help()
    for name in sub.choices:
        assert f"\n  {name} " in text, name
    assert "--version" in text


def test_version_prints_the_package_version(capsys):
    with pytest.raises(SystemExit) as info:
        main(["--version"])
    assert info.value.code == 0
    out = capsys.readouterr().out.strip()
    assert out == f"teamenv {teamenv.__version__}"
    assert teamenv.__version__ == importlib.metadata.version("teamenv")


def test_subcommand_usage_names_the_command(capsys):
    with pytest.raises(SystemExit):
        main(["render", "--help"])
    assert capsys.readouterr().out.startswith("usage: teamenv render ")


MATCH_FLAGS = ["--field", "mj7v7", "--team-size", "5", "--half-time", "40", "--halves", "1",
               "--observation", "vision", "--vision", "mj", "--channel", "mj",
               "--locomotion-profile", "t1_league", "--double-touch"]


@pytest.mark.parametrize("command", [["match", "full", "chaser"],
                                     ["tournament", "run", "full", "chaser", "--db", "t.sqlite"],
                                     ["optimize", "full"]])
def test_every_match_playing_command_reads_the_same_match_options(command):
    from teamenv.match import MatchOptions

    args = build_parser().parse_args([*command, *MATCH_FLAGS])
    assert MatchOptions.from_arguments(args) == MatchOptions(
        field="mj7v7", team_size=5, half_time_s=40.0, halves=1, observation_mode="vision",
        vision="mj", channel="mj", locomotion_profile="t1_league", double_touch=True)
    defaults = build_parser().parse_args(command)
    assert MatchOptions.from_arguments(defaults) == MatchOptions()
