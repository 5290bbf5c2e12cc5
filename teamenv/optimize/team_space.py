"""A team's search space: build the team once (as a match would) and read its config's fields.

teamenv never imports a team's code by name, so the config dataclass is found on the built
team: its ``config`` attribute (``strategy.teams.full.FullTeam.config`` is a
``FullTeamConfig``), whose fields declare their domains with ``search(...)``.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import is_dataclass, replace
from typing import Any

from teamenv.match import MatchOptions
from teamenv.search_space import Domain, SearchSpace, build_search_space, parse_bounds


def team_config(team: str, base_config: Mapping[str, Any], options: MatchOptions) -> Any:
    """The config dataclass instance of ``team`` built with ``base_config`` for ``options``."""
    from teamenv.env import SoccerParallelEnv
    from teamenv.search_space import SearchSpaceError

    env = SoccerParallelEnv(left=team, left_config=dict(base_config), **options.env_kwargs())
    try:
        config = getattr(env.teams["left"], "config", None)
    finally:
        env.close()
    if config is None or not is_dataclass(config):
        raise SearchSpaceError(f"team {team!r}: has no dataclass `config` attribute, so it "
                               "declares no search space (see teamenv.search_space)")
    return config


def team_search_space(team: str, base_config: Mapping[str, Any], options: MatchOptions, *,
                      only: Sequence[str] | None = None,
                      bounds: Sequence[str] | Mapping[str, Domain] = ()) -> SearchSpace:
    """``team``'s search space: its declared domains (or ``only`` these fields), with
    ``bounds`` (``NAME=LOW:HIGH[:log][:int]`` / ``NAME=a|b|c`` texts, or domains) on top."""
    domains = dict(bounds) if isinstance(bounds, Mapping) else dict(map(parse_bounds, bounds))
    config = team_config(team, base_config, options)
    space = build_search_space(config, only=only, bounds=domains, section=f"team {team!r} config")
    _check_ends(team, config, space)
    return space


def _check_ends(team: str, config: Any, space: SearchSpace) -> None:
    """Each parameter's extreme values (a Range's ends, every option of a Choice) must be
    accepted by the config's own validation, so no candidate fails in the middle of a run."""
    from teamenv.search_space import Choice, SearchSpaceError

    for p in space.parameters:
        values = p.domain.options if isinstance(p.domain, Choice) else (p.decode(0.0),
                                                                        p.decode(1.0))
        for value in values:
            try:
                replace(config, **{p.name: value})
            except (ValueError, TypeError) as exc:
                raise SearchSpaceError(f"team {team!r}: the search domain {p.domain.describe()} "
                                       f"of {p.name} reaches {p.name}={value!r}, which the team "
                                       f"rejects: {exc}") from None
