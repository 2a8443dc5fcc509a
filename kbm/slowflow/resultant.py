"""Every fixed point of a polynomial slow flow, by elimination (resultants).

The slow flow's rates are polynomials in ``a``, ``1/a`` and the harmonics ``cos(j Phi)``,
``sin(j Phi)`` of ``Phi = p phi``.  With ``c = cos Phi``, ``s = sin Phi`` (Chebyshev:
``cos(j Phi) = T_j(c)``, ``sin(j Phi) = s U_{j-1}(c)``, ``s**2 = 1 - c**2``) each equation
becomes ``P0(a, c) + s P1(a, c) = 0``; eliminating ``s`` gives ``P0 Q1 - Q0 P1 = 0`` and
``P0**2 - (1 - c**2) P1**2 = 0``, and the resultant of these in ``c`` a polynomial in ``a``
alone.  Its positive roots hold every amplitude of a fixed point; each is completed to
``(c, s)`` on the unit circle, checked against both equations and polished by Newton's
method.  This is the exact counterpart of the grid scan of :func:`kbm.slowflow.steady.
fixed_points` (slower, for checks and for slow flows of low order).
"""

from __future__ import annotations

import math

import numpy as np
import sympy as sp

from ..symbols import a
from ..model.forced import phi, sigma
from ..expansion.forced_result import SlowFlow
from .steady import FixedPoint, _add_new, _newton, _period

__all__ = ["fixed_points_resultant"]

_c, _s = sp.symbols("c s")


def _in_cs(expr: sp.Expr, p: int) -> sp.Expr:
    """``expr`` with ``cos(m phi)``, ``sin(m phi)`` (``m = j p``) written in ``c``, ``s``."""
    reps = {}
    for f in expr.atoms(sp.cos, sp.sin):
        if not f.has(phi):
            continue
        m = f.args[0].coeff(phi)
        j = int(m / p)
        if isinstance(f, sp.cos):
            reps[f] = sp.chebyshevt(j, _c)
        else:
            reps[f] = _s * sp.chebyshevu(j - 1, _c)
    return expr.xreplace(reps)


def _split(expr: sp.Expr) -> tuple[sp.Expr, sp.Expr]:
    """``(P0, P1)`` with ``expr = P0 + s P1`` modulo ``s**2 = 1 - c**2``, denominators in
    ``a`` cleared."""
    num = sp.numer(sp.together(sp.expand(expr)))
    poly = sp.Poly(sp.expand(num), _s)
    p0, p1 = sp.Integer(0), sp.Integer(0)
    for (k,), coeff in poly.terms():
        w = (1 - _c**2)**(k // 2)
        if k % 2:
            p1 += coeff * w
        else:
            p0 += coeff * w
    return sp.expand(p0), sp.expand(p1)


def fixed_points_resultant(sf: SlowFlow, sigma_value: float, *, amplitude_max: float = 50.0,
                           tol: float = 1e-8) -> list[FixedPoint]:
    """Every fixed point with ``0 < a < amplitude_max`` at detuning ``sigma_value``.

    The rates are made exact (:func:`sympy.nsimplify` of their coefficients) before the
    elimination; the roots found are polished on the floating-point slow flow.
    """
    p = sf.resonance.p if sf.resonance else 1
    sv = sp.nsimplify(sigma_value, rational=True)
    eqs = [sp.nsimplify(_in_cs(sp.expand(e.subs(sigma, sv)), p), rational=True)
           for e in sf.exprs]
    (P0, P1), (Q0, Q1) = _split(eqs[0]), _split(eqs[1])
    R1 = sp.expand(P0 * Q1 - Q0 * P1)
    R2 = sp.expand(P0**2 - (1 - _c**2) * P1**2) if P1 != 0 else P0
    if R1 == 0:
        R1 = sp.expand(Q0**2 - (1 - _c**2) * Q1**2) if Q1 != 0 else Q0
    res = sp.Poly(sp.resultant(R1, R2, _c), a)
    if res.is_zero:
        raise ArithmeticError("the resultant vanishes identically (a curve of fixed points)")
    _, res = res.terms_gcd()  # the factor a**k: no fixed point at a > 0
    res = sp.Poly(res.as_expr(), a).sqf_part()
    roots = [complex(r) for r in res.nroots(n=30, maxsteps=5000)] if res.degree() > 0 else []
    amps = sorted({round(r.real, 12) for r in roots
                   if abs(r.imag) < 1e-8 * (1 + abs(r)) and 0 < r.real < amplitude_max})
    per = _period(sf)
    found: list[FixedPoint] = []
    for av in amps:
        cands = []
        for poly in (R2, R1):
            pc = sp.Poly(sp.expand(poly.subs(a, sp.nsimplify(av, rational=True))), _c)
            if pc.degree() > 0:
                cands += [complex(r).real for r in np.roots([float(x) for x in pc.all_coeffs()])
                          if abs(complex(r).imag) < 1e-6 and abs(complex(r).real) <= 1 + 1e-6]
        for cv in cands:
            cv = max(-1.0, min(1.0, cv))
            for sgn in (1, -1):
                Phi = math.atan2(sgn * math.sqrt(max(0.0, 1 - cv * cv)), cv)
                u, _ = _newton(sf, np.array([av, Phi / p]), sigma_value, 30, 1e-14)
                r = np.array([np.ravel(x)[0] for x in sf.rates(u[0], u[1], sigma_value)])
                if np.all(np.isfinite(u)) and np.max(np.abs(r)) < tol and u[0] > 0:
                    _add_new(found, sf, sigma_value, u, per)
    return sorted(found, key=lambda f: f.amplitude)
