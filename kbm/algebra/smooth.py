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


class TaylorTable:
    """The partial derivatives ``F_ij`` of ``F``, differentiated and compiled on demand.

    Parameters
    ----------
    F
        A sympy expression in ``x`` and ``xdot`` only (parameters already numbers).
    extra
        Further variables of ``F`` (the forcing angle of a forced oscillator), passed to
        the compiled functions after ``x`` and ``xdot``.
    """

    def __init__(self, F: sp.Expr, extra: tuple = ()):
        self.F = sp.sympify(F)
        self.extra = tuple(extra)
        self._expr: dict[tuple[int, int], sp.Expr] = {(0, 0): self.F}
        self._func: dict[tuple[int, int], object] = {}

    def expr(self, i: int, j: int) -> sp.Expr:
        """``d^(i+j) F / dx^i dxdot^j`` (from the neighbour already known)."""
        key = (i, j)
        if key not in self._expr:
            self._expr[key] = (sp.diff(self.expr(i - 1, j), x) if i > 0
                               else sp.diff(self.expr(i, j - 1), xdot))
        return self._expr[key]

    def function(self, i: int, j: int):
        """``F_ij`` compiled for numpy arrays ``(x, xdot, *extra)``."""
        key = (i, j)
        if key not in self._func:
            with np.errstate(all="ignore"):
                self._func[key] = sp.lambdify((x, xdot, *self.extra), self.expr(i, j),
                                              modules=_MODULES)
        return self._func[key]

    def builder(self, alg, X: Leaf, V: Leaf) -> "SmoothBuilder":
        """The builder :func:`kbm.averaging._recursion` calls (its ``builder`` argument)."""
        return SmoothBuilder(alg, X, V, self)


class TaylorOf(Node):
    """``F(x_0 + Dx, v_0 + Dv)`` as a lazy series in eps (see the module docstring)."""

    def __init__(self, zero, sample, Dx: Node, Dv: Node):
        super().__init__(zero)
        self._sample = sample  # (i, j) -> the series F_ij(x_0, v_0)
        self._Dx, self._Dv = Dx, Dv
        self._mono: dict[tuple[int, int], Node] = {}
        self._deriv: dict[tuple[int, int], object] = {}

    def monomial(self, i: int, j: int) -> Node:
        """``Dx**i Dv**j`` (``i + j >= 1``), its leading ``i + j`` coefficients zero."""
        key = (i, j)
        if key not in self._mono:
            if i == 0 and j == 1:
                node = self._Dv
            elif i == 1 and j == 0:
                node = self._Dx
            elif j > 0:
                node = Product(self._zero, self.monomial(i, j - 1), self._Dv, i + j - 1, 1)
            else:
                node = Product(self._zero, self.monomial(i - 1, 0), self._Dx, i - 1, 1)
            self._mono[key] = node
        return self._mono[key]

    def derivative(self, i: int, j: int):
        key = (i, j)
        if key not in self._deriv:
            self._deriv[key] = self._sample(i, j)
        return self._deriv[key]

    def _make(self, n: int):
        if n == 0:
            return self.derivative(0, 0)
        acc = self._zero()
        for total in range(1, n + 1):
            for i in range(total + 1):
                j = total - i
                deriv = self.derivative(i, j)
                if deriv.is_zero():  # F_ij vanishes (F polynomial of low degree in x, x')
                    continue
                mono = self.monomial(i, j).coeff(n)
                if mono.is_zero():
                    continue
                term = mono * deriv
                acc = acc + term.scale_q(sp.Rational(1, factorial(i) * factorial(j)))
        return acc


class SmoothBuilder:
    """Makes the lazy series of ``F`` over a :class:`~kbm.algebra.grid_fourier.GridAlgebra`.

    Only :meth:`build` is asked for by the recursion; ``F`` is the table's.
    """

    def __init__(self, alg, X: Leaf, V: Leaf, table: TaylorTable):
        self.alg, self.X, self.V, self.table = alg, X, V, table

    def sample(self, i: int, j: int):
        """``F_ij(x_0, v_0)`` on the grid, checked to be finite (the exact zero when ``F_ij``
        vanishes identically)."""
        if self.table.expr(i, j) == 0:
            return self.alg.zero()
        x0 = self.X.coeff(0).values
        v0 = self.V.coeff(0).values
        with np.errstate(all="ignore"):
            vals = np.broadcast_to(np.asarray(self.table.function(i, j)(x0, v0), dtype=float),
                                   x0.shape).copy()
        bad = ~np.isfinite(vals)
        if bad.any():
            r, c = np.argwhere(bad)[0]
            what = "F" if (i, j) == (0, 0) else f"the derivative d^{i + j}F/dx^{i} dxdot^{j}"
            raise ParameterError(
                f"{what} is not finite at x = {x0[r, c]:.6g}, xdot = {v0[r, c]:.6g} "
                f"(amplitude a = {self.alg.a[r]:.6g}, phase psi = {self.alg.psi[c]:.6g}), "
                f"for F = {self.table.F}: the numeric backend needs F smooth and finite on "
                f"|x| <= a_max, |xdot| <= omega0 a_max; shrink the a-range or change F")
        return type(self.X.coeff(0))(vals)

    def build(self, expr: sp.Expr) -> Node:
        zero = self.alg.zero
        return TaylorOf(zero, self.sample, Tail(zero, self.X), Tail(zero, self.V))
