"""The sliding potential of the paper's eq. (4) and the quasi-static slip energy.

``U(x, L) = Omega^2 (x - L)^2 / 2 - (Delta/k) cos(k x)``, ``k = 2 pi/lambda``, with
``L = v t`` the stage position.  A stick state is a minimum of ``U(., L)``; it
disappears at a saddle-node point where ``dU/dx = 0 = d^2U/dx^2``:
``cos(k x0) = -Omega^2/(Delta k)`` and ``L0 = x0 + Delta sin(k x0)/Omega^2``.
This exists only when ``Delta k > Omega^2`` (otherwise ``U`` has a single
minimum for every ``L``: smooth sliding, no stick-slip).  In a quasi-static
slip the slider jumps from ``x0`` to a minimum ``x1`` of ``U(., L0)`` further on
and the energy ``Delta W = U(x0, L0) - U(x1, L0)`` is dissipated.

None of these formulas is typed here: :func:`eq4` derives ``U``, its derivatives, the
saddle node's ``x0`` and ``L0`` and the spring force once from the symbolic CDC
(:mod:`kbm.model.builtins`): the substrate is the model's conservative potential
(:func:`numerics.flow.template.conservative_potential`, the one derivation the flow
template and ``kbm slide``'s energy audit use) in the physical ``Delta = mu delta``, the
spring the one to the stage's drive ``Omega^2 v t`` at ``L = v t``; ``x0`` and ``L0`` are
sympy's roots of ``d^2U/dx^2 = 0`` and ``dU/dx = 0``.

References
----------
M. D'Acunto, eq. (4) and Section 2; the Prandtl-Tomlinson model (Tomlinson 1929).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from kbm.errors import ParameterError

__all__ = ["potential", "SaddleNode", "saddle_node", "slip_energy", "Eq4", "eq4"]


@dataclass(frozen=True)
class Eq4:
    """The paper's eq. (4) and what follows from it, as numerical functions of
    ``(x, L, Delta, k, Omega)`` (``x0`` of ``(Delta, k, Omega)``, ``L0`` of
    ``(x, Delta, k, Omega)``).

    Attributes
    ----------
    U, dU, d2U
        ``U(x, L)`` and its first two derivatives in ``x``.
    x0
        The root of ``d^2U/dx^2 = 0`` on the rising flank of the well at 0 (the saddle
        node's slider position; defined where ``Delta k > Omega^2``).
    L0
        The stage position at which ``x`` is an equilibrium (``dU/dx = 0``).
    spring_force
        ``-d/dx`` of the spring's part of ``U``: the force on the slider pulled to ``L``.
    expr
        ``U`` as a sympy expression (its symbols ``x, L, Delta, k, Omega``).
    """

    U: Callable
    dU: Callable
    d2U: Callable
    x0: Callable
    L0: Callable
    spring_force: Callable
    expr: object


def _product_sum(expr, args: tuple, modules: str) -> Callable:
    """``expr``, a sum of products ``c(Delta, k, Omega) f(x, L, k)``, lambdified with each
    ``c`` evaluated apart before it multiplies ``f``: the order of the operations of eq. (4)
    written as ``Omega^2 (x - L)^2/2 - (Delta/k) cos(k x)``, so that the values keep their
    last bits (sympy would print ``-Delta*cos(k*x)/k``)."""
    import sympy as sp

    x, L = args[:2]
    grouped = []
    for term in sp.Add.make_args(expr):
        coef, factor = term.as_independent(x, L, as_Add=False)
        grouped.append(sp.UnevaluatedExpr(coef) * factor)
    return sp.lambdify(args, sp.Add(*grouped), modules)


@functools.lru_cache(maxsize=2)
def eq4(modules: str = "math") -> Eq4:
    """Eq. (4) derived once from the symbolic CDC (the module's docstring), lambdified with
    ``modules`` (``"math"`` for scalars, ``"numpy"`` for arrays).

    Examples
    --------
    >>> eq4().expr
    -Delta*cos(k*x)/k + Omega**2*(-L + x)**2/2
    """
    import sympy as sp

    from kbm.model.builtins import get_model
    from kbm.parameters.names import names_of
    from kbm.symbols import t as T, x as X

    from ..flow.template import conservative_potential

    model = get_model("cdc")
    L, v = sp.Symbol("L"), sp.Dummy("v")
    delta = sp.Symbol("delta")
    substrate = conservative_potential(model).subs(delta, names_of("cdc").physical["delta"])
    # eq. (4)'s zero of energy: the additive constant of int_0^x dropped
    substrate = sp.Add(*[u for u in sp.Add.make_args(sp.expand(substrate)) if u.has(X)])
    drive = model.with_stage_velocity(v).drive.subs(T, L / v)
    spring = sp.factor((model.omega0**2 * X - drive)**2 / (2 * model.omega0**2))
    U = spring + substrate
    args = (X, L) + tuple(sp.Symbol(n) for n in ("Delta", "k", "Omega"))
    dU, d2U = sp.diff(U, X), sp.diff(U, X, 2)
    # the root on the rising flank of the well at 0, in (0, lam/2): at Delta = 3, lam = 1,
    # Omega = 1 (the paper's) acos(.)/k, not 2 pi/k minus it
    paper = dict(zip(args[2:], (3, 2 * sp.pi, 1)))
    (x0,) = [r for r in sp.solve(d2U, X) if 0 < r.subs(paper) < sp.Rational(1, 2)]
    (L0,) = sp.solve(dU, L)
    return Eq4(U=_product_sum(U, args, modules),
               dU=sp.lambdify(args, dU, modules), d2U=sp.lambdify(args, d2U, modules),
               x0=sp.lambdify(args[2:], x0, modules),
               L0=sp.lambdify((X,) + args[2:], L0, modules),
               spring_force=sp.lambdify(args, -sp.diff(spring, X), modules), expr=U)


def _check(Delta: float, lam: float, Omega: float) -> float:
    for name, val in (("Delta", Delta), ("lam", lam), ("Omega", Omega)):
        if not math.isfinite(val):
            raise ParameterError(f"{name} must be finite, got {val}")
    if lam <= 0:
        raise ParameterError(f"the period of the potential lam must be > 0, got {lam}")
    if Omega <= 0:
        raise ParameterError(f"the spring frequency Omega must be > 0, got {Omega}")
    if Delta < 0:
        raise ParameterError(f"the strength of the potential Delta must be >= 0, got {Delta}")
    return 2 * math.pi / lam


def potential(x, L, *, Delta: float, lam: float = 1.0, Omega: float = 1.0):
    """``U(x, L) = Omega^2 (x - L)^2/2 - (Delta lam/2 pi) cos(2 pi x/lam)`` (paper eq. 4,
    :func:`eq4`)."""
    k = _check(Delta, lam, Omega)
    x = np.asarray(x, dtype=float)
    return eq4("numpy").U(x, L, Delta, k, Omega)


@dataclass(frozen=True, eq=False)
class SaddleNode:
    """The loss of the stick state and the quasi-static slip that follows.

    Attributes
    ----------
    x0, L0
        Slider and stage position where the stick state disappears.
    static_force
        Spring force ``Omega^2 (L0 - x0) = Delta sin(k x0)`` at that moment: the
        quasi-static static friction (slightly less than ``Delta``).
    minima
        The next minima ``x1, x2, ...`` of ``U(., L0)`` after ``x0`` (one per well).
    delta_W
        ``U(x0, L0) - U(x_j, L0)`` for each of those minima; ``delta_W[0]`` is the
        one-well slip energy of the paper.
    """

    x0: float
    L0: float
    static_force: float
    minima: tuple[float, ...]
    delta_W: tuple[float, ...]


def saddle_node(Delta: float, lam: float = 1.0, Omega: float = 1.0, *,
                n_wells: int = 4) -> SaddleNode | None:
    """The saddle-node point of eq. (4) and the slip energies to the next ``n_wells`` minima.

    Returns ``None`` when ``Delta k <= Omega^2`` (no stick-slip).

    Examples
    --------
    >>> s = saddle_node(3.0, 1.0, 1.0)
    >>> round(s.static_force, 6), round(s.delta_W[0], 6)
    (2.995775, 2.583491)
    """
    k = _check(Delta, lam, Omega)
    f = eq4()
    # d^2U/dx^2 = Omega^2 + Delta k cos(k x) has a root (x0's arccos is defined) only here
    if not (Delta > 0 and f.d2U(math.pi / k, 0.0, Delta, k, Omega) < 0):
        return None
    x0 = f.x0(Delta, k, Omega)  # on the rising flank of the well at 0
    L0 = f.L0(x0, Delta, k, Omega)
    force = f.spring_force(x0, L0, Delta, k, Omega)

    def dU(x):
        return f.dU(x, L0, Delta, k, Omega)

    minima = []
    lo = x0 + 1e-9 * lam
    step = lam / 64
    x = lo
    while len(minima) < n_wells and x < x0 + (n_wells + 2) * lam + abs(L0):
        a, b = x, x + step
        fa, fb = dU(a), dU(b)
        if fa < 0 <= fb:  # dU goes up through zero: a minimum of U
            minima.append(brentq(dU, a, b, xtol=1e-15, rtol=1e-15))
        x = b
    U0 = float(potential(x0, L0, Delta=Delta, lam=lam, Omega=Omega))
    dW = tuple(U0 - float(potential(m, L0, Delta=Delta, lam=lam, Omega=Omega)) for m in minima)
    return SaddleNode(x0=x0, L0=L0, static_force=force, minima=tuple(minima), delta_W=dW)


def slip_energy(Delta: float, lam: float = 1.0, Omega: float = 1.0) -> float | None:
    """``Delta W`` of a one-well quasi-static slip (``None`` when there is no stick-slip)."""
    s = saddle_node(Delta, lam, Omega, n_wells=1)
    return None if s is None else s.delta_W[0]
