"""Dynamic role assignment (MMD+MSD², exact; greedy baseline) and voting on role vectors."""

from strategy.positioning.roles.assignment import (
    Assignment,
    RoleAssignmentError,
    assign_roles,
    assign_roles_all,
    distance_matrix,
    solve_greedy,
    solve_mmd_msd2,
)
from strategy.positioning.roles.voting import (
    RoleVoter,
    VotingError,
    is_permutation,
    tally_votes,
    vote_matrix,
)

__all__ = [
    "Assignment", "RoleAssignmentError", "RoleVoter", "VotingError", "assign_roles",
    "assign_roles_all", "distance_matrix", "is_permutation", "solve_greedy", "solve_mmd_msd2",
    "tally_votes", "vote_matrix",
]
