"""Newton's method on a cycle's shooting problem, compiled with the sensitivity flow.

This file is read as text and appended, after the DOP853 stepper, to the module that
:func:`numerics.flow.sensitivity.sensitivity_flow` prints (its ``rhs`` and ``flow``
integrate the nine states of :mod:`numerics.flow.sensitivity`); numba compiles all three.

:func:`shoot_correct` is the corrector of
:meth:`numerics.shooting.planar.PlanarProblem.correct`, step for step, without a return to Python between its iterations: the unknowns are
``u = (x0, T, p)`` of the cycle through ``(x0, 0)``; the equations ``R(u) = 0`` (the
return to the start, or in half-period mode ``y(T/2) = -y(0)``) and one linear condition
``row . u = target``; the Jacobian from the variational equations and the parameter
sensitivity of one integration.  The model's parameter vector must be affine in ``p``
(``pbase + (p - p_ref) rates``), as it is when every derived value is linear in the varied
parameter (``delta = Delta/mu`` in ``Delta``); the caller checks that.
"""

import math

import numpy as np
from numba import njit


@njit(cache=True)
def _solve3(J, r, out):
    """``out = J^-1 r`` for a 3x3 ``J`` by Gaussian elimination with partial pivoting;
    ``False`` when a pivot vanishes (singular)."""
    a = J.copy()
    b = r.copy()
    for c in range(3):
        piv = c
        for i in range(c + 1, 3):
            if abs(a[i, c]) > abs(a[piv, c]):
                piv = i
        if a[piv, c] == 0.0:
            return False
        if piv != c:
            for j in range(3):
                a[c, j], a[piv, j] = a[piv, j], a[c, j]
            b[c], b[piv] = b[piv], b[c]
        for i in range(c + 1, 3):
            f = a[i, c] / a[c, c]
            for j in range(c, 3):
                a[i, j] -= f * a[c, j]
            b[i] -= f * b[c]
    for i in range(2, -1, -1):
        s = b[i]
        for j in range(i + 1, 3):
            s -= a[i, j] * out[j]
        out[i] = s / a[i, i]
    return True


@njit(cache=True)
def _trivial_distance(m00, m01, m10, m11):
    """``|m - 1|`` for the eigenvalue ``m`` of the 2x2 matrix closest to 1."""
    half_tr = 0.5 * (m00 + m11)
    disc = half_tr * half_tr - (m00 * m11 - m01 * m10)
    if disc >= 0.0:
        r = math.sqrt(disc)
        return min(abs(half_tr + r - 1.0), abs(half_tr - r - 1.0))
    return math.hypot(half_tr - 1.0, math.sqrt(-disc))


