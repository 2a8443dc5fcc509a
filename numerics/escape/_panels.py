"""Adaptive piecewise-Chebyshev representation of orbit integrals over an energy range.

The orbit integrals of an annulus (the action ``I(E)``, the work ``Gamma(E)``, ``K(E) =
oint x^2 x' dx``) are analytic inside the annulus, with a logarithmic singularity of the
form ``(E - E_s) ln|E - E_s|`` at a separatrix energy ``E_s`` (the period ``T = dI/dE``
diverges like ``ln|E - E_s|`` there) and sharp but smooth features near a near-inflection
of the potential (where ``T(E)`` peaks).  A single polynomial fit over the annulus
converges only algebraically at the separatrix and oscillates at the peak (issue 36,
finding 1).  Here the energy range is cut into panels: each panel carries the Chebyshev
interpolant of the *exact* orbit quadratures at its Chebyshev points, and a panel is
split until the interpolant's last coefficients fall below the tolerance, geometrically
towards a separatrix end (hp-refinement: the error of a log-singular end falls like the
width of the last panel) and in halves elsewhere.

Reference: L. N. Trefethen, *Approximation Theory and Approximation Practice* (SIAM,
2013), ch. 8 (Chebyshev coefficient decay) and ch. 19 (piecewise and graded meshes).
"""

from __future__ import annotations

import functools

import numpy as np
from numpy.polynomial import Chebyshev

__all__ = ["Piecewise", "adaptive_panels"]

#: Chebyshev points per panel
NODES = 24
#: ratio of the geometric grading towards a singular panel end
GRADING = 0.1


class Piecewise:
    """A function given by Chebyshev series on consecutive panels ``[b_i, b_{i+1}]``.

    Calls evaluate the panel holding each argument (clipped to the range); ``deriv``,
    ``integ`` and adding a constant return :class:`Piecewise` again, so that it stands in
    for :class:`numpy.polynomial.Chebyshev` where a single fit was used before.
    """

    def __init__(self, breaks, pieces) -> None:
        self.breaks = np.asarray(breaks, float)
        self.pieces = list(pieces)

    def __repr__(self) -> str:
        return (f"Piecewise({len(self.pieces)} panels on [{self.breaks[0]:.6g}, "
                f"{self.breaks[-1]:.6g}])")

    def __call__(self, E):
        E = np.asarray(E, float)
        flat = np.atleast_1d(E).ravel()
        k = np.clip(np.searchsorted(self.breaks, flat, side="right") - 1, 0,
                    len(self.pieces) - 1)
        out = np.empty(flat.shape)
        for j in np.unique(k):
            m = k == j
            out[m] = self.pieces[j](flat[m])
        return out.reshape(E.shape) if E.ndim else out[0]

    def __add__(self, c: float) -> "Piecewise":
        return Piecewise(self.breaks, [p + c for p in self.pieces])

    __radd__ = __add__

    def deriv(self) -> "Piecewise":
        """The derivative, panel by panel."""
        return Piecewise(self.breaks, [p.deriv() for p in self.pieces])

    def integ(self, lbnd: float | None = None) -> "Piecewise":
        """The continuous antiderivative, ``0`` at the left end (or at ``lbnd``)."""
        out, acc = [], 0.0
        for a, b, p in zip(self.breaks[:-1], self.breaks[1:], self.pieces):
            q = p.integ(lbnd=a)
            out.append(q + acc)
            acc += float(q(b))
        res = Piecewise(self.breaks, out)
        return res if lbnd is None else res + (-float(res(lbnd)))

    @classmethod
    def sample(cls, breaks, fun, n: int = 2 * NODES) -> "Piecewise":
        """The interpolants of ``fun`` at ``n`` Chebyshev points of each panel."""
        pieces = []
        for a, b in zip(breaks[:-1], breaks[1:]):
            pieces.append(_interpolant(np.asarray(fun(_cheb_points(a, b, n)), float), a, b))
        return cls(breaks, pieces)


