"""The one continuation driver of branches of periodic orbits in one parameter (Keller 1977;
Doedel, *Lecture notes on numerical analysis of nonlinear equations*, sec. 2).

:class:`Continuation` follows both directions from the first point by
:func:`numerics.shooting.arclength.walk` on a branch problem
(:mod:`numerics.shooting.branch_problem`, whose corrector accepts every point by the one
standard, :mod:`numerics.shooting.acceptance`).  Its cases are one degree of freedom
(:class:`numerics.cycles.continuation.CycleContinuation`) and ``N``
(:class:`numerics.shooting.coupled_branch.CoupledContinuation`); the results are those of
:mod:`numerics.shooting.branch_result`.
"""

from __future__ import annotations

import copy

from numerics.shooting.acceptance import trivial_ok
from numerics.shooting.arclength import FAIL, walk

__all__ = ["Continuation"]


class Continuation:
    """Both directions of a branch of ``prob`` in ``bounds``, per direction into
    :attr:`points` and :attr:`special`.  A case defines ``begin(first)``, ``record(point)``
    (what is kept of a point), ``collapsed(point, error) -> reason`` and, at each accepted
    point ``b`` after ``a``, ``locate(a, b, ds)`` (the special points between them), then
    ``b`` is kept if :meth:`converged`, ``advance(a, b, ds) -> (point, next ds)`` and
    ``end(a, point, ds) -> reason`` (not empty: the direction ends); it may replace
    :meth:`step` and :meth:`at_edge` (work on a point placed at the end of the range; one of
    :data:`~numerics.shooting.arclength.FAIL` raised there drops it)."""

    #: the walk halves a step whose tangent turns below this cosine (above ``turn_above``)
    max_turn, turn_above = 0.9, 0.0
    #: the points that failed :meth:`converged`; whether the branch closed on itself
    dropped, closed = 0, False
    #: whether a direction that starts at the end of the range is followed
    skip_at_bounds = False
    edge_text, full_text, reason_text = ("reached {name} = {edge:g}",
                                         "{n} points (--max-points)", "{why}")

    def __init__(self, prob, bounds: tuple[float, float], *, ds: float, ds_max: float,
                 ds_min: float, max_points: int, period_factor: float, hopf_fraction: float):
        self.prob, self.name, self.bounds = prob, prob.vary, bounds
        self.ds, self.ds_max, self.ds_min, self.max_points = ds, ds_max, ds_min, int(max_points)
        #: the ends: the period beyond this multiple of its start, the amplitude below this
        #: fraction of its largest
        self.period_factor, self.hopf_fraction = period_factor, hopf_fraction
        self.points: list = []
        self.special: list = []

    def converged(self, pt) -> bool:
        """Test 3 of the one standard on a kept point: an autonomous orbit's trivial
        multiplier (the first) within ``TRIVIAL_TOL`` of 1."""
        return self.prob.forced or trivial_ok(pt.mults[:1])

    def step(self, pt, ds: float):
        return self.prob.arc(pt, ds)

    def at_edge(self, a, b) -> None:
        pass

    def follow(self, first, direction: int) -> str:
        """Follow the branch from ``first`` towards ``direction`` (``1``: larger values of
        the parameter); why it ended."""
        pt = copy.copy(first)  # the same point, oriented for this direction
        if pt.tangent[-1] * direction < 0 or (pt.tangent[-1] == 0 and direction < 0):
            pt.tangent = -pt.tangent
        self.points, self.special = [self.record(pt)], []
        self.begin(pt)

        def visit(a, b, ds):
            self.locate(a, b, ds)
            if self.converged(b):
                self.points.append(self.record(b))
            else:
                self.dropped += 1
            b, ds_next = self.advance(a, b, ds)
            return b, ds_next, self.end(a, b, ds)

        def edge(a, b, p):
            if len(self.points) == 1 and p == float(pt.u[-1]):  # the start, at an end of the
                return self.edge_text.format(name=self.name, edge=p)  # range: not twice
            try:
                end = self.prob.at_parameter(a, b, p)
                self.at_edge(a, end)
                self.points.append(self.record(end))
            except FAIL:
                pass
            return self.edge_text.format(name=self.name, edge=p)

        return walk(pt, self.ds, step=self.step, visit=visit, collapsed=self.collapsed,
                    ds_min=self.ds_min, parameter=lambda q: float(q.u[-1]), bounds=self.bounds,
                    at_edge=edge, max_turn=self.max_turn, turn_above=self.turn_above,
                    full=lambda: (self.full_text.format(n=self.max_points)
                                  if len(self.points) >= self.max_points else None))

    def run(self, first, directions, prepend: bool = True) -> tuple[list, list, list]:
        """``(points, special points, reasons)`` through ``first`` in ``directions``: the
        points in the order of the parameter at the start, the special points in the order
        met (a direction towards smaller values reversed and put first, if ``prepend``)."""
        p0, (lo, hi) = float(first.u[-1]), self.bounds
        points, special, reasons = [], [], []
        for d in directions:
            if self.skip_at_bounds and ((d > 0 and p0 >= hi) or (d < 0 and p0 <= lo)):
                continue
            why, side = self.follow(first, d), "larger" if d > 0 else "smaller"
            reasons.append(self.reason_text.format(why=why, side=side, name=self.name))
            pts, found = self.points, self.special
            points = points + (pts[1:] if points else pts) if d > 0 else pts[::-1] + points[1:]
            special = found[::-1] + special if d < 0 and prepend else special + found
            if self.closed:
                break  # the other direction is the same loop
        return points, special, reasons
