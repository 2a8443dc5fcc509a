"""The defining systems of the codim-1 bifurcations of an autonomous one-degree-of-freedom
model ``x'' = f(x, x')`` in two parameters ``(a, b)``.

:class:`OneDof` holds the model at fixed values of its other parameters and gives ``f`` and
its derivatives at ``(a, b)`` (from the model's symbolic acceleration) and the extended flow
(state, fundamental matrix, ``int div f dt``; :mod:`numerics.flow`, the compiled DOP853 of
the shooting code where numba is available).  The defining systems, ``G(z) = 0`` with ``z``
ending in ``(a, b)``, for :func:`numerics.bifurcation.curve.continue_curve`:

- :meth:`OneDof.hopf`: ``z = (x, a, b)``, ``f(x, 0) = 0`` and ``tr J = f_v(x, 0) = 0``; a
  Hopf point where ``det J = -f_x > 0`` (else a neutral saddle); test functions ``det J``
  (zero: Bogdanov–Takens) and the first Lyapunov coefficient (zero: Bautin);
- :meth:`OneDof.saddle_node`: ``z = (x, a, b)``, ``f = f_x = 0`` (a fold of equilibria);
  test functions ``f_v`` (Bogdanov–Takens) and ``f_xx`` (cusp);
- :meth:`OneDof.cycle_fold`: ``z = (x0, T, a, b)``, the shooting residual
  ``(x(T) - x0, x'(T))`` from ``(x0, 0)`` and ``int_0^T div f dt = 0`` (the non-trivial
  Floquet multiplier is 1, Liouville's formula; it is ``exp`` of a real number, so a
  planar autonomous flow has no period doubling).

The first Lyapunov coefficient of ``x' = v, v' = f(x, v)`` at a Hopf point (``f_v = 0``,
``f_x = -w^2``) is, with the canonical form of Guckenheimer & Holmes (3.4.11) after
``u = x, w_ = -v/w``,

``l1 = (f_xxv + w^2 f_vvv + f_xv (f_xx/w^2 + f_vv))/16``

(negative: supercritical; van der Pol ``f = -x + mu (1 - x^2) v`` gives ``-mu/8``).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from types import MappingProxyType

import numpy as np
import sympy as sp
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from numerics._memo import memo
from numerics.errors import ConvergenceError, IntegrationError
from numerics.flow import compile_model, extended_state, template_flow

__all__ = ["OneDof", "Equilibrium"]

#: tolerances of the shooting flow in the defining systems of cycles
RTOL, ATOL = 1e-12, 1e-13
#: the derivatives of f kept (orders in x, v)
_ORDERS = ((0, 0), (1, 0), (0, 1), (2, 0), (1, 1), (0, 2), (3, 0), (2, 1), (0, 3))


class Equilibrium(tuple):
    """``(x, kind)`` with kind ``"saddle"``, ``"center"`` (a focus or node: ``f_x < 0``)."""


class OneDof:
    """The model ``x'' = f(x, x')`` at ``params`` with the two parameters ``axes`` free.

    Parameters
    ----------
    model : Oscillator or str
    params : Mapping
        The other parameters (physical or scaled names, ``mu``); values of the axes in it
        are ignored.
    axes : (str, str)
        The names of ``a`` and ``b`` (as the user gave them: ``Delta``, ``beta``, ``mu``).
    """

    def __init__(self, model, params: Mapping, axes: tuple[str, str], at: tuple[float, float]):
        self.model = model
        self.axes = tuple(axes)
        self.params = {k: v for k, v in dict(params).items() if k not in self.axes}
        self._cache: dict = {}
        cm = self.compiled(*at)
        self.template = cm.template
        self._plane = _plane(model, self.params, self.axes, at, cm.template)
        self.flow = template_flow(cm.template)
        self._d, self._f_rest, self.odd = _derivatives(cm.template.model,
                                                       cm.template.names)

    def compiled(self, a: float, b: float):
        """The :class:`numerics.flow.CompiledModel` at ``(a, b)`` (memoised)."""
        key = (float(a), float(b))
        cm = self._cache.get(key)
        if cm is None:
            if len(self._cache) > 4096:
                self._cache.clear()
            values = {**self.params, self.axes[0]: key[0], self.axes[1]: key[1]}
            cm = _on_plane(getattr(self, "_plane", None), self.model, values, key)
            if cm is None:
                cm = compile_model(self.model, values, template=getattr(self, "template", None))
            self._cache[key] = cm
        return cm

    def d(self, i: int, j: int, x: float, v: float, a: float, b: float) -> float:
        """``d^(i+j) f / dx^i dv^j`` at ``(x, v)`` and ``(a, b)``."""
        return float(self._d[(i, j)](x, v, *self.compiled(a, b).pvec))

    # -- equilibria ---------------------------------------------------------------------------
    def equilibria(self, a: float, b: float, L: float, n: int = 4001) -> list[Equilibrium]:
        """The zeros of ``f(x, 0)`` on ``[-L, L]`` (sign changes on ``n`` points, Brent),
        each with its kind."""
        cm = self.compiled(a, b)
        f = self._d[(0, 0)]
        pv = cm.pvec
        xs = np.linspace(-L, L, n)
        vals = _on_grid(self._f_rest, f, xs, pv)
        out = []
        for k in np.flatnonzero((vals[:-1] == 0) | (vals[:-1] * vals[1:] < 0)):
            x = xs[k] if vals[k] == 0 else brentq(lambda s: f(s, 0.0, *pv), xs[k], xs[k + 1],
                                                   xtol=1e-14, rtol=1e-15)
            fx = self.d(1, 0, x, 0.0, a, b)
            out.append(Equilibrium((float(x), "saddle" if fx > 0 else "center")))
        return out

    def eigen(self, x: float, a: float, b: float) -> tuple[float, float]:
        """``(tr J, det J) = (f_v, -f_x)`` at the equilibrium ``x``."""
        return self.d(0, 1, x, 0.0, a, b), -self.d(1, 0, x, 0.0, a, b)

    def lyapunov(self, x: float, a: float, b: float) -> float:
        """The first Lyapunov coefficient at a Hopf point (module docstring)."""
        w2 = -self.d(1, 0, x, 0.0, a, b)
        if w2 <= 0:
            return float("nan")
        dd = {k: self.d(*k, x, 0.0, a, b) for k in ((2, 0), (1, 1), (0, 2), (2, 1), (0, 3))}
        return (dd[(2, 1)] + w2 * dd[(0, 3)] + dd[(1, 1)] * (dd[(2, 0)] / w2 + dd[(0, 2)])) / 16

    # -- defining systems ------------------------------------------------------------------------
    def hopf(self):
        """``(G, tests)`` of the Hopf curve, ``z = (x, a, b)``."""
        def G(z):
            x, a, b = z
            return np.array([self.d(0, 0, x, 0.0, a, b), self.d(0, 1, x, 0.0, a, b)])

        tests = {"bogdanov-takens": lambda z: -self.d(1, 0, z[0], 0.0, z[1], z[2]),
                 "bautin": lambda z: self.lyapunov(*z)}
        return G, tests

    def saddle_node(self):
        """``(G, tests)`` of the fold of equilibria, ``z = (x, a, b)``."""
        def G(z):
            x, a, b = z
            return np.array([self.d(0, 0, x, 0.0, a, b), self.d(1, 0, x, 0.0, a, b)])

        tests = {"bogdanov-takens": lambda z: self.d(0, 1, z[0], 0.0, z[1], z[2]),
                 "cusp": lambda z: self.d(2, 0, z[0], 0.0, z[1], z[2])}
        return G, tests

    def end_state(self, x0: float, T: float, a: float, b: float) -> np.ndarray:
        """The extended state after ``T`` from ``(x0, 0)``: ``(x, v, Phi11, Phi21, Phi12,
        Phi22, int div f, ...)`` (compiled DOP853 at rtol 1e-12, else scipy's)."""
        if not (T > 0 and math.isfinite(x0)):
            raise ConvergenceError(f"left the domain: x0 = {x0:.6g}, T = {T:.6g}")
        cm = self.compiled(a, b)
        if self.flow is not None:
            r = self.flow(extended_state(x0), T, cm.pvec, RTOL, ATOL)
            if r.status:
                raise IntegrationError(f"the flow from x0 = {x0:.6g} failed: {r.message}")
            return np.asarray(r.y[-1], dtype=float)
        sol = solve_ivp(cm.rhs_ext, (0.0, T), extended_state(x0), method="DOP853", rtol=RTOL,
                        atol=ATOL)
        if not sol.success:
            raise IntegrationError(sol.message)
        return sol.y[:, -1]

    def cycle_fold(self):
        """``G`` of the fold of cycles, ``z = (x0, T, a, b)``."""
        def G(z):
            x0, T, a, b = z
            y = self.end_state(x0, T, a, b)
            return np.array([y[0] - x0, y[1], y[6]])
        return G


@memo(maxsize=16)
def _derivatives(model, names: tuple[str, ...]):
    """``(d, f_rest, odd)`` of ``model`` with its parameter values in the order ``names`` (a
    template's, :class:`numerics.flow.ModelTemplate`): ``d[(i, j)](x, v, *pvec)`` the
    derivatives of ``f`` in :data:`_ORDERS` (lambdified with ``math``; a read-only mapping),
    ``f_rest(x, v, *pvec)`` the function ``f`` of an array ``x`` (``numpy``: ``f(x, 0)`` on a
    grid), and whether ``f`` is odd (``f(-x, -v) = -f(x, v)``).

    A pure-function memo: its arguments are immutable values (a frozen, hashable model and a
    tuple of names), its value is immutable and a function of them alone, so a cached value
    is what a fresh call gives (``tests/test_memo_purity.py``)."""
    acc = model.acceleration()
    X, V = sp.Symbol("x"), sp.Symbol("xdot")
    syms = [sp.Symbol(n) for n in names]
    d = {}
    for i, j in _ORDERS:
        e = sp.diff(acc, X, i, V, j) if (i or j) else acc
        d[(i, j)] = sp.lambdify((X, V, *syms), e, modules=["math", "scipy"])
    f_rest = sp.lambdify((X, V, *syms), acc, modules=["numpy", "scipy"])
    odd = bool(sp.simplify(acc.subs({X: -X, V: -V}, simultaneous=True) + acc) == 0)
    return MappingProxyType(d), f_rest, odd


def _on_grid(f_rest, f, xs: np.ndarray, pv) -> np.ndarray:
    """``f(x, 0)`` on the grid ``xs`` as the scalar ``f`` gives it, where it matters: the
    array function ``f_rest`` everywhere, the scalar one at the points where ``|f|`` is
    within ``1e-8`` of its largest size on the grid (a sign there could differ by the last
    bits of ``numpy``'s functions against ``math``'s); the scalar one everywhere where the
    array function does not give finite values of the grid's shape."""
    try:
        with np.errstate(all="ignore"):
            vals = np.asarray(f_rest(xs, 0.0, *pv), dtype=float)
    except (TypeError, ValueError, ArithmeticError, AttributeError):
        vals = None
    if vals is None or vals.shape != xs.shape or not np.all(np.isfinite(vals)):
        return np.array([f(x, 0.0, *pv) for x in xs])
    vals = vals.copy()
    for k in np.flatnonzero(np.abs(vals) <= 1e-8 * (1.0 + float(np.max(np.abs(vals))))):
        vals[k] = f(xs[k], 0.0, *pv)
    return vals


def _plane(model, params: Mapping, axes: tuple[str, str], at: tuple[float, float], template):
    """``(line along a at b0, kbm.parameters.bound.ParameterLine along b at a0)``: the model bound
    once, each point's values from the two lines (no sympy), where no value of the template
    depends on both axes (``delta = Delta/mu`` over ``(Delta, mu)`` does) and the line's
    template is the model's; else ``None`` (:func:`numerics.flow.compile_model` at each
    point)."""
    from kbm.parameters.bound import ParameterLine
    from numerics.flow import CompiledLine

    try:
        line_a = CompiledLine(model, {**params, axes[1]: at[1]}, axes[0], at[0])
        line_b = ParameterLine(model, {**params, axes[0]: at[0]}, axes[1], at[1])
    except (ValueError, ArithmeticError, TypeError):
        return None
    if set(line_a.line.changed) & set(line_b.changed) or line_a.template != template:
        return None
    return line_a, line_b


def _on_plane(plane, model, values: Mapping, key: tuple[float, float]):
    """The compiled model at ``key`` from ``plane`` (:func:`_plane`), equal to
    :func:`numerics.flow.compile_model`'s; ``None`` where the plane cannot give it."""
    if plane is None:
        return None
    from kbm.parameters.bound import bind

    line_a, line_b = plane
    try:
        others = line_b.floats(key[1])
        if others is None:
            return None
        return line_a.with_values(key[0], others, lambda: bind(model, values))
    except (ValueError, ArithmeticError, TypeError):
        return None
