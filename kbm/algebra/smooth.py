"""Any smooth ``F(x, xdot)`` along the KBM series, by its Taylor expansion.

Along ``x = x_0 + Dx``, ``xdot = v_0 + Dv`` with ``Dx = sum_{n>=1} eps**n X_n`` and
``Dv = sum_{n>=1} eps**n V_n``,

``F(x, xdot) = sum_{i, j} F_ij(x_0, v_0) Dx**i Dv**j / (i! j!)``,
``F_ij = d^(i+j) F / dx^i dxdot^j``,

and the coefficient of ``eps**n`` needs ``i + j <= n`` only (``Dx``, ``Dv`` start at
``eps**1``).  The partial derivatives are taken symbolically once
(:class:`TaylorTable`, cached across grids) and compiled with
:func:`sympy.lambdify` for numpy, so ``F`` may use any function numpy or scipy
evaluates; the monomials ``Dx**i Dv**j`` are lazy series of
:mod:`~kbm.algebra.lazy_series`, each product formed once.
"""

from __future__ import annotations

from math import factorial

import numpy as np
import sympy as sp

from ..errors import ParameterError
from ..symbols import x, xdot
from .lazy_series import Leaf, Node, Product, Tail

__all__ = ["TaylorTable", "TaylorOf", "SmoothBuilder"]

_MODULES = ["scipy", "numpy"]


def _indices(k: int, total: int):
    """The multi-indices of ``k`` variables with the sum ``total``, the first index rising
    (for two variables ``(0, total), (1, total - 1), ...``)."""
    if k == 1:
        yield (total,)
        return
    for first in range(total + 1):
        for rest in _indices(k - 1, total - first):
            yield (first, *rest)


class TaylorTable:
    """The partial derivatives ``F_beta`` of ``F``, differentiated and compiled on demand.

    Parameters
    ----------
    F
        A sympy expression in ``variables`` only (parameters already numbers).
    extra
        Further variables of ``F`` (the forcing angle of a forced oscillator), passed to
        the compiled functions after ``variables``.
    variables
        The variables of the expansion: ``(x, xdot)`` for one degree of freedom,
        ``(x1, .., xN, xdot1, .., xdotN)`` for ``N`` coupled ones.
    """

    def __init__(self, F: sp.Expr, extra: tuple = (), variables: tuple = (x, xdot)):
        self.F = sp.sympify(F)
        self.extra = tuple(extra)
        self.variables = tuple(variables)
        zero = (0,) * len(self.variables)
        self._expr: dict[tuple[int, ...], sp.Expr] = {zero: self.F}
        self._func: dict[tuple[int, ...], object] = {}

    def expr(self, *beta: int) -> sp.Expr:
        """``d^|beta| F / d variables^beta`` (from the neighbour already known: the first
        variable with a non-zero index differentiated last)."""
        key = tuple(beta)
        if key not in self._expr:
            l = next(i for i, b in enumerate(key) if b > 0)
            prev = key[:l] + (key[l] - 1,) + key[l + 1:]
            self._expr[key] = sp.diff(self.expr(*prev), self.variables[l])
        return self._expr[key]

    def function(self, *beta: int):
        """``F_beta`` compiled for numpy arrays ``(*variables, *extra)``."""
        key = tuple(beta)
        if key not in self._func:
            with np.errstate(all="ignore"):
                self._func[key] = sp.lambdify((*self.variables, *self.extra), self.expr(*key),
                                              modules=_MODULES)
        return self._func[key]


