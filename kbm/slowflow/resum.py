"""Resummation of a power series and the location of its nearest singularities.

Pure functions on a list of coefficients ``c_0, c_1, ...`` of ``f(t) = sum c_n t**n``
(numbers that mpmath reads: floats, ``mpf``, rationals):

- :func:`pade` and :func:`pade_resum`: diagonal Pade approximants ``[M/M]`` and a
  value of ``f`` outside the disc of convergence, with the spread of neighbouring
  approximants as its error estimate (Baker & Graves-Morris, *Pade
  Approximants*, 2nd ed., ch. 1);
- :func:`nearest_singularity`: the radius and argument of a pair of complex-conjugate
  singularities from the coefficients' three-term ratios (Mercer & Roberts, *J. Phys.
  A* 23 (1990) L1035; a generalisation of the Domb-Sykes ratio plot), the ratio
  estimates extrapolated in ``1/n``, and the nearest pole of the highest Pade
  approximant as a second opinion.

Andersen & Geer (1982) found the frequency of the van der Pol cycle, a series in
``t = mu**2``, to have its nearest singularities at ``|t| ~= 3.42``: beyond that the
partial sums diverge and the Pade approximants still converge.
"""

from __future__ import annotations

from dataclasses import dataclass

import mpmath

__all__ = ["pade", "pade_resum", "Resummed", "Singularity", "nearest_singularity",
           "ratio_estimates"]


def _mp(coeffs) -> list:
    return [mpmath.mpf(c) if not isinstance(c, mpmath.mpf) else c for c in coeffs]


def pade(coeffs, M: int, L: int | None = None) -> tuple[list, list]:
    """``(p, q)``: numerator and denominator coefficients of the Pade approximant ``[L/M]``.

    ``q[0] = 1``; needs ``L + M + 1`` coefficients (``L = M`` by default).  Raises
    ``ZeroDivisionError`` when the linear system is singular at the working
    precision (too noisy coefficients for that degree).
    """
    L = M if L is None else L
    c = _mp(coeffs)
    if L + M + 1 > len(c):
        raise ValueError(f"[{L}/{M}] needs {L + M + 1} coefficients, got {len(c)}")
    return mpmath.pade(c[:L + M + 1], L, M)


def _eval(p, q, t):
    return mpmath.polyval(p[::-1], t) / mpmath.polyval(q[::-1], t)


@dataclass(frozen=True)
class Resummed:
    """A Pade-resummed value.

    Attributes
    ----------
    value
        ``[M/M](t)`` at the chosen ``M``.
    error
        ``|[M/M](t) - [M'/M'](t)|`` for the neighbouring degree ``M'`` tried: an
        estimate of the error, not a bound.
    degree
        The chosen ``M``.
    """

    value: mpmath.mpf
    error: mpmath.mpf
    degree: int