@functools.lru_cache(maxsize=8)
def _legendre(n: int) -> tuple[np.ndarray, np.ndarray]:
    """numpy's ``n``-point Gauss-Legendre rule, computed once (an eigenvalue problem: it was
    a third of the 2000 bins of :meth:`numerics.escape.envelope.EnergyEnvelope.energy_bins`
    that ``kbm noise`` evaluates)."""
    x, w = np.polynomial.legendre.leggauss(n)
    x.flags.writeable = w.flags.writeable = False
    return x, w


def gauss_on(breaks, n: int = 32) -> tuple[np.ndarray, np.ndarray]:
    """Composite ``n``-point Gauss-Legendre rule on the panels ``breaks``."""
    x, w = _legendre(n)
    b = np.asarray(breaks, float)
    half = 0.5 * np.diff(b)
    nodes = (b[:-1, None] + half[:, None] * (x[None, :] + 1)).ravel()
    weights = (half[:, None] * w[None, :]).ravel()
    return nodes, weights


def _cheb_points(a: float, b: float, n: int = NODES) -> np.ndarray:
    k = np.arange(n)
    return 0.5 * (a + b) + 0.5 * (b - a) * np.cos(np.pi * (k + 0.5) / n)


def _interpolant(f: np.ndarray, a: float, b: float) -> Chebyshev:
    """The Chebyshev interpolant of the values ``f`` at :func:`_cheb_points` of ``[a, b]``
    (discrete cosine transform: well conditioned however narrow the panel)."""
    n = f.size
    theta = np.pi * (np.arange(n) + 0.5) / n
    coef = (2.0 / n) * np.cos(np.outer(np.arange(n), theta)) @ f
    coef[0] /= 2
    return Chebyshev(coef, domain=[a, b])


def adaptive_panels(values, lo: float, hi: float, *, singular_lo: bool, singular_hi: bool,
                    tol: float = 1e-12, max_panels: int = 400):
    """Panels on ``[lo, hi]`` on which every function of ``values`` is resolved.

    Parameters
    ----------
    values : callable
        ``values(E) -> list of arrays`` (the exact functions at the energies ``E``).
    lo, hi : float
    singular_lo, singular_hi : bool
        Whether an end is a separatrix (graded geometrically towards it).
    tol : float
        Tail of each panel's Chebyshev coefficients, relative to the function's largest
        value over the range.
    max_panels : int

    Returns
    -------
    (breaks, list of list of Chebyshev)
        The break points and, per function, its interpolant on each panel.
    """
    span = hi - lo
    floor = 1e-13 * max(1.0, abs(lo), abs(hi))

    def fit(a, b):
        return [_interpolant(v, a, b) for v in values(_cheb_points(a, b))]

    todo = [(lo, hi)]
    done: dict = {}
    scale = None
    while todo:
        a, b = todo.pop()
        fits = fit(a, b)
        if scale is None:
            scale = [max(float(np.max(np.abs(f.coef))), 1e-300) for f in fits]
        tail = max(float(np.max(np.abs(f.coef[-3:]))) / s for f, s in zip(fits, scale))
        at_lo = singular_lo and a == lo
        at_hi = singular_hi and b == hi
        if tail <= tol or b - a <= floor or len(done) + len(todo) >= max_panels:
            done[(a, b)] = fits
            continue
        if at_lo and not at_hi:
            cut = a + GRADING * (b - a)
        elif at_hi and not at_lo:
            cut = b - GRADING * (b - a)
        else:
            cut = 0.5 * (a + b)
        if not a < cut < b or (b - a) < 1e-15 * span:
            done[(a, b)] = fits
            continue
        todo += [(a, cut), (cut, b)]
    keys = sorted(done)
    breaks = [keys[0][0]] + [k[1] for k in keys]
    per = list(zip(*[done[k] for k in keys]))
    return np.asarray(breaks), [list(p) for p in per]
