"""The Krylov-Bogoliubov-Mitropolsky recursion, once: ``N`` modes, an optional forcing angle.

For ``x_i'' + omega_i**2 x_i = mu F_i(x, x', theta)`` (i = 1..N; ``theta = nu t`` with
``nu = nu0 + mu sigma`` when forced) the expansion (Bogoliubov & Mitropolsky 1961, ch. 1,
3 and 5; Nayfeh & Mook 1979, ch. 4 and 6) is

``x_i = a_i cos(psi_i) + sum_{n>=1} mu**n u_{i,n}(a, psi, theta)``,
``da_i/dt = sum mu**n A_{i,n}``, ``dpsi_i/dt = omega_i + sum mu**n B_{i,n}``,

with rates that hold only slow harmonics and no ``u_{i,n}`` holding a resonant one, so that
``a_i`` is exactly the amplitude of ``x_i``'s component at its own frequency.  With
``L0 = sum_l omega_l d/dpsi_l (+ nu0 d/dtheta)`` and

``D_j = sum_l (A_{l,j} d/da_l + B_{l,j} d/dpsi_l)  (+ sigma d/dtheta for j = 1)``

the coefficients of the velocity and the acceleration are
``V_{i,m} = L0 u_{i,m} + sum_{j=1}^m D_j u_{i,m-j}`` and
``[x_i'']_m = L0 V_{i,m} + sum_{j=1}^m D_j V_{i,m-j}``.  At order ``n`` the unknowns of mode
``i`` enter as ``(L0**2 + omega_i**2) u_{i,n} - 2 omega_i A_{i,n} sin(psi_i) - 2 omega_i a_i
B_{i,n} cos(psi_i)``; with ``R_{i,n}`` the coefficient of ``mu**(n-1)`` of ``F_i`` minus every
known term of ``[x_i'']_n``, its resonant part gives ``A_{i,n}``, ``B_{i,n}``
(:meth:`~kbm.algebra.base.RecursionAlgebra.secular`) and the rest ``u_{i,n}``
(:meth:`~kbm.algebra.base.RecursionAlgebra.solve`).

:func:`kbm_recursion` is that loop, over any :class:`~kbm.algebra.base.RecursionAlgebra`.  The
engines are its cases:

- one degree of freedom (:mod:`kbm.expansion.one_dof`): ``N = 1``, no forcing, a one-angle
  :class:`~kbm.algebra.base.FourierAlgebra` through :class:`OneAngle`
  (:func:`one_angle_recursion`);
- a forced oscillator (:mod:`kbm.expansion.forced`, :mod:`kbm.backend.forced`): ``N = 1`` with the
  forcing angle, ``sigma d/dtheta`` in ``D_1`` at a declared resonance; the grid algebra of
  :mod:`kbm.algebra.grid` without the forcing angle runs the numeric :mod:`kbm.backend.one_dof`;
- coupled oscillators (:mod:`kbm.expansion.coupled`, :mod:`kbm.backend.jets`): any ``N``, forced
  or not; the jets with one unforced mode at a batch of amplitudes are the evaluated
  :mod:`kbm.backend.pointwise`.

The right-hand side reaches the loop as lazy series in ``mu``
(:mod:`kbm.algebra.lazy_series`) along the leaves ``x_l = sum mu**n X_{l,n}``,
``xdot_l = sum mu**n V_{l,n}``, which the loop fills order by order.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import sympy as sp

from ..algebra.base import FourierAlgebra, RecursionAlgebra
from ..algebra.lazy_series import Builder, Leaf, Node

__all__ = ["kbm_recursion", "one_angle_recursion", "OneAngle", "RightHandSide"]

#: ``rhs(X, V)``: for each mode ``i`` the pairs ``(k, node)``, ``node`` the lazy series (in
#: ``mu``, along the leaves ``X[l]``, ``V[l]``) of the coefficient of ``mu**k`` of ``F_i``
#: (a hard forcing, a detuning or a forcing frequency in ``F`` make ``F`` depend on ``mu``)
RightHandSide = Callable[[Sequence[Leaf], Sequence[Leaf]], Sequence[Sequence[tuple[int, Node]]]]


def kbm_recursion(alg: RecursionAlgebra, rhs: RightHandSide, order: int, *,
                  last_u: bool = True) -> tuple[list[list], list[list], list[list]]:
    """``A``, ``B``, ``U``: per mode ``i`` the lists ``A_{i,1..N}``, ``B_{i,1..N}``,
    ``u_{i,1..N}`` in the algebra's types (see the module docstring).

    Parameters
    ----------
    alg
        The algebra (:class:`~kbm.algebra.base.RecursionAlgebra`).
    rhs
        Makes the lazy series of the right-hand sides along the leaves
        (:data:`RightHandSide`).
    order
        The highest order ``N``.
    last_u
        ``False`` skips the last (most costly) ``u_{i,N}`` when only the rates are needed.
    """
    n_modes = alg.dof
    zero = alg.zero
    X0 = [alg.x0(i) for i in range(n_modes)]
    V0 = [alg.L0(x0) for x0 in X0]
    XL = [Leaf(zero, x0) for x0 in X0]
    VL = [Leaf(zero, v0) for v0 in V0]
    terms = rhs(XL, VL)
    A: list[list] = [[] for _ in range(n_modes)]
    B: list[list] = [[] for _ in range(n_modes)]
    U: list[list] = [[] for _ in range(n_modes)]
    detuned = alg.detuned

    def F_coeff(i: int, m: int):
        """The coefficient of ``mu**m`` of ``F_i``."""
        parts = []
        for k, node in terms[i]:
            if k <= m:
                c = node.coeff(m - k)
                if not c.is_zero():
                    parts.append(c)
        if not parts:
            return zero()
        out = parts[0]
        for c in parts[1:]:
            out = out + c
        return out

    def D(j: int, f):  # D_j f (j >= 1)
        out = zero()
        for l in range(n_modes):
            Alj, Blj = A[l][j - 1], B[l][j - 1]
            if not alg.rate_vanishes(Alj):
                out = out + alg.times(Alj, alg.da(f, l))
            if not alg.rate_vanishes(Blj):
                out = out + alg.times(Blj, alg.dpsi(f, l))
        if j == 1 and detuned:  # nu = nu0 + mu sigma: sigma d/dtheta at order one
            out = out + alg.sigma_dtheta(f)
        return out

    Xs = [[x0] for x0 in X0]
    Vs = [[v0] for v0 in V0]
    for m in range(1, order + 1):
        known, R = [], []
        for i in range(n_modes):
            v_known = zero()
            for j in range(1, m):
                v_known = v_known + D(j, Xs[i][m - j])
            acc = alg.L0(v_known)
            for j in range(1, m):
                acc = acc + D(j, Vs[i][m - j])
            known.append(v_known)
            R.append(F_coeff(i, m - 1) - acc)
        for i in range(n_modes):
            Ai, Bi = alg.secular(R[i], i, m)
            A[i].append(Ai)
            B[i].append(Bi)
        if m == order and not last_u:
            break
        for i in range(n_modes):
            u = alg.solve(R[i], i, m)
            U[i].append(u)
            if m < order:
                v = alg.L0(u) + D(m, X0[i]) + known[i]
                Xs[i].append(u)
                Vs[i].append(v)
                XL[i].append(u)
                VL[i].append(v)
    return A, B, U


class OneAngle:
    """A one-angle :class:`~kbm.algebra.base.FourierAlgebra` as the case ``N = 1`` (no
    forcing) of :class:`~kbm.algebra.base.RecursionAlgebra`.

    Its rates are coefficients ``c(a)``: a rate times a series is ``alg.scale(f, c)``, and
    ``L0 = omega0 d/dpsi``.
    """

    dof = 1
    detuned = False

    def __init__(self, alg: FourierAlgebra):
        self.alg = alg
        self.zero = alg.zero

    def x0(self, i: int):
        return self.alg.x0()

    def L0(self, f):
        return self.alg.scale(self.alg.dpsi(f), self.alg.w0)

    def da(self, f, l: int):
        return self.alg.da(f)

    def dpsi(self, f, l: int):
        return self.alg.dpsi(f)

    def sigma_dtheta(self, f):  # pragma: no cover - never asked: detuned is False
        raise TypeError("a one-angle algebra has no forcing angle")

    def times(self, c, f):
        return self.alg.scale(f, c)

    def rate_vanishes(self, c: Any) -> bool:
        return not c

    def secular(self, R, i: int, n: int):
        return self.alg.secular(R)

    def solve(self, R, i: int, n: int):
        return self.alg.solve(R)


def one_angle_recursion(alg: FourierAlgebra, F: sp.Expr, order: int, last_u: bool = True,
                        builder=Builder) -> tuple[list, list, list]:
    """:func:`kbm_recursion` for ``x'' + omega0**2 x = mu F(x, x')`` over a one-angle algebra:
    the lists ``A_1..A_N``, ``B_1..B_N``, ``u_1..u_N``.

    ``builder(alg, X, V).build(F)`` makes the lazy series of ``F`` along the leaves ``X``,
    ``V`` (:class:`~kbm.algebra.lazy_series.Builder` by default).
    """
    def rhs(X, V):
        return [[(0, builder(alg, X[0], V[0]).build(F))]]

    A, B, U = kbm_recursion(OneAngle(alg), rhs, order, last_u=last_u)
    return A[0], B[0], U[0]


class SlowRates:
    """The rates of a multi-angle algebra are its own (slow) series: a rate times a series is
    their product (a mixin of the :class:`~kbm.algebra.base.RecursionAlgebra` algebras whose
    :meth:`secular` returns series)."""

    def times(self, c, f):
        return c * f

    def rate_vanishes(self, c) -> bool:
        return c.is_zero()
