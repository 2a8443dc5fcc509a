"""The fold of small cycles continued into its Bautin point (issue 38).

Near a Bautin (generalised Hopf) point the fold-of-cycles system of
:meth:`numerics.bifurcation.autonomous.OneDof.cycle_fold` is singular: the cycle shrinks to
the equilibrium and its residuals vanish with its size.  Here the cycle is scaled by its
size ``eps``, an unknown, so that the curve can be followed as ``eps -> 0``:

``x = x_e + eps u,  x' = eps w,  u' = w,  w' = (f(x_e + eps u, eps w) - f(x_e, 0))/eps``

from ``(u, w) = (1, 0)``, and the defining system in ``z = (x_e, eps, T, a, b)``

``x_e - x_e* = 0,  u(T) - 1 = 0,  w(T) = 0,  int_0^T f_v dt / (eps^2 + eps_ref^2) = 0``

with ``x_e*`` the equilibrium (``f(x_e*, 0) = 0``) in extended precision.  The last
equation is the non-trivial multiplier's logarithm (Liouville); on a cycle of radius
``r ~ eps`` near a Hopf point with Lyapunov coefficients ``l1, l2`` it is
``2 T r^2 (l1 + 2 l2 r^2)`` (Kuznetsov, *Elements of Applied Bifurcation Theory*, 3rd
ed., sec. 8.3), so the fold curve leaves the Bautin point (``l1 = 0``) like ``eps^2``; the
weight ``1/(eps^2 + eps_ref^2)`` only scales the row (its zero set is that of the
multiplier's).

The fold condition is ``O(eps^2)`` beside the ``O(1)`` cycle, so the orbit is needed to
``~1e-18``: the scaled flow is integrated in extended precision (``numpy.longdouble``,
64-bit mantissa) by a fixed-step explicit Runge–Kutta method of order 8 (Dormand–Prince,
Hairer, Nørsett & Wanner, *Solving ODEs I*, II.5; its weights moved by ~1e-16 so that the
conditions up to order 3 hold to the extended precision, :func:`_exact_weights`), and for
``|eps| <= EPS_TAYLOR`` the field is ``f``'s Taylor series about ``(x_e*, 0)`` (no
cancellation in ``f(x_e + eps u) - f(x_e)``).  The Jacobian's columns are one batch.

:func:`into_bautin` follows the curve from a point of the ordinary fold curve down to
``eps_min`` and ends it at the Bautin point itself, the ``eps = 0`` member of the family,
solved from its own system (Hopf conditions and ``l1 = 0``, :meth:`OneDof.hopf`,
:meth:`OneDof.lyapunov`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import sympy as sp
from scipy.integrate._ivp import dop853_coefficients as _dop

from numerics._show import num
from numerics.bifurcation.corrector import correct, numerical_jacobian
from numerics.errors import ConvergenceError
from numerics.flow.template import acceleration_jacobian

__all__ = ["ScaledFold", "bautin_point", "into_bautin"]

#: below this |eps| the scaled field is f's Taylor series of this order (truncation
#: ~ eps^K f^(K+1)/(K+1)!, below the extended precision's rounding)
EPS_TAYLOR, TAYLOR_ORDER = 2e-3, 9
_LD = np.longdouble
_S = _dop.N_STAGES
_A = np.array(_dop.A[:_S, :_S], dtype=_LD)
_B = np.array(_dop.B, dtype=_LD)



def _exact_weights(A: np.ndarray, B: np.ndarray) -> np.ndarray:
    """``B`` moved (by ~1e-16, least change) so that the order conditions up to order 3 of
    the autonomous method (``c = A 1``) hold in extended precision: the float64 tableau's
    defects (~1e-16) would add a first-order error ``~1e-16 h`` (the fold system needs the
    orbit to ~1e-18)."""
    c = A.sum(axis=1)
    M = np.array([np.ones_like(c), c, c * c, A @ c])
    target = np.ones(4, dtype=_LD) / np.array([1, 2, 3, 6], dtype=_LD)
    defect = target - M @ B
    return B + np.linalg.pinv(M.astype(float)).astype(_LD) @ defect


_B = _exact_weights(_A, _B)


class ScaledFold:
    """The amplitude-scaled fold system of ``kit`` (a :class:`OneDof`), module docstring.

    Parameters
    ----------
    kit : OneDof
    steps : int
        Runge–Kutta steps over one period.
    """

    def __init__(self, kit, steps: int = 600, eps_ref: float = 1.0):
        self.kit, self.steps, self.eps_ref = kit, steps, eps_ref
        acc = kit.template.model.acceleration()
        X, V = sp.Symbol("x"), sp.Symbol("xdot")
        syms = [sp.Symbol(n) for n in kit.template.names]
        self._f = sp.lambdify((X, V, *syms), acc, modules="numpy")
        fx, fv = acceleration_jacobian(acc, kit.template.model.name)
        self._fv = sp.lambdify((X, V, *syms), fv, modules="numpy")
        self._fx = sp.lambdify((X, V, *syms), fx, modules="numpy")
        # the Taylor coefficients d^(i+j) f / dx^i dv^j / (i! j!) at (x_e, 0), 1 <= i+j <= K
        self._taylor = []
        for n in range(1, TAYLOR_ORDER + 1):
            for i in range(n + 1):
                e = sp.diff(acc, X, i, V, n - i).subs(V, 0)
                if e != 0:
                    c = sp.Rational(1, math.factorial(i) * math.factorial(n - i))
                    self._taylor.append((i, n - i, sp.lambdify((X, *syms), c * e,
                                                               modules="numpy")))

    def _params(self, Z: np.ndarray, dZ: np.ndarray | None) -> list:
        pv = np.array([self.kit.compiled(a, b).pvec for a, b in Z[:, 3:5]], dtype=_LD)
        if dZ is not None and np.any(dZ[:, 3:5] != 0):  # pvec's linear change (exact here)
            for row, (a, b) in enumerate(Z[:, 3:5]):
                for k, (da, db) in enumerate(((1, 0), (0, 1))):
                    h = 1e-6 * (1 + abs(Z[row, 3 + k]))
                    dp = (np.asarray(self.kit.compiled(a + da * h, b + db * h).pvec, dtype=_LD)
                          - np.asarray(self.kit.compiled(a - da * h, b - db * h).pvec,
                                       dtype=_LD)) / _LD(2 * h)
                    pv[row] = pv[row] + dp * dZ[row, 3 + k]
        return [pv[:, k] for k in range(pv.shape[1])]

    def ends(self, Z, dZ=None) -> np.ndarray:
        """The residuals (module docstring) at the rows of ``Z`` (a batch of ``z``), each
        plus its offset in ``dZ`` (extended precision, :meth:`polish`)."""
        Z = np.atleast_2d(np.asarray(Z, dtype=float))
        if np.any(Z[:, 2] <= 0) or np.any(Z[:, 1] == 0):
            raise ConvergenceError("the scaled cycle needs T > 0 and eps != 0")
        dZ = None if dZ is None else np.atleast_2d(np.asarray(dZ, dtype=_LD))
        P = self._params(Z, dZ)
        ZL = Z.astype(_LD) if dZ is None else Z.astype(_LD) + dZ
        xe, eps = ZL[:, 0], ZL[:, 1]
        zero = _LD(0) * xe
        x_in = xe
        for _ in range(3):  # the equilibrium in extended precision: the flow's centre
            xe = xe - self._f(xe, zero, *P) / self._fx(xe, zero, *P)
        f0 = self._f(xe, zero, *P)
        if float(np.max(np.abs(Z[:, 1]))) <= EPS_TAYLOR:  # cancellation-free: f's series
            terms = [(i, j, c(xe, *P) * eps ** (i + j - 1)) for i, j, c in self._taylor]

            def acc(y):
                return sum(c * y[0] ** i * y[1] ** j for i, j, c in terms)
        else:
            def acc(y):
                return (self._f(xe + eps * y[0], eps * y[1], *P) - f0) / eps

        def rhs(y):
            return np.array([y[1], acc(y), self._fv(xe + eps * y[0], eps * y[1], *P)])

        n = len(Z)
        y = np.array([np.ones(n, dtype=_LD), np.zeros(n, dtype=_LD), np.zeros(n, dtype=_LD)])
        h = ZL[:, 2] / self.steps
        K = np.empty((_S,) + y.shape, dtype=_LD)
        for _ in range(self.steps):
            for s in range(_S):
                K[s] = rhs(y + h * np.tensordot(_A[s, :s], K[:s], axes=(0, 0)))
            y = y + h * np.tensordot(_B, K, axes=(0, 0))
        out = np.array([x_in - xe, y[0] - 1, y[1], y[2] / (eps ** 2 + _LD(self.eps_ref) ** 2)]).T
        return out if dZ is not None else np.asarray(out, dtype=float)

    def G(self, z) -> np.ndarray:
        """``G(z)``, ``z = (x_e, eps, T, a, b)``."""
        return self.ends(np.asarray(z, dtype=float)[None, :])[0]

    def jac(self, z, h: float = 1e-7) -> np.ndarray:
        """``G'(z)`` by central differences (steps ``h (1 + |z_i|)``), in one batch."""
        z = np.asarray(z, dtype=float)
        steps = h * (1.0 + np.abs(z))
        steps[1] = h * abs(z[1])  # eps: relative, it tends to 0
        E = np.diag(steps)
        R = self.ends(np.vstack([z + E, z - E]))
        return ((R[:len(z)] - R[len(z):]) / (2 * steps[:, None])).T