@njit(cache=True)
def shoot_correct(u0, row, target, pbase, rates, p_ref, half, rtol, n_out, max_steps,
                  max_iter, tol_residual, tol_correction, tol_accuracy, trivial_tol,
                  noise_rtol):
    """Newton on ``R(u) = 0, row . u = target`` from ``u0``.

    Returns ``(status, it, u, R, A, b, ys, info)``: status 0 converged (``u`` with the last
    Newton correction, already below the tolerance, added; the last integration, at ``u``
    before it, stands for the point: ``ys`` its samples, of half the period in half-period
    mode), 1 the integration failed (``info`` = the stepper's status, the time reached is
    not known), 2 a step too large, 3 no convergence in ``max_iter`` iterations (``info`` =
    the last ``|R|``), 4 ``u`` left the domain (``T <= 0`` or not finite), 5 a singular
    Jacobian; ``it`` the number of integrations done minus one.

    The acceptance test is the Python corrector's, with the numbers of the one standard
    (:mod:`numerics.shooting.acceptance`) passed in by the caller at the prediction's scale
    (this module is compiled from its text: it imports nothing of the package):
    ``|R| <= tol_residual noise`` and the Newton correction computed at the point
    ``<= tol_correction noise`` (the standard's tests 1 and 2) and ``< tol_accuracy noise``
    (the accuracy of the point returned), ``noise`` the size of the monodromy matrix times
    ``rtol / noise_rtol`` (at least 1), and the trivial multiplier 1 to ``trivial_tol``
    (test 3; or the last iteration).
    """
    npar = pbase.shape[0]
    pv = np.empty(2 * npar)
    for k in range(npar):
        pv[npar + k] = rates[k]
    u = u0.copy()
    R = np.zeros(2)
    A = np.zeros((2, 2))
    b = np.zeros(2)
    J = np.zeros((3, 3))
    rhs_ = np.zeros(3)
    du = np.zeros(3)
    y0 = np.zeros(9)
    y2 = np.zeros(2)
    f2 = np.zeros(2)
    n = max(1, n_out // 2) if half else n_out
    ys = np.zeros((n + 1, 9))
    for it in range(max_iter + 1):
        x0, T, p = u[0], u[1], u[2]
        if not (T > 0.0 and math.isfinite(x0) and math.isfinite(p)):
            return 4, it, u, R, A, b, ys, 0.0
        for k in range(npar):
            pv[k] = pbase[k] + (p - p_ref) * rates[k]
        for i in range(9):
            y0[i] = 0.0
        y0[0] = x0
        y0[2] = 1.0
        y0[5] = 1.0
        span = 0.5 * T if half else T
        ys, status, _steps = flow(y0, span, pv, rtol, rtol, n, max_steps)  # noqa: F821
        if status != 0:
            return 1, it, u, R, A, b, ys, float(status)
        e = ys[n]
        for i in range(9):
            if not math.isfinite(e[i]):
                return 1, it, u, R, A, b, ys, 3.0
        y2[0] = e[0]
        y2[1] = e[1]
        rhs(span, y2, pv, f2)  # noqa: F821 - the acceleration at the end
        acc = f2[1]
        b[0] = e[7]
        b[1] = e[8]
        if half:
            R[0] = e[0] + x0
            R[1] = e[1]
            A[0, 0] = e[2] + 1.0
            A[0, 1] = 0.5 * e[1]
            A[1, 0] = e[3]
            A[1, 1] = 0.5 * acc
            # the whole period's monodromy matrix Phi(T/2)^2 (columns e[2:4], e[4:6])
            m00 = e[2] * e[2] + e[4] * e[3]
            m01 = e[2] * e[4] + e[4] * e[5]
            m10 = e[3] * e[2] + e[5] * e[3]
            m11 = e[3] * e[4] + e[5] * e[5]
        else:
            R[0] = e[0] - x0
            R[1] = e[1]
            A[0, 0] = e[2] - 1.0
            A[0, 1] = e[1]
            A[1, 0] = e[3]
            A[1, 1] = acc
            m00, m01, m10, m11 = e[2], e[4], e[3], e[5]
        size = max(max(abs(m00), abs(m01)), max(abs(m10), abs(m11)))
        noise = max(1.0, size * rtol / noise_rtol)
        for i in range(2):
            J[i, 0] = A[i, 0]
            J[i, 1] = A[i, 1]
            J[i, 2] = b[i]
            rhs_[i] = -R[i]
        for j in range(3):
            J[2, j] = row[j]
        rhs_[2] = -(row[0] * u[0] + row[1] * u[1] + row[2] * u[2] - target)
        if not _solve3(J, rhs_, du):
            return 5, it, u, R, A, b, ys, 0.0
        r_max = max(abs(R[0]), abs(R[1]))
        du_max = max(max(abs(du[0]), abs(du[1])), abs(du[2]))
        if (r_max <= tol_residual * noise and du_max <= tol_correction * noise
                and du_max < tol_accuracy * noise):
            if _trivial_distance(m00, m01, m10, m11) <= trivial_tol or it == max_iter:
                for i in range(3):  # the point with the last correction, known to be small
                    u[i] += du[i]
                return 0, it, u, R, A, b, ys, 0.0
        if it == max_iter:
            return 3, it, u, R, A, b, ys, r_max
        if abs(du[0]) > 0.5 * abs(u[0]) or abs(du[1]) > 0.5 * u[1]:
            return 2, it, u, R, A, b, ys, 0.0
        for i in range(3):
            u[i] += du[i]
    return 3, max_iter, u, R, A, b, ys, max(abs(R[0]), abs(R[1]))


@njit(cache=True)
def accelerations(xs, p):
    """``x''`` at the rest points ``(x, 0)`` of the sample ``xs`` (the conservative force
    along the axis: its zeros are the equilibria, its integral the potential)."""
    out = np.empty(xs.shape[0])
    y = np.zeros(2)
    f = np.zeros(2)
    for k in range(xs.shape[0]):
        y[0] = xs[k]
        rhs(0.0, y, p, f)  # noqa: F821
        out[k] = f[1]
    return out
