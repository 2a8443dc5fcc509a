"""Results of the continuation of limit cycles (one degree of freedom): the layout of one
degree of freedom of the one branch result, :mod:`numerics.shooting.branch_result`."""

from numerics.shooting.branch_result import (SPECIAL_KINDS, Branch, BranchPoint, SpecialPoint,
                                             branch_point)

__all__ = ["BranchPoint", "SpecialPoint", "Branch", "SPECIAL_KINDS", "branch_point"]