class TaylorOf(Node):
    """``F(y_0 + Dy)`` as a lazy series in eps along ``K`` variables (see the module
    docstring; ``K = 2`` for ``(x, xdot)``, ``2 N`` for ``N`` coupled oscillators).

    ``sample(*beta)`` gives the series ``F_beta(y_0)``; ``deltas`` are the lazy series
    ``Dy_l`` (without their ``eps**0`` coefficients).
    """

    def __init__(self, zero, sample, *deltas: Node):
        super().__init__(zero)
        self._sample = sample  # beta -> the series F_beta(y_0)
        self._deltas = deltas
        self._mono: dict[tuple[int, ...], Node] = {}
        self._deriv: dict[tuple[int, ...], object] = {}

    def monomial(self, *beta: int) -> Node:
        """``prod_l Dy_l**beta_l`` (``|beta| >= 1``), its leading ``|beta|`` coefficients
        zero: the previous monomial times the last variable with a non-zero index."""
        key = tuple(beta)
        if key not in self._mono:
            total = sum(key)
            l = max(i for i, b in enumerate(key) if b > 0)
            if total == 1:
                node = self._deltas[l]
            else:
                prev = key[:l] + (key[l] - 1,) + key[l + 1:]
                node = Product(self._zero, self.monomial(*prev), self._deltas[l], total - 1, 1)
            self._mono[key] = node
        return self._mono[key]

    def derivative(self, *beta: int):
        key = tuple(beta)
        if key not in self._deriv:
            self._deriv[key] = self._sample(*key)
        return self._deriv[key]

    def _make(self, n: int):
        k = len(self._deltas)
        if n == 0:
            return self.derivative(*(0,) * k)
        acc = self._zero()
        for total in range(1, n + 1):
            for beta in _indices(k, total):
                deriv = self.derivative(*beta)
                if deriv.is_zero():  # F_beta vanishes (F polynomial of low degree)
                    continue
                mono = self.monomial(*beta).coeff(n)
                if mono.is_zero():
                    continue
                term = mono * deriv
                weight = 1
                for b in beta:
                    weight *= factorial(b)
                acc = acc + term.scale_q(sp.Rational(1, weight))
        return acc


class SmoothBuilder:
    """Makes the lazy series of ``F(x_0 + Dx, v_0 + Dv, theta)`` over the grid algebra
    (:class:`kbm.algebra.grid.SampledAlgebra`, forced or not).  Only :meth:`build` is asked
    for by the recursion; ``F`` is the table's, ``extra`` the samples of its further
    arguments (the forcing angle ``theta``); the leaves' samples are their ``sigma**0``
    rows.
    """

    def __init__(self, alg, X: Leaf, V: Leaf, table: TaylorTable, extra: tuple = ()):
        self.alg, self.X, self.V, self.table, self.extra = alg, X, V, table, tuple(extra)

    def not_finite(self, i: int, j: int, index: tuple, x0: np.ndarray, v0: np.ndarray) -> str:
        """The message for ``F_ij`` not finite at the grid point ``index``."""
        r, c, l = index
        what = "F" if (i, j) == (0, 0) else f"the derivative d^{i + j}F/dx^{i} dxdot^{j}"
        forced = f", theta = {self.alg.theta[l]:.6g}" if self.extra else ""
        return (f"{what} is not finite at x = {x0[index]:.6g}, xdot = {v0[index]:.6g} "
                f"(amplitude a = {self.alg.a[r]:.6g}, phase psi = {self.alg.psi[c]:.6g}"
                f"{forced}), for F = {self.table.F}: the numeric backend needs F smooth and "
                f"finite on |x| <= a_max, |xdot| <= omega0 a_max; shrink the a-range or "
                f"change F")

    def sample(self, i: int, j: int):
        """``F_ij(x_0, v_0, *extra)`` on the grid, checked to be finite (the exact zero when
        ``F_ij`` vanishes identically)."""
        if self.table.expr(i, j) == 0:
            return self.alg.zero()
        x0, v0 = self.X.coeff(0).values[0], self.V.coeff(0).values[0]
        with np.errstate(all="ignore"):
            vals = np.broadcast_to(np.asarray(self.table.function(i, j)(x0, v0, *self.extra),
                                              dtype=float), x0.shape).copy()
        bad = ~np.isfinite(vals)
        if bad.any():
            raise ParameterError(self.not_finite(i, j, tuple(np.argwhere(bad)[0]), x0, v0))
        return self.alg.sample(vals)

    def build(self, expr: sp.Expr) -> Node:
        zero = self.alg.zero
        return TaylorOf(zero, self.sample, Tail(zero, self.X), Tail(zero, self.V))
