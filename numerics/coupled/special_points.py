"""Special points on a branch of periodic orbits of a coupled system, located as AUTO-07p
does: a test function that changes sign between two points, and bisection along the
arclength by the one locator (:func:`numerics.shooting.locate.zero_on_chord`;
:mod:`numerics.coupled.continuation`).

- fold: the parameter component of the tangent;
- period doubling: ``det(Phi + I)`` (a real multiplier through ``-1``);
- Neimark-Sacker (torus): ``prod_{i<j} (lambda_i lambda_j - 1)`` over the non-trivial
  multipliers, kept only where the located pair is complex (a real pair ``lambda, 1/lambda``
  also zeroes it: a neutral saddle, not a bifurcation).
"""

from __future__ import annotations

import numpy as np

from numerics.coupled.branch_result import CoupledSpecialPoint
from numerics.shooting.branch_problem import OrbitPoint, OrbitProblem
from numerics.shooting.locate import zero_on_chord


def _tests(prob: OrbitProblem, pt: OrbitPoint) -> dict[str, float]:
    """The test functions at ``pt``: fold, period doubling, Neimark-Sacker."""
    z = pt.rest
    ns = 1.0
    for i in range(len(z)):
        for j in range(i + 1, len(z)):
            ns *= (z[i] * z[j] - 1.0)
    return {"fold": float(pt.tangent[-1]),
            "period-doubling": float(np.real(np.prod(1.0 + z))),
            "neimark-sacker": float(np.real(ns))}


def _locate(prob: OrbitProblem, a: OrbitPoint, b: OrbitPoint, kind: str, fa: float):
    """The zero of test ``kind`` between ``a`` and ``b`` by the one locator
    (:func:`numerics.shooting.locate.zero_on_chord`)."""
    return zero_on_chord(prob.correct, a, b, lambda pm: _tests(prob, pm)[kind], fa)


def _specials(prob: OrbitProblem, a: OrbitPoint, b: OrbitPoint, out: list) -> None:
    fa, fb = _tests(prob, a), _tests(prob, b)
    for kind in ("fold", "period-doubling", "neimark-sacker"):
        if fa[kind] * fb[kind] >= 0:
            continue
        found = _locate(prob, a, b, kind, fa[kind])
        if found is None:
            continue
        pt, bracket = found
        if kind == "neimark-sacker":
            close = [z for z in pt.rest if abs(abs(z) - 1) < 1e-3 and abs(z.imag) > 1e-6]
            if not close:
                continue  # a real pair lambda, 1/lambda: a neutral saddle
        if kind == "period-doubling" and not any(abs(z + 1) < 1e-3 for z in pt.rest):
            continue
        out.append(CoupledSpecialPoint(kind, float(pt.u[-1]), float(pt.T), pt.amps,
                                       tuple(complex(z) for z in pt.mults), bracket,
                                       tuple(float(v) for v in pt.u[:len(pt.Phi)])))


def _distinct(special: list[CoupledSpecialPoint]) -> list[CoupledSpecialPoint]:
    """Each located point once (a point met again, from the other side of the start or
    around a closed branch, is dropped)."""
    out: list[CoupledSpecialPoint] = []
    for s in special:
        if not any(o.kind == s.kind
                   and abs(o.parameter - s.parameter) <= 1e-7 * max(1.0, abs(o.parameter))
                   and np.max(np.abs(np.subtract(o.state, s.state))) < 1e-4 for o in out):
            out.append(s)
    return out
