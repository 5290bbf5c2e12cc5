"""Formations for any team size: the built-ins for 7 and 11 players, and subsets of them.

The built-in formations are written for 7 v 7 (``mj7v7``) and 11 v 11 (``simspark``). A team
of another size takes the positions of the next larger built-in in a fixed priority order
(goalie, centre forward, central midfield, the centre backs, then the wide players), so a 5-a-side team
keeps a goalie, a forward, a midfielder and two backs. Every formation is scaled to the match's
pitch.
"""

from __future__ import annotations

from functools import lru_cache

from strategy.positioning.formation.builtin import builtin_formation, builtin_formation_names
from strategy.positioning.formation.model import Formation, FormationError
from teamenv.field import FieldSpec

KINDS: tuple[str, ...] = ("attack", "defend", "kickoff-ours", "kickoff-theirs", "setplay-ours",
                          "setplay-theirs")
"""The situations a team has a formation for."""

_PRIORITY = {
    # role indices, most important first (7: G, FW, CM, LB, RB, LM, RM; 11: G, CF, DM,
    # centre backs, central halves, wings/forwards, side backs)
    7: (0, 6, 3, 1, 2, 4, 5),
    11: (0, 10, 5, 1, 2, 6, 7, 8, 9, 3, 4),
}


def team_formation(name: str, n_players: int, field: FieldSpec) -> Formation:
    """The formation ``name`` for ``n_players`` on ``field``.

    ``name`` is a kind (one of ``KINDS``: the built-in of the right size is chosen) or a
    built-in formation name such as ``"11v11-attack"`` (then its size must be ``n_players``,
    or larger: a subset is taken).
    """
    return _cached(name, int(n_players), field)


@lru_cache(maxsize=64)
def _cached(name: str, n: int, field: FieldSpec) -> Formation:
    if not 1 <= n <= 11:
        raise FormationError(f"team formation: n_players must be 1..11, got {n!r}")
    if name in KINDS:
        base_size = 7 if n <= 7 else 11
        name = f"{base_size}v{base_size}-{name}"
    elif name not in builtin_formation_names():
        raise FormationError(f"team formation: unknown formation {name!r}; give a kind "
                             f"{KINDS} or a built-in name {builtin_formation_names()}")
    full = builtin_formation(name, field)
    if full.n_players == n:
        return full
    if full.n_players < n:
        raise FormationError(f"team formation {name!r} has {full.n_players} players, "
                             f"the team has {n}")
    order = _PRIORITY.get(full.n_players)
    keep = sorted(order[:n]) if order else list(range(n))
    return Formation([full.roles[i] for i in keep], full.ball_samples,
                     full.sample_positions[:, keep, :], field=full.field_size,
                     name=f"{name}[{n}]", description=full.description,
                     outside=full.outside)  # type: ignore[arg-type]