def pade_resum(coeffs, t, *, degrees=None, dps: int = 40) -> Resummed:
    """``f(t)`` from diagonal Pade approximants, where the partial sums may diverge.

    Parameters
    ----------
    coeffs
        ``c_0 .. c_n``.
    t
        The point (real).
    degrees
        The ``M`` to try (default: 10 values up to ``n // 2``).  The value kept is
        the one that agrees best with the previous degree tried.
    dps
        Decimal digits of the linear algebra.

    Returns
    -------
    Resummed
    """
    n = len(coeffs) - 1
    top = n // 2
    if degrees is None:
        lo = max(1, top // 4)
        step = max(1, (top - lo) // 10)
        degrees = list(range(top, lo - 1, -step))[::-1]
    with mpmath.workdps(dps):
        c = _mp(coeffs)
        t = mpmath.mpf(t)
        vals = []
        for M in degrees:
            try:
                p, q = pade(c, M)
            except ZeroDivisionError:
                continue
            vals.append((M, _eval(p, q, t)))
        if not vals:
            raise ArithmeticError("every Pade approximant tried was singular")
        if len(vals) == 1:
            M, v = vals[0]
            return Resummed(+v, mpmath.inf, M)
        best = None
        for (M0, v0), (M1, v1) in zip(vals, vals[1:]):
            d = abs(v1 - v0)
            if best is None or d <= best[1]:
                best = (M1, d, v1)
        M, d, v = best
        return Resummed(+v, +d, M)


def ratio_estimates(coeffs, start: int = 4) -> list[tuple[int, mpmath.mpf, mpmath.mpf]]:
    """``[(n, R_n, theta_n)]``: Mercer-Roberts estimates of ``R e^{+-i theta}`` from
    ``c_{n-2} .. c_{n+1}`` (``B_n**2 = (c_{n+1} c_{n-1} - c_n**2)/(c_n c_{n-2} - c_{n-1}**2)``,
    ``R_n = 1/B_n``, ``cos theta_n = (c_{n-1} B_n/c_n + c_{n+1}/(B_n c_n))/2``).
    Indices where the formulas break down (a zero or negative ``B_n**2``) are left out."""
    c = _mp(coeffs)
    out = []
    for n in range(max(start, 2), len(c) - 1):
        den = c[n] * c[n - 2] - c[n - 1] ** 2
        num = c[n + 1] * c[n - 1] - c[n] ** 2
        if den == 0 or c[n] == 0:
            continue
        B2 = num / den
        if B2 <= 0:
            continue
        B = mpmath.sqrt(B2)
        cos_t = (c[n - 1] * B / c[n] + c[n + 1] / (B * c[n])) / 2
        theta = mpmath.acos(max(-1, min(1, cos_t)))
        out.append((n, 1 / B, theta))
    return out


@dataclass(frozen=True)
class Singularity:
    """The nearest singularities ``t = R e^{+-i theta}`` of a series in ``t``.

    Attributes
    ----------
    radius, angle
        ``R`` and ``theta`` from the ratio estimates extrapolated to ``n -> oo``
        (a fit ``R_n = R + b/n + c/n**2`` over the last half of the coefficients;
        ``theta``: the mean of the last quarter).
    radius_last
        The last ratio estimate ``R_n`` (not extrapolated).
    pole_radius, pole_angle
        Modulus and argument of the pole nearest the origin of the highest
        diagonal Pade approximant that could be formed, Froissart doublets (a pole
        with a zero within ``1e-6 |pole|`` of it: noise) left out; ``None`` if none.
    variable
        The name of ``t`` (e.g. ``"mu**2"``).
    """

    radius: float
    angle: float
    radius_last: float
    pole_radius: float | None
    pole_angle: float | None
    variable: str = "t"


def nearest_singularity(coeffs, *, variable: str = "t", dps: int = 40,
                        pole_degree: int = 30) -> Singularity:
    """Estimate the nearest singularities of ``sum c_n t**n`` (a complex-conjugate pair, or a
    real one with ``theta = 0`` or ``pi``).

    Needs some 20 nonzero coefficients at least; the ratio estimates converge like
    ``1/n``, the extrapolated one faster.  ``pole_degree`` bounds the Pade
    approximant whose poles are the second opinion.
    """
    with mpmath.workdps(dps):
        est = ratio_estimates(coeffs)
        if len(est) < 8:
            raise ValueError("too few usable coefficients to estimate a radius of convergence "
                             f"({len(est)} ratio estimates); compute the series to a higher order")
        tail = est[len(est) // 2:]
        # least squares for R_n = R + b/n + c/n^2
        A = mpmath.matrix([[1, mpmath.mpf(1) / n, mpmath.mpf(1) / n**2] for n, _, _ in tail])
        y = mpmath.matrix([r for _, r, _ in tail])
        sol = mpmath.lu_solve(A.T * A, A.T * y)
        R = sol[0]
        quarter = est[3 * len(est) // 4:]
        theta = mpmath.fsum(th for _, _, th in quarter) / len(quarter)
        pole_r = pole_a = None
        c = _mp(coeffs)
        M = min((len(c) - 1) // 2, pole_degree)
        while M >= 2 and pole_r is None:
            try:
                p, q = pade(c, M)
                poles = mpmath.polyroots(q[::-1], maxsteps=400, extraprec=4 * dps)
                zeros = mpmath.polyroots(p[::-1], maxsteps=400, extraprec=4 * dps) \
                    if len(p) > 1 else []
                # a pole with a zero next to it is a Froissart doublet (noise), not the function's
                real = [r for r in poles
                        if all(abs(r - z) > 1e-6 * abs(r) for z in zeros)]
                if real:
                    root = min(real, key=abs)
                    pole_r, pole_a = float(abs(root)), float(abs(mpmath.arg(root)))
                else:
                    M -= max(1, M // 10)
            except (ZeroDivisionError, mpmath.libmp.NoConvergence):
                M -= max(1, M // 10)
        return Singularity(radius=float(R), angle=float(theta), radius_last=float(est[-1][1]),
                           pole_radius=pole_r, pole_angle=pole_a, variable=variable)
