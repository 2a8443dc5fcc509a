"""Look-ups in the paper's error maps (:mod:`numerics.paper.validity`,
:mod:`numerics.paper.methods`) shared by their test modules (not tests themselves)."""

from __future__ import annotations


def point_at(grid_map, mu: float, Delta: float):
    """The point of ``grid_map`` (a validity or methods map) at ``mu`` and ``Delta``."""
    return next(p for p in grid_map.points
                if p.params["mu"] == mu and p.params["Delta"] == Delta)