def bautin_point(kit, guess: Sequence[float]) -> np.ndarray:
    """The Bautin point ``(x_e, a, b)``: Hopf conditions and ``l1 = 0`` (Newton from
    ``guess``)."""
    G, _ = kit.hopf()

    def H(z):
        return np.concatenate([G(z), [kit.lyapunov(*z)]])

    z = np.asarray(guess, dtype=float)
    for _ in range(40):
        r = H(z)
        dz = np.linalg.solve(numerical_jacobian(H, z, 1e-6), -r)
        z = z + dz
        if np.max(np.abs(dz)) < 1e-14 * (1 + np.max(np.abs(z))):
            break
    if not np.max(np.abs(H(z))) < 1e-11:
        near = ", ".join(num(g, 6) for g in np.asarray(guess, dtype=float))
        raise ConvergenceError(f"no Bautin point near (x_e, a, b) = ({near}): residual "
                               f"{num(np.max(np.abs(H(z))), 3)} (Hopf conditions and l1 = 0; "
                               "1e-11 needed)")
    return z


def into_bautin(kit, fold_point: Sequence[float], bautin: Sequence[float], *, eps_min: float = 1e-4, ratio: float = 0.25,
                steps: int = 600, progress=None) -> dict:
    """The fold curve from ``fold_point = (x0, T, a, b)`` (a converged point of the ordinary
    fold system near the Hopf curve) into the Bautin point near ``bautin = (x_e, a, b)``.

    The scaled system (:class:`ScaledFold`) is solved by Newton's method at
    ``eps = eps0 ratio^k`` down to ``eps_min`` (the last value ``eps_min`` itself), each from
    the prediction ``z_B + (z_prev - z_B)(eps/eps_prev)^2`` (the fold curve leaves the
    Bautin point like ``eps^2``, Kuznetsov sec. 8.3), and ended at the Bautin point, the
    family's member at ``eps = 0``, solved from its own system (:func:`bautin_point`).

    Returns a dict: ``points`` (the converged ``z = (x_e, eps, T, a, b)``, ``eps``
    decreasing), ``residuals``, ``end`` (the Bautin point ``(x_e, a, b)``).
    """
    x0, T, a, b = (float(v) for v in fold_point)
    sf = ScaledFold(kit, steps)
    end = bautin_point(kit, bautin)
    eqs = [x for x, _ in kit.equilibria(a, b, max(2.0, 2 * abs(end[0]) + 1))]
    xe = min(eqs, key=lambda x: abs(x - end[0]))  # the equilibrium at (a, b) nearest x_B
    row = np.zeros(5)
    row[1] = 1.0
    z = np.array([xe, x0 - xe, T, a, b])
    w = 2 * math.pi / math.sqrt(max(1e-300, -kit.d(1, 0, end[0], 0.0, end[1], end[2])))
    zb = np.array([end[0], 0.0, w, end[1], end[2]])
    points, residuals = [], []
    eps = z[1]
    # the cycle at the start's (eps, a) first (x_e, T, b; Newton), then the fold
    cyc = np.array([z[0], z[2], z[4]])

    def cycle(u):
        return sf.G([u[0], z[1], u[1], z[3], u[2]])[:3]

    for _ in range(12):
        r = cycle(cyc)
        if float(np.max(np.abs(r))) < 1e-14:
            break
        cyc = cyc - np.linalg.solve(numerical_jacobian(cycle, cyc), r)
    z = np.array([cyc[0], z[1], cyc[1], z[3], cyc[2]])
    while True:
        guess = z if not points else zb + (z - zb) * (eps / z[1]) ** 2
        guess[1] = eps
        z, res, _, _ = correct(sf.G, guess, row, eps, jac=sf.jac, tol=1e-13, xtol=1e-9,
                               max_steps=20)
        points.append(z)
        residuals.append(res)
        if progress is not None:
            progress(z)
        if abs(eps) <= eps_min:
            break
        eps = math.copysign(max(eps_min, abs(eps) * ratio), eps)
    return {"points": points, "residuals": residuals, "end": end}
