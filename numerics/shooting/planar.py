"""The branch problem of one degree of freedom: the case ``N = 1`` of
:class:`numerics.shooting.branch_problem.BranchProblem` (``kbm branch`` of an oscillator,
:func:`numerics.cycles.continuation.continue_cycles`), with the section ``xdot = 0``
eliminated from the unknowns.

``u = (x0, T, p)``; :class:`PlanarProblem` evaluates ``R(u) = (x(T) - x0, x'(T))`` and its
Jacobian (variational equations for ``(x0, T)``; for ``p`` the parameter sensitivity
integrated with them, :mod:`numerics.flow.sensitivity`, or a central difference where the
compiled flow is not used); its corrector is the one of the branch problem, or its compiled
twin (``shoot_correct``, :mod:`numerics.flow.sensitivity`) in one call;
:meth:`PlanarProblem.reanchor` moves a point's section to the largest ``x``.
"""

from __future__ import annotations

import math

import numpy as np

from numerics.shooting import acceptance as _acceptance
from numerics.shooting.arclength import FAIL as _FAIL
from numerics.shooting.branch_problem import BranchProblem
from numerics.shooting.floquet import floquet_multipliers
from numerics.shooting.orbit import NEWTON_MAX_STEPS
from numerics.errors import ConvergenceError, IntegrationError
from numerics.flow import CompiledLine, Method, choose_method, extended_state, flow
from numerics.flow.line_card import compiled_line
from numerics.flow.sensitivity import (flow_with_sensitivity, sensitivity_flow, sensitivity_state,
                                       shooting_corrector)

__all__ = ["PlanarProblem", "PlanarPoint"]


