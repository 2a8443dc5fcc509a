"""Cycles whose period grows without bound: multiple shooting in the period, parameter free.

Near a homoclinic (or heteroclinic) end the parameter of a branch converges to ``p_h``
like ``exp(-T/k)``: from a period of about 15 on, the cycle is better continued in its
period ``T``, with ``p`` an unknown (as AUTO's HomCont and Lin's method do).  A single
shooting over ``T`` amplifies errors like ``exp(lambda_u T)`` near each saddle; here the
period is cut into ``M`` segments of at most :data:`SEGMENT` time units:

unknowns ``y_0, ..., y_{M-1}`` (the state at the segment starts) and ``p``;
equations ``y_{j+1} - phi_h(y_j; p) = 0`` (``y_M = y_0``) and the phase ``x'(0) = 0``,

solved by Newton with the segments' monodromy matrices (variational equations) and a
central difference in ``p``.  ``T`` is stepped up by a factor until the target; the new
segment starts are read off the previous orbit at proportionally rescaled times.

:func:`follow_period` returns the ``(T, p)`` pairs; the homoclinic parameter is the limit
of ``p``, which the period law ``T = -k ln|p - p_h| + c`` (:mod:`numerics.cycles.homoclinic`)
extrapolates from the points where ``|p - p_h|`` is still resolved.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from numerics.errors import ConvergenceError, IntegrationError
from numerics.flow import CompiledLine, Method, extended_state, flow

__all__ = ["LongPeriodPoint", "follow_period", "SEGMENT"]

#: longest segment of the multiple shooting (time units): exp(lambda_u SEGMENT) stays small
SEGMENT = 1.0


@dataclass(frozen=True)
class LongPeriodPoint:
    """A cycle of period ``period`` at ``parameter``, its start ``x0`` (``x' = 0``), the
    segments used, Newton's final residual and the non-trivial Floquet multiplier.

    The multiplier is ``exp(int_0^T div f dt)`` (Liouville: the trivial one is 1), summed
    as the logarithms of the segments' monodromy determinants, so that it stays accurate
    where the monodromy's entries grow like ``exp(lambda_u T)``.
    """

    period: float
    parameter: float
    x0: float
    segments: int
    residual: float
    multiplier: float = math.nan


class _Segments:
    def __init__(self, model, params: dict, vary: str, rtol: float, at: float):
        self.model, self.params, self.vary, self.rtol = model, params, vary, rtol
        self.line = CompiledLine(model, params, vary, at)

    def field(self, y, p: float) -> np.ndarray:
        """The vector field ``(x', x'')`` at ``y``."""
        cm = self.line(p)
        return np.array([y[1], cm.acc(0.0, y[0], y[1])])

    def step(self, y, h: float, p: float, extended: bool = True):
        """``(phi_h(y), Phi)`` for one segment; ``self.divergence`` is set to the integral
        of the field's divergence over it (extended only)."""
        cm = self.line(p)
        if extended:
            yT = flow(cm, extended_state(y[0], y[1]), h, 1, Method.COMPILED, self.rtol,
                      self.rtol)[-1]
            self.divergence = float(yT[6])
            return yT[:2], np.array([[yT[2], yT[4]], [yT[3], yT[5]]])
        yT = flow(cm, [y[0], y[1]], h, 1, Method.COMPILED, self.rtol, self.rtol)[-1]
        return yT[:2], None

    def orbit(self, y0, T: float, p: float, n: int) -> np.ndarray:
        """The states at ``n + 1`` equally spaced times over ``[0, T]``, segment by segment
        (each of at most SEGMENT)."""
        cm = self.line(p)
        out = [np.asarray(y0, float)]
        dt = T / n
        for _ in range(n):
            out.append(flow(cm, [out[-1][0], out[-1][1]], dt, 1, Method.COMPILED, self.rtol,
                            self.rtol)[-1][:2])
        return np.array(out)


def _newton(seg: _Segments, Y: np.ndarray, tau: np.ndarray, p: float, T: float,
            ref: np.ndarray, tol: float, max_iter: int, free_p: bool = True):
    """Newton on the segments with Poincare sections: unknowns ``Y`` (M x 2), the segments'
    durations ``tau`` and ``p``; equations ``Y_{j+1} = phi_{tau_j}(Y_j; p)``, ``Y_j`` on the
    plane through ``ref_j`` normal to the flow there, and ``sum tau = T``.

    With ``free_p`` false ``p`` is kept (it has reached its limit ``p_h`` in double
    precision): the equations are then one more than the unknowns, consistent to within
    ``|p - p_h|``, and each step is their least-squares solution, of least norm in the
    directions the matrix does not resolve (rank-revealing QR, LAPACK's ``gelsy``).  Past
    that point how the period is shared among the segments waiting at the saddles is not
    determined in double precision either (the matrix's condition number reaches 1e17), and
    the plain Newton step moves those durations at random."""
    M = len(Y)
    n = 3 * M + 1
    normals = [f / np.linalg.norm(f) for f in (seg.field(r, p) for r in ref)]
    res = math.inf
    for _ in range(max_iter):
        logdet = 0.0
        R = np.zeros(n)
        J = np.zeros((n, n))
        dp = 1e-7 * max(1.0, abs(p))
        for j in range(M):
            k = (j + 1) % M
            yj, Phi = seg.step(Y[j], tau[j], p)
            logdet += seg.divergence  # log det Phi_j (Liouville)
            yp, _ = seg.step(Y[j], tau[j], p + dp, extended=False)
            ym, _ = seg.step(Y[j], tau[j], p - dp, extended=False)
            rows = slice(2 * j, 2 * j + 2)
            R[rows] = Y[k] - yj
            J[rows, 2 * k:2 * k + 2] += np.eye(2)
            J[rows, 2 * j:2 * j + 2] -= Phi
            J[rows, 2 * M + j] = -seg.field(yj, p)
            J[rows, -1] = -(yp - ym) / (2 * dp)
            R[2 * M + j] = float(np.dot(Y[j] - ref[j], normals[j]))
            J[2 * M + j, 2 * j:2 * j + 2] = normals[j]
        R[-1] = float(np.sum(tau) - T)
        J[-1, 2 * M:3 * M] = 1.0
        res = float(np.max(np.abs(R)))
        if res < tol:
            # the residual decides: near the saddles the mesh's points may slide along the
            # orbit at almost no cost (the matrix is nearly singular there), the cycle and
            # p do not
            return Y, tau, p, res, logdet
        if free_p:
            dz = np.linalg.solve(J, -R)
        else:
            from scipy.linalg import lstsq

            dz = np.append(lstsq(J[:, :-1], -R, cond=1e-13, lapack_driver="gelsy")[0], 0.0)
        # damped: every duration stays above a third of itself, p moves by at most 1e-3
        dt = dz[2 * M:3 * M]
        lam = min(1.0, float(np.min(np.where(dt < 0, -(2 / 3) * tau / np.minimum(dt, -1e-300),
                                               np.inf))), 1e-3 / max(abs(dz[-1]), 1e-300))
        dz = lam * dz
        Y = Y + dz[:2 * M].reshape(M, 2)
        tau = tau + dz[2 * M:3 * M]
        p = p + dz[-1]
    raise ConvergenceError(f"multiple shooting at T = {T:.6g} did not converge in {max_iter} "
                           f"iterations (residual {res:.2e})")


def _refine(seg: _Segments, Y: np.ndarray, tau: np.ndarray, p: float):
    """Split every segment longer than SEGMENT in two (the mesh follows the time spent near
    the saddles)."""
    Ys, taus = [], []
    for y, t in zip(Y, tau):
        if t > SEGMENT:
            half = 0.5 * t
            Ys += [y, seg.step(y, half, p, extended=False)[0]]
            taus += [half, half]
        else:
            Ys.append(y)
            taus.append(t)
    return np.array(Ys), np.array(taus)


def follow_period(model, params: dict, vary: str, x0: float, period: float, parameter: float,
                  target: float, *, factor: float = 1.01, rtol: float = 1e-11,
                  tol: float = 1e-9, max_iter: int = 30) -> list[LongPeriodPoint]:
    """Continue the cycle through ``(x0, 0)`` of period ``period`` at ``vary = parameter``
    in its period, up to ``target``, the parameter free.

    Raises
    ------
    numerics.errors.ConvergenceError
        If the first cycle does not converge; later failures end the list (the points
        found so far are returned, the last one's period short of ``target``).
    """
    seg = _Segments(model, dict(params), vary, rtol, parameter)
    M = max(4, math.ceil(period / SEGMENT))
    Y = seg.orbit((x0, 0.0), period, parameter, M)[:-1]
    tau = np.full(M, period / M)
    Y, tau, p, res, logdet = _newton(seg, Y, tau, parameter, period, Y.copy(), tol, max_iter)
    out = [LongPeriodPoint(period, float(p), float(Y[0][0]), M, res, math.exp(logdet))]
    T, step = period, factor - 1.0
    still = 0  # consecutive points at which p moved by less than 1e-12 of itself
    while T < target:
        T_new = min(target, T * (1 + step))
        Yr, taur = _refine(seg, Y, tau, p)
        # the extra time goes where the orbit is slow (near the saddles)
        w = 1.0 / np.array([np.linalg.norm(seg.field(y, p)) for y in Yr]) ** 2
        guess = taur + (T_new - T) * w / w.sum()
        try:
            Yn, taun, pn, res, logdet = _newton(seg, Yr, guess, p, T_new, Yr.copy(), tol,
                                                max_iter, free_p=still < 2)
        except (ConvergenceError, IntegrationError, np.linalg.LinAlgError):
            step /= 2
            if step < 1e-3:
                break  # the points found so far are returned
            continue
        still = still + 1 if abs(pn - p) <= 1e-12 * max(1.0, abs(p)) else 0
        Y, tau, p, T = Yn, taun, pn, T_new
        out.append(LongPeriodPoint(T, float(p), float(Y[0][0]), len(Y), res,
                                   math.exp(logdet)))
        step = min(1.5 * step, 0.1)
    return out
