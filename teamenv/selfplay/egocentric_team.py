"""Policy files that read egocentric player slots, and the team that plays them.

A ``teamenv-mlp-v1`` file (``teamenv.policy_team``) whose network was trained on
``teamenv.egocentric.EgocentricObservation`` rows carries two more integer entries,
``egocentric_teammates`` and ``egocentric_opponents`` (the slot counts). ``load_policy`` reads
such a file as it reads any other (it ignores entries it does not know), but the ``policy``
team would hand the network the env's raw rows; ``EgocentricPolicyTeam`` puts the transform
in between. It plays files without the two entries exactly as the ``policy`` team does, so
it can stand for both. As a team spec (it is not a registered name)::

    teamenv.selfplay.egocentric_team:EgocentricPolicyTeam:path=snapshots/gen-0003.npz

Because the slots do not depend on the team size, an egocentric file plays any team size.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

import comms
from teamenv.egocentric import EgocentricObservation
from teamenv.input_files import read_npz
from teamenv.policy_team import MLPPolicy, PolicyFileError, PolicyTeam, load_policy
from teamenv.policy_team.mlp_file import OPTION_COUNT_KEY, OPTION_TEAM_KEY
from teamenv.team_config import team_config
from teamenv.teams import TeamContext

#: The team spec name of ``EgocentricPolicyTeam`` (``module:Class``).
TEAM_SPEC_NAME = "teamenv.selfplay.egocentric_team:EgocentricPolicyTeam"
SLOT_KEYS = ("egocentric_teammates", "egocentric_opponents")
#: A file whose rows end with the ball-race columns (``teamenv.egocentric``) says so here.
BALL_RACE_KEY = "egocentric_ball_race"
#: A file whose rows leave out the game state (clock, half, score) says so here.
GAME_STATE_KEY = "egocentric_game_state"


def add_egocentric_slots(path: str | Path, teammates: int, opponents: int,
                         ball_race: bool = False, game_state: bool = True) -> Path:
    """Mark the policy file ``path`` as reading ``teammates`` + ``opponents`` egocentric
    slots, the ball-race columns when ``ball_race``, no game-state columns unless
    ``game_state`` (rewrites it with the entries added)."""
    path = Path(path)
    arrays = read_npz(path, f"policy file {str(path)!r}", PolicyFileError)
    arrays[SLOT_KEYS[0]] = np.asarray(int(teammates))
    arrays[SLOT_KEYS[1]] = np.asarray(int(opponents))
    if ball_race:
        arrays[BALL_RACE_KEY] = np.asarray(True)
    if not game_state:
        arrays[GAME_STATE_KEY] = np.asarray(False)
    with path.open("wb") as fh:  # a file object: numpy would append .npz to a bare name
        np.savez(fh, **arrays)
    return path


def egocentric_slots(path: str | Path) -> tuple[int, int] | None:
    """The (teammates, opponents) slot counts of a policy file, None for a raw-row file."""
    arrays = read_npz(path, f"policy file {str(path)!r}", PolicyFileError)
    if not any(key in arrays for key in SLOT_KEYS):
        return None
    if not all(key in arrays for key in SLOT_KEYS):
        raise PolicyFileError(f"policy file {str(path)!r}: give both {SLOT_KEYS} or neither")
    try:
        counts = tuple(int(arrays[key]) for key in SLOT_KEYS)
    except (TypeError, ValueError) as exc:
        raise PolicyFileError(f"policy file {str(path)!r}: {SLOT_KEYS}: {exc}") from None
    if min(counts) < 0:
        raise PolicyFileError(f"policy file {str(path)!r}: {SLOT_KEYS} must be >= 0, got "
                              f"{counts}")
    return counts[0], counts[1]


def add_option_team(path: str | Path, team: str, options: int) -> Path:
    """Mark the policy file ``path`` as scoring ``options`` options for ``team`` (a team
    spec; ``teamenv.policy_team.mlp_file``'s ``option_team`` entries): rewrites it."""
    path = Path(path)
    arrays = read_npz(path, f"policy file {str(path)!r}", PolicyFileError)
    arrays[OPTION_TEAM_KEY] = np.asarray(str(team))
    arrays[OPTION_COUNT_KEY] = np.asarray(int(options))
    with path.open("wb") as fh:
        np.savez(fh, **arrays)
    return path


class EgocentricPolicy:
    """A policy file's network fed egocentric rows: ``policy(raw_rows) -> actions``.

    Offers what ``PolicyTeam`` uses of an ``MLPPolicy`` (``network_actions``, ``gate``,
    ``action_repeat``, ``observation_mode``); its ``observation_size`` is None because the
    raw row length (which the team checks) depends on the team size and the transform checks
    it itself. The reflexes read the raw rows (the ball's columns are the same in both).
    """

    def __init__(self, network: MLPPolicy, transform: EgocentricObservation) -> None:
        if network.observation_size != transform.size:
            raise PolicyFileError(f"policy {network.source}: takes {network.observation_size} "
                                  f"values, its egocentric slots give {transform.size}")
        self.network, self.transform = network, transform
        self.observation_mode = network.observation_mode
        self.observation_size = None
        self.action_repeat = network.action_repeat
        self.source = network.source

    def network_actions(self, obs_batch: np.ndarray) -> np.ndarray:
        return self.network.network_actions(self.transform(obs_batch))

    def gate(self, obs_batch: np.ndarray, actions: np.ndarray) -> np.ndarray:
        return self.network.gate(obs_batch, actions)

    def __call__(self, obs_batch: np.ndarray) -> np.ndarray:
        return self.gate(obs_batch, self.network_actions(obs_batch))


def egocentric_policy(path: str | Path, context: TeamContext,
                      option_team: str | None = None) -> EgocentricPolicy:
    """The egocentric policy file ``path`` (``option_team``: the team a file that scores
    options is read by) fed the egocentric rows of the env ``context`` describes."""
    slots = egocentric_slots(path)
    if slots is None:
        raise PolicyFileError(f"policy file {str(path)!r}: no egocentric slots "
                              f"({SLOT_KEYS})")
    if context.observation_mode != "state":
        raise PolicyFileError(f"policy file {str(path)!r}: egocentric slots read state-mode "
                              f"observations; the env uses {context.observation_mode!r}")
    heard = int(comms.get_profile(context.channel).max_heard)
    arrays = read_npz(path, f"policy file {str(path)!r}", PolicyFileError)
    transform = EgocentricObservation(context.team_size, heard, *slots,
                                      ball_race=bool(arrays.get(BALL_RACE_KEY, False)),
                                      game_state=bool(arrays.get(GAME_STATE_KEY, True)))
    return EgocentricPolicy(load_policy(path, option_team=option_team), transform)


@dataclass(frozen=True)
class EgocentricPolicyTeamConfig:
    """``path``: a ``teamenv-mlp-v1`` file, with or without egocentric slots."""

    path: str | Path | None = None


class EgocentricPolicyTeam:
    """Every agent of a side driven by one policy file, through its egocentric slots when
    the file has them (``add_egocentric_slots``), else exactly as the ``policy`` team."""

    def __init__(self, context: TeamContext, **config: Any) -> None:
        options = team_config("egocentric policy", EgocentricPolicyTeamConfig, config,
                              error=PolicyFileError)
        if options.path is None:
            raise PolicyFileError(f"egocentric policy team ({context.side}): 'path' (a "
                                  f"policy file) is required")
        if egocentric_slots(options.path) is None:
            self.team = PolicyTeam(context, path=options.path)
            return
        self.team = PolicyTeam(context, policy=egocentric_policy(options.path, context))

    def reset(self, seed: int) -> None:
        self.team.reset(seed)

    def act(self, observations):
        return self.team.act(observations)
