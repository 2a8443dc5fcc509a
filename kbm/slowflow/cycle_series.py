"""The limit cycle's mu-series computed on the cycle itself (Lindstedt-Poincare).

For ``x'' + omega0**2 x = mu F(x, x')`` with polynomial ``F`` the periodic orbit is
sought with ``tau = omega t`` as

``x(tau) = sum_n mu**n x_n(tau)``, ``omega = sum_n mu**n omega_n`` (``omega_0 = omega0``),
``omega**2 x_tautau + omega0**2 x = mu F(x, omega x_tau)``,

each ``x_n`` a trigonometric polynomial (:class:`~kbm.algebra.zfourier.ZSeries`)
normalised as the KBM expansion is: the first harmonic of ``x`` is ``a cos(tau)``
with ``a = sum mu**n a_n`` and no ``sin(tau)`` term.  So ``a`` is the
first-harmonic amplitude ``a*`` of :mod:`kbm.slowflow.series` and ``omega`` its frequency
``omega*``: the same series, computed without the averaged equations.

At order ``n`` the equation is ``omega0**2 (x_n'' + x_n) = R_n`` with
``R_n = F_{n-1} - sum_{i=1}^{n} Omega_i x_{n-i}''`` (``Omega = omega**2``,
``F_{n-1}`` the coefficient of ``mu**(n-1)`` of ``F`` along the series).  Its
``cos(tau)`` and ``sin(tau)`` components must vanish: they fix ``omega_n`` and the
amplitude correction ``a_{n-1}``, which enters ``R_n`` linearly through
``dF/da`` at the first-order cycle (``a_0``: the root of ``A_1``); the slope
``-2 omega0 A_1'(a_0)`` must not vanish (a hyperbolic cycle).  The products of
``F`` are Cauchy products of the truncated series in ``mu``, formed once each:
the cost is about ``N**2`` products of Fourier polynomials of length ``~N``.
After ``a_{n-1}`` is known the stored coefficients ``n - 1`` of every node of
``F`` are corrected by ``a_{n-1} d(node_0)/da`` (they are linear in ``x_{n-1}``).

References
----------
A. H. Nayfeh, *Perturbation Methods*, Wiley (1973), sec. 3.1 (Lindstedt-Poincare).
C. M. Andersen and J. F. Geer, "Power series expansions for the frequency and
period of the limit cycle of the van der Pol equation", SIAM J. Appl. Math. 42
(1982) 678-693.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

import sympy as sp

from ..algebra.zfourier import Arithmetic, ZSeries
from ..errors import AveragedCycleError
from ..symbols import x, xdot

__all__ = ["CycleSeriesRaw", "lindstedt_series", "polynomial_terms"]


@dataclass(frozen=True)
class CycleSeriesRaw:
    """Coefficients of ``omega*`` and ``a*`` in the scalars of one arithmetic.

    Attributes
    ----------
    order
        Highest power of ``mu``.
    omega, amplitude
        ``order + 1`` coefficients each (``omega[0] = omega0``, ``amplitude[0] = a_0``).
    arithmetic
        The :class:`~kbm.algebra.zfourier.Arithmetic` they are in.
    """

    order: int
    omega: tuple
    amplitude: tuple
    arithmetic: Arithmetic


def polynomial_terms(F: sp.Expr) -> list[tuple[int, int, Fraction]] | None:
    """``[(i, j, c)]`` with ``F = sum c x**i xdot**j`` and rational ``c``, or ``None`` if ``F``
    is not such a polynomial (other symbols, non-rational coefficients, other functions)."""
    try:
        poly = sp.Poly(sp.expand(F), x, xdot)
    except sp.PolynomialError:
        return None
    out = []
    for (i, j), c in poly.terms():
        if not c.is_Rational:
            return None
        out.append((int(i), int(j), Fraction(int(c.p), int(c.q))))
    return out


# ----------------------------------------------------------------------------- nodes of F
class _Node:
    """A power series in mu with :class:`ZSeries` coefficients ``c`` and ``D = d c_0/da``."""

    __slots__ = ("c", "D")

    def __init__(self):
        self.c: list[ZSeries] = []
        self.D: ZSeries | None = None

    def extend(self, m: int) -> None:  # compute coefficient m (all below are known)
        raise NotImplementedError


class _Leaf(_Node):
    """``x`` or ``xdot``: coefficients appended by the recursion."""

    def extend(self, m: int) -> None:  # pragma: no cover - the recursion fills leaves itself
        raise RuntimeError("leaf coefficients are set by the recursion")


class _Product(_Node):
    __slots__ = ("l", "r")

    def __init__(self, left: _Node, right: _Node):
        super().__init__()
        self.l, self.r = left, right
        self.D = (left.D * right.c[0] + left.c[0] * right.D)
        self.c.append(left.c[0].square() if left is right else left.c[0] * right.c[0])

    def extend(self, m: int) -> None:
        lc, rc = self.l.c, self.r.c
        if self.l is self.r:  # a square: half the products
            acc = None
            for i in range(0, (m + 1) // 2):
                t = lc[i] * lc[m - i]
                acc = t if acc is None else acc + t
            acc = acc + acc if acc is not None else None
            if m % 2 == 0:
                sq = lc[m // 2].square()
                acc = sq if acc is None else acc + sq
        else:
            acc = lc[0] * rc[m]
            for i in range(1, m + 1):
                acc = acc + lc[i] * rc[m - i]
        self.c.append(acc)


class _Linear(_Node):
    """``const + sum_k w_k node_k`` (rational weights)."""

    __slots__ = ("terms", "const", "_zero")

    def __init__(self, terms: list[tuple[Any, _Node]], const: ZSeries | None, zero: ZSeries):
        super().__init__()
        self.terms = terms
        self.const = const
        c0 = const if const is not None else zero
        D = zero
        for w, node in terms:
            c0 = c0 + node.c[0].scale(w)
            D = D + node.D.scale(w)
        self.c.append(c0)
        self.D = D
        self._zero = zero

    def extend(self, m: int) -> None:
        acc = self._zero
        for w, node in self.terms:
            acc = acc + node.c[m].scale(w)
        self.c.append(acc)


class _Tree:
    """``F(x, xdot)`` as product and linear nodes over the leaves ``X`` and ``V``."""

    def __init__(self, terms, ar: Arithmetic, X: _Leaf, V: _Leaf):
        self.nodes: list[_Node] = []  # creation order = dependency order
        self._pows: dict[tuple[int, int], _Node] = {(1, 0): X, (0, 1): V}
        zero = ZSeries.zero(ar)
        const = None
        lin = []
        for i, j, c in terms:
            if i == 0 and j == 0:
                const = ZSeries.constant(ar, ar.num(c))
                continue
            node = self._monomial(i, j)
            lin.append((ar.num(c), node))
        self.F = _Linear(lin, const, zero)
        self.nodes.append(self.F)

    def _power(self, base: tuple[int, int], e: int) -> _Node:
        key = (base[0] * e, base[1] * e)
        if key in self._pows:
            return self._pows[key]
        if e % 2:
            node = _Product(self._power(base, e - 1), self._power(base, 1))
        else:
            half = self._power(base, e // 2)
            node = _Product(half, half)
        self.nodes.append(node)
        self._pows[key] = node
        return node

    def _monomial(self, i: int, j: int) -> _Node:
        if (i, j) in self._pows:
            return self._pows[(i, j)]
        if j == 0:
            return self._power((1, 0), i)
        if i == 0:
            return self._power((0, 1), j)
        node = _Product(self._power((1, 0), i), self._power((0, 1), j))
        self.nodes.append(node)
        self._pows[(i, j)] = node
        return node


# ----------------------------------------------------------------------------- the recursion
def lindstedt_series(terms: list[tuple[int, int, Fraction]], omega0: Fraction, a0: Any,
                     order: int, ar: Arithmetic,
                     progress: Callable[[int], object] | None = None) -> CycleSeriesRaw:
    """The ``mu``-series of ``omega*`` and ``a*`` by the Lindstedt-Poincare recursion.

    Parameters
    ----------
    terms
        ``F = sum c x**i xdot**j`` as ``(i, j, c)`` (:func:`polynomial_terms`).
    omega0
        The linear frequency (positive rational).
    a0
        The first-order amplitude (a root of ``A_1``), a scalar of ``ar``.
    order
        Highest power ``N`` of ``mu`` (the recursion runs to ``mu**(N+1)``, which
        fixes ``a_N``).
    ar
        The arithmetic (:func:`kbm.algebra.zfourier.arithmetic`).
    progress
        Called with 1 after each power of ``mu`` (``N + 1`` calls at most; a
        :mod:`tqdm` bar's ``update``): the step to ``mu**n`` costs about ``n`` times the
        first, so that van der Pol to ``mu**1000`` in double precision takes minutes.

    Returns
    -------
    CycleSeriesRaw

    Raises
    ------
    kbm.errors.AveragedCycleError
        If ``a0`` is not a root of ``A_1`` (exact arithmetic) or the cycle is not
        hyperbolic (``A_1'(a0) = 0``).
    """
    N = order
    w0 = ar.num(omega0)
    w0sq = w0 * w0
    trig = ZSeries.trig
    zero_s = ar.zero
    X, V = _Leaf(), _Leaf()
    X.c.append(trig(ar, a0, zero_s, 1))
    V.c.append(trig(ar, zero_s, -(w0 * a0), 1))
    X.D = trig(ar, ar.num(Fraction(1)), zero_s, 1)
    V.D = trig(ar, zero_s, -w0, 1)
    tree = _Tree(terms, ar, X, V)
    nodes = tree.nodes
    Fnode = tree.F
    G = Fnode.D  # dF_0/da at a0
    Gc, Gs = G.harmonic(1)
    omega = [w0]
    Omega = [w0sq]
    amp = [a0]
    Xpp = [X.c[0].dtau().dtau()]

    def rhs(n: int) -> ZSeries:  # F_{n-1} - sum_{i=1}^{n-1} Omega_i x''_{n-i}
        R = Fnode.c[n - 1]
        for i in range(1, n):
            R = R - Xpp[n - i].scale(Omega[i])
        return R

    R = rhs(1)
    C, S = R.harmonic(1)
    if ar.is_exact() and S != 0:
        raise AveragedCycleError(f"a0 = {a0} is not a root of A_1 (sin component {S} of F "
                                 "on the first-order cycle)")
    if Gs == 0:
        raise AveragedCycleError(f"A_1'(a0) = 0 at a0 = {a0}: the cycle is not hyperbolic "
                                 "and has no regular series in mu")
    for n in range(1, N + 2):
        m = n - 1
        if progress is not None:
            progress(1)
        if n >= 2:
            for node in nodes:
                node.extend(m)
            R = rhs(n)
            C, S = R.harmonic(1)
            delta = -S / Gs  # a_{n-1}
            amp.append(delta)
            if n == N + 1:
                break
            # the stored coefficients m were made with a_m = 0: add a_m d(node_0)/da
            X.c[m] = X.c[m] + X.D.scale(delta)
            V.c[m] = V.c[m] + V.D.scale(delta)
            for node in nodes:
                node.c[m] = node.c[m] + node.D.scale(delta)
            Xpp[m] = X.c[m].dtau().dtau()
            R = rhs(n)
            C, S = R.harmonic(1)
        elif N == 0:
            # order 0 still needs a_0 only
            break
        # cos(tau) balance: C + Omega_n a0 = 0  (-Omega_n x_0'' = Omega_n a0 cos(tau))
        Om_n = -C / a0
        Omega.append(Om_n)
        s = zero_s
        for i in range(1, n):
            s = s + omega[i] * omega[n - i]
        omega.append((Om_n - s) / (2 * w0))
        R = R - Xpp[0].scale(Om_n)
        xn = R.solve_periodic(w0sq)
        X.c.append(xn)
        Xpp.append(xn.dtau().dtau())
        v = xn.dtau().scale(w0)
        for i in range(1, n + 1):
            v = v + X.c[n - i].dtau().scale(omega[i])
        V.c.append(v)
    return CycleSeriesRaw(order=N, omega=tuple(omega[:N + 1]), amplitude=tuple(amp[:N + 1]),
                          arithmetic=ar)