class PlanarProblem(BranchProblem):
    """``R(u)``, its Jacobian and the bookkeeping of one continuation."""

    max_iter = 8
    through_prediction = False
    forced = False

    def __init__(self, model, params: dict, vary: str, method, rtol: float, at: float):
        self.model, self.params, self.vary = model, params, vary
        self.requested = Method.parse(method)
        self.rtol = rtol
        self.evaluations = 0
        self.meth = None
        self.sensitive = False
        #: the compiled corrector (:meth:`correct`), where the flow with the sensitivity is
        #: compiled and the parameter vector affine in ``vary``; ``None``: Python's Newton
        self.kernel = None
        self._compiled_kit = None
        self.p_ref, self.rates_ref = at, None
        # bound once; per value only what depends on ``vary`` is replaced
        self.line = compiled_line(model, params, vary, at)  # a line card's when stored
        #: the field is odd for every value of ``vary`` (``f(-y) = -f(y)``); ``half`` is set
        #: when the branch's cycles are symmetric as well (:meth:`use_symmetry`)
        self.odd = self.line.odd if self.line.odd is not None else _odd_field(self.line)
        if self.line.odd is None:  # kept in the line card for the warm runs (issue 39)
            from numerics.flow.line_card import remember

            remember(self.line.card_key, odd=bool(self.odd))
        self.half = False

    def use_symmetry(self, pt: "PlanarPoint") -> None:
        """Shoot half a period from now on when the field is odd and the cycle of ``pt`` is
        symmetric, ``y(t + T/2) = -y(t)`` (its sample at ``T/2`` is ``-y(0)`` to 1e-6): the
        branch keeps the symmetry, the half-period problem has the same solutions on it and
        costs half the integration.  Its monodromy matrix is ``Phi(T/2)^2`` (the Jacobian is
        even in ``y``)."""
        if not self.odd or self.half or pt.ys is None or len(pt.ys) % 2 == 0:
            return
        mid = pt.ys[(len(pt.ys) - 1) // 2]
        scale = max(1.0, abs(pt.u[0]))
        self.half = bool(abs(mid[0] + pt.u[0]) < 1e-6 * scale and abs(mid[1]) < 1e-6 * scale)

    def choose(self, u) -> None:
        """The integrator at ``u`` (the stiffness there); the compiled corrector and the
        sensitivity where the compiled flow is chosen and they exist for the model."""
        p = float(u[2])
        cm = self.line(p)
        self.meth = choose_method(cm, self.requested, "shooting", abs(u[0]), u[1])
        if self._compiled_kit is None:  # the line's template is fixed: decided once
            rates = self.line.rates(p)  # None when vary changes the model (stage velocity)
            ok = rates is not None and sensitivity_flow(cm.template) is not None
            kernel = shooting_corrector(cm.template) if ok and self.line.line.affine else None
            self._compiled_kit = (ok, kernel, rates)
        ok, kernel, rates = self._compiled_kit
        self.sensitive = self.meth is Method.COMPILED and ok
        self.kernel = kernel if self.sensitive else None
        # the reference of the affine parameter vector: the values at p (compiled above)
        # and the rates, constant along an affine line
        self.p_ref, self.rates_ref = p, rates

    def force(self, p: float):
        """The vectorised force ``g(x) = -x''(x, 0)`` along the axis at ``vary = p``, compiled
        with the flow (``accelerations`` of the corrector's module), or ``None`` where the
        compiled corrector is not used."""
        if self.kernel is None:
            return None
        cm = self.line(p)
        module = sensitivity_flow(cm.template).module
        pv = np.concatenate([np.asarray(cm.pvec, dtype=float), self.rates_ref])

        def g(xs):
            out = -module.accelerations(np.atleast_1d(np.asarray(xs, dtype=float)), pv)
            return out if np.ndim(xs) else float(out[0])
        return g

    def eval(self, u, n_out: int = 1, with_p: bool = False, full: bool = False):
        """``(R, A = dR/d(x0, T), yT, ys)`` at ``u``; with ``with_p`` also ``b = dR/dp``
        (one integration with the sensitivity, else two more for a central difference).

        In half-period mode (:meth:`use_symmetry`; not with ``full``) ``R = y(T/2) + y(0)``
        and its derivatives, while ``yT`` and ``ys`` describe the whole period: the end
        state, ``Phi(T) = Phi(T/2)^2``, twice the divergence integral, and the samples of
        the second half as minus those of the first.
        """
        x0, T, p = float(u[0]), float(u[1]), float(u[2])
        if not (T > 0 and math.isfinite(x0) and math.isfinite(p)):
            raise ConvergenceError(f"left the domain: x0 = {x0:.6g}, T = {T:.6g}")
        cm = self.line(p)
        self.evaluations += 1
        sens = with_p and self.sensitive
        half = self.half and not full
        span = 0.5 * T if half else T
        n = max(1, n_out // 2) if half else n_out
        if sens:
            ys = flow_with_sensitivity(cm, self.line.rates(p), sensitivity_state(x0), span,
                                       n, self.rtol, self.rtol, max_steps=NEWTON_MAX_STEPS)
        else:
            ys = flow(cm, extended_state(x0), span, n, self.meth, self.rtol, self.rtol,
                      max_steps=NEWTON_MAX_STEPS)
        yT = ys[-1]
        acc = cm.acc(span, yT[0], yT[1])
        b = np.array([yT[7], yT[8]]) if sens else None
        if half:
            R = np.array([yT[0] + x0, yT[1]])
            A = np.array([[yT[2] + 1.0, 0.5 * yT[1]], [yT[3], 0.5 * acc]])
            ys, yT = _whole_period(ys)
        else:
            R = np.array([yT[0] - x0, yT[1]])
            A = np.array([[yT[2] - 1.0, yT[1]], [yT[3], acc]])
        if not with_p:
            return R, A, yT, ys
        return R, A, (self.dRdp(u) if b is None else b), yT, ys

    def dRdp(self, u):
        """``dR/dp`` by a central difference (two integrations)."""
        p = float(u[2])
        h = 1e-6 * max(1.0, abs(p))  # central: R can curve strongly in p (SEDF near 3.2)
        return (self.eval((u[0], u[1], p + h))[0] - self.eval((u[0], u[1], p - h))[0]) / (2 * h)

    def correct(self, u_pred, row, target: float, max_iter: int | None = None) -> "PlanarPoint":
        """Newton on ``R(u) = 0, row . u = target``.

        A point is accepted when its residual is below the tolerance and so is the Newton
        correction computed there (the error of ``u`` to first order), ``rtol`` times the
        size of ``u``: the last evaluation is the accepted point's, with its monodromy
        matrix, and no evaluation confirms a step already known to be below the tolerance.
        (With ten times that bound on the correction the periods were off by up to 1.5e-9
        on the SEDF branch against cycles shot at rtol 1e-12; with it, 1.4e-11, for 5 %
        more integrations.)

        The point returned is ``u`` plus that last correction (Newton converges
        quadratically: its error is of the order of the correction squared), with the
        integration at ``u`` standing for it: monodromy matrix, samples, tangent, and the
        residual ``R(u)`` (an upper bound), all off by at most the tolerance.  Near a
        homoclinic end the period changes 700 times faster than the parameter: a point
        within 1e-9 of the branch in ``(x0, T, p)`` had a period off by 1.4e-7 (relative)
        from the cycle shot at its own ``p`` (rtol 1e-12); with the correction added, within
        6e-9, where shooting from scratch itself loses its accuracy
        (``tests/test_compiled_corrector.py``).

        The compiled corrector (``_correct_compiled``) does the same in one call.
        """
        max_iter = self.max_iter if max_iter is None else max_iter
        u_pred = np.asarray(u_pred, dtype=float)
        if self.kernel is not None:
            return _correct_compiled(self, u_pred, row, target, max_iter)
        self._tol = (*_tolerances(u_pred, self.rtol), max_iter)
        return super().correct(u_pred, row, target, max_iter)

    def evaluate(self, u):
        R, A, b, yT, ys = self.eval(u, 32, with_p=True)
        return R, np.column_stack([A, b]), (A, b, yT, ys)

    def accept(self, u, R, du, data, it) -> bool:
        scale, tol_u, max_iter = self._tol
        A, b, yT, ys = data
        # the integration error of R grows with the monodromy matrix (near a separatrix)
        noise = _acceptance.noise_factor(float(np.max(np.abs(yT[2:6]))), self.rtol)
        corr = float(np.max(np.abs(du)))
        if not (_acceptance.accepted(float(np.max(np.abs(R))), corr, self.rtol, scale, noise)
                and corr < tol_u * noise):
            return False
        # near a separatrix the loose tolerance may leave the trivial multiplier off 1:
        # one more iteration there (the point would not pass the printed test)
        mults = floquet_multipliers(np.array([[yT[2], yT[4]], [yT[3], yT[5]]]), yT[6])
        return _acceptance.trivial_ok(mults[:1]) or it == max_iter

    def too_large(self, u, du) -> str | None:
        if abs(du[0]) > 0.5 * abs(u[0]) or abs(du[1]) > 0.5 * u[1]:
            return f"corrector step too large at p = {u[2]:.8g}"
        return None

    def where(self, u) -> str:
        return f"p = {u[2]:.8g}"

    def point(self, u, R, du, data, it) -> "PlanarPoint":
        A, b, yT, ys = data
        return PlanarPoint(u + du, R, A, b, yT, ys, it)

    def reanchor(self, pt: "PlanarPoint") -> "PlanarPoint":
        """The same cycle with the section at its largest ``x`` when ``x0`` is only a local
        maximum: there ``x'' < 0`` keeps the section transversal, where a local maximum can
        merge with a minimum (``x'' = 0``, a false fold of the section point)."""
        if pt.amp <= pt.u[0] + 1e-3 * pt.size:  # hysteresis: two nearly equal maxima
            return pt
        try:
            new = self.fix(np.array([pt.x_top, pt.u[1], pt.u[2]]), max_iter=25)
        except _FAIL:
            return pt
        if new.amp > new.u[0] + 1e-3 * new.size or \
                abs(new.u[1] - pt.u[1]) > 1e-6 * pt.u[1]:
            return pt
        if new.tangent[2] * pt.tangent[2] < 0:
            new.tangent = -new.tangent
        return new


def _tolerances(u_pred, rtol: float) -> tuple[float, float]:
    """``(S, tol_u)`` of a correction from ``u_pred``: the orbit's scale ``S = max(1, |x0|)``
    of the acceptance standard, and the accuracy of the point, a correction below ``rtol``
    times the size of ``u`` (tighter than the standard's ``sqrt(rtol) S`` unless ``T`` or
    ``|p|`` exceeds ``S / sqrt(rtol)``)."""
    scale = max(1.0, abs(float(u_pred[0])))
    return scale, rtol * max(scale, float(u_pred[1]), abs(float(u_pred[2])))


def _odd_field(line: CompiledLine) -> bool:
    """Whether the autonomous field is odd, ``x''(-x, -x') = -x''(x, x')``, for every value of
    the varied parameter (the other values substituted, the varied ones symbols)."""
    import sympy as sp

    from kbm.symbols import x, xdot

    base = line.line.base
    model = base.model
    if not getattr(model, "is_autonomous", False):
        return False
    subs = {sp.Symbol(k): v for k, v in base.values.items() if k not in line.line.changed}
    try:
        acc = model.acceleration().subs(subs)
        return sp.expand(acc + acc.subs({x: -x, xdot: -xdot}, simultaneous=True)) == 0
    except Exception:  # noqa: BLE001 - not decided: the whole period is shot
        return False


def _whole_period(ys: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The samples and the end of the whole period from those of the first half of a
    symmetric cycle, ``y(t + T/2) = -y(t)``: the state of the second half is minus the
    first's, the monodromy matrix ``Phi(T/2)^2`` and the divergence integral twice the
    half's (the other entries of the second half's rows are copies, not used)."""
    second = ys[1:].copy()
    second[:, :2] *= -1.0
    whole = np.vstack([ys, second])
    e = ys[-1]
    Phi = np.array([[e[2], e[4]], [e[3], e[5]]])
    M = Phi @ Phi
    end = whole[-1].copy()
    end[2:6] = (M[0, 0], M[1, 0], M[0, 1], M[1, 1])
    end[6] = 2.0 * e[6]
    whole[-1] = end
    return whole, end


class PlanarPoint:
    """A converged point with what the continuation needs next."""

    def __init__(self, u, R, A, b, yT, ys, iters):
        self.u, self.R, self.yT, self.ys, self.iters = u, R, yT, ys, iters
        self.v = u  # the unknowns Newton works in (unscaled)
        # the tangent spans the kernel of dR/du = [A b]: the cross product of its rows
        r0, r1 = (A[0, 0], A[0, 1], b[0]), (A[1, 0], A[1, 1], b[1])
        t = np.array([r0[1] * r1[2] - r0[2] * r1[1], r0[2] * r1[0] - r0[0] * r1[2],
                      r0[0] * r1[1] - r0[1] * r1[0]])
        self.tangent = t / math.sqrt(float(t @ t))
        self.mults = floquet_multipliers(np.array([[yT[2], yT[4]], [yT[3], yT[5]]]), yT[6])
        # the first and the last sample are the start (x0, 0) and the return to it: x0 stands
        # for both (the samples are those of the last integration, the point is corrected)
        inner = ys[1:-1, 0] if len(ys) > 2 else ys[:, 0]
        self.amp = float(max(u[0], np.max(inner)))
        self.x_top = float(inner[int(np.argmax(inner))])
        self.size = self.amp - float(min(u[0], np.min(inner)))  # peak to peak of x
        self.mid = self.amp - 0.5 * self.size
        self.phi = float(np.max(np.abs(yT[2:6])))  # size of the monodromy matrix


def _correct_compiled(prob: PlanarProblem, u_pred, row, target: float,
                      max_iter: int) -> PlanarPoint:
    """:meth:`PlanarProblem.correct` in one call of the compiled corrector
    (``shoot_correct`` of :mod:`numerics.flow.sensitivity`'s module): the same iterations,
    tests and errors, with the parameter vector ``pvec(p_ref) + (p - p_ref) rates``
    (affine in ``p``)."""
    u = np.array(u_pred, dtype=float)
    p_ref, rtol = prob.p_ref, prob.rtol
    scale, tol_u = _tolerances(u, rtol)
    status, it, u, R, A, b, ys, info = prob.kernel(
        u, np.asarray(row, dtype=float), float(target),
        np.asarray(prob.line(p_ref).pvec, dtype=float), prob.rates_ref, p_ref, bool(prob.half),
        rtol, 32, NEWTON_MAX_STEPS, max_iter, _acceptance.residual_tolerance(rtol, scale),
        _acceptance.correction_tolerance(rtol, scale), tol_u, _acceptance.TRIVIAL_TOL,
        _acceptance.NOISE_RTOL)
    prob.evaluations += it + 1
    if status == 0:
        if prob.half:
            ys, yT = _whole_period(ys)
        else:
            yT = ys[-1]
        return PlanarPoint(u, R, A, b, yT, ys, it)
    if status == 1:
        from numerics.flow.jit import FlowResult

        why = FlowResult(ys, int(info), 0).message or "the state became non-finite"
        raise IntegrationError(f"DOP853 (compiled) failed on a period of {u[1]:.6g}: {why}")
    if status == 2:
        raise ConvergenceError(f"corrector step too large at p = {u[2]:.8g}")
    if status == 4:
        raise ConvergenceError(f"left the domain: x0 = {u[0]:.6g}, T = {u[1]:.6g}")
    if status == 5:
        raise np.linalg.LinAlgError("Singular matrix")
    raise ConvergenceError(f"corrector did not converge in {max_iter} iterations at "
                           f"p = {u[2]:.8g} (|R| = {info:.2e})")

