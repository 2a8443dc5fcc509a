"""The shooting problem of a branch of periodic orbits in scaled unknowns, and its
corrector (pseudo-arclength continuation, :mod:`numerics.coupled.continuation`; Doedel,
*Lecture notes on numerical analysis of nonlinear equations*, sec. 2).

- an autonomous system: unknowns ``u = (y0, T, p)``, equations ``phi_T(y0; p) - y0 = 0``
  and the phase condition ``xdot_1(0) = 0``;
- a forced system (``theta = nu t``): unknowns ``u = (y0, p)``, the period
  ``T = m 2 pi/nu(p)`` fixed by the forcing, equations ``phi_T(y0; p) - y0 = 0``.

The Jacobian holds the monodromy ``Phi - I``, the field at the end (autonomous, for ``T``)
and a central difference in ``p``; the tangent is its null vector, the corrector Newton's
method on the hyperplane normal to it.  Every point has all ``2N`` Floquet multipliers.
"""

from __future__ import annotations

import math

import numpy as np

from kbm.coupled import CoupledOscillators
from numerics.coupled.branch_result import CoupledBranchPoint
from numerics.coupled.flow import coupled_flow
from numerics.errors import ConvergenceError
from numerics.shooting.acceptance import accepted, orbit_scale, trivial_ok
from numerics.shooting.arclength import correct_on_hyperplane, null_vector, predict
from numerics.shooting.orbit import multipliers, peak


class _Problem:
    """``R(u)``, its Jacobian and the multipliers, for one model and one parameter."""

    def __init__(self, model: CoupledOscillators, params: dict, vary: str, rtol: float):
        self.model, self.params, self.vary, self.rtol = model, params, vary, rtol
        self.n = model.dof
        self.forced = model.forced
        self.evaluations = 0
        if self.forced:
            self.m = model.response_periods
        self._flows: dict[float, object] = {}
        self._base = None  # compiled once; a model parameter is then a value of it
        #: the unknowns are ``u = scale * v``; steps are taken in ``v`` (each component of
        #: order one along the branch: a weighted arclength, as AUTO-07p's THL/THU)
        self.scale: np.ndarray | None = None

    def start(self, u0: np.ndarray, width: float) -> "_Pt":
        """The first point of a branch: ``u0`` corrected at its parameter, the scales set
        from it (the states by their largest ``|y0|``, ``T`` by itself, ``p`` by ``width``)."""
        n2 = 2 * self.n
        self.scale = np.concatenate([np.full(n2, max(1.0, float(np.max(np.abs(u0[:n2]))))),
                                     u0[n2:-1], [width]])
        row = np.zeros(len(u0))
        row[-1] = 1.0
        return _correct(self, u0 / self.scale, row, u0[-1] / width, max_iter=20)

    def flow(self, p: float):
        fl = self._flows.get(p)
        if fl is None:
            if len(self._flows) > 32:
                self._flows.clear()
            if self._base is None:
                self._base = coupled_flow(self.model, {**self.params, self.vary: p})
            if self.vary in self._base.values:
                fl = self._base.at(**{self.vary: p})
            else:  # a physical name (Delta): its scaled values are bound again
                fl = coupled_flow(self.model, {**self.params, self.vary: p})
            self._flows[p] = fl
        return fl

    def period(self, u: np.ndarray, fl) -> float:
        return self.m * 2 * math.pi / fl.nu if self.forced else float(u[2 * self.n])

    def residual(self, v: np.ndarray):
        """``(R, Phi, yT, fl, T)`` at ``u = scale * v``."""
        n2 = 2 * self.n
        u = v * self.scale
        p = float(u[-1])
        fl = self.flow(p)
        T = self.period(u, fl)
        if not (T > 0 and np.all(np.isfinite(u))):
            raise ConvergenceError(f"left the domain: T = {T:.6g} at {self.vary} = {p:.8g}")
        self.evaluations += 1
        yT, Phi, _ = fl.monodromy(u[:n2], T, rtol=self.rtol)
        R = yT - u[:n2]
        if not self.forced:
            R = np.append(R, u[self.n])  # the phase condition xdot_1(0) = 0
        return R, Phi, yT, fl, T

    def jacobian(self, v: np.ndarray, Phi, yT, fl, T) -> np.ndarray:
        """``dR/dv`` (the monodromy, the field, a central difference in the parameter)."""
        n2 = 2 * self.n
        u = v * self.scale
        p = float(u[-1])
        h = 1e-6 * max(1.0, abs(p))
        vp, vm = v.copy(), v.copy()
        vp[-1], vm[-1] = (p + h) / self.scale[-1], (p - h) / self.scale[-1]
        dp = (self.residual(vp)[0] - self.residual(vm)[0]) / (2 * h)
        rows = len(dp)
        J = np.zeros((rows, len(u)))
        J[:n2, :n2] = Phi - np.eye(n2)
        if not self.forced:
            J[:n2, n2] = fl.rhs(yT, T)
            J[n2, self.n] = 1.0
        J[:, -1] = dp
        return J * self.scale

    def multipliers(self, Phi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(all, non-trivial)``: autonomous systems have the trivial one first."""
        return multipliers(Phi, autonomous=not self.forced)


class _Pt:
    """A converged point: ``u``, the tangent and what the tests need."""

    def __init__(self, prob: _Problem, v, R, Phi, yT, fl, T, J):
        self.v, self.T = v, T
        self.u = v * prob.scale
        self.res = float(np.max(np.abs(R)))
        self.J = J
        self.mults, self.rest = prob.multipliers(Phi)
        self.Phi = Phi
        n = prob.n
        ys = fl.states(self.u[:2 * n], T, 512, rtol=prob.rtol)[:-1]
        self.amps = tuple(peak(np.abs(ys[:, i])) for i in range(n))
        self.tangent = null_vector(J)

    def record(self) -> CoupledBranchPoint:
        n2 = len(self.Phi)
        return CoupledBranchPoint(float(self.u[-1]), float(self.T),
                                  tuple(float(v) for v in self.u[:n2]), self.amps,
                                  tuple(complex(z) for z in self.mults),
                                  bool(np.all(np.abs(self.rest) < 1.0)), self.res)


def _correct(prob: _Problem, v_pred, row, target: float, max_iter: int = 10) -> _Pt:
    """Newton on ``R(v) = 0, row . v = target`` (scaled unknowns), by the corrector shared
    with one degree of freedom (:func:`numerics.shooting.arclength.correct_on_hyperplane`)."""
    def evaluate(v):
        R, Phi, yT, fl, T = prob.residual(v)
        J = prob.jacobian(v, Phi, yT, fl, T)
        return R, J, (Phi, yT, fl, T, J)

    def accept(v, R, dv, data, it):
        # the acceptance standard (numerics.shooting.acceptance), and the accuracy of the
        # point: a scaled correction below 1e-8
        scale = orbit_scale((v * prob.scale)[:2 * prob.n])
        return bool(accepted(float(np.max(np.abs(R))), float(np.max(np.abs(dv * prob.scale))),
                             prob.rtol, scale) and np.max(np.abs(dv)) < 1e-8
                    and (prob.forced or trivial_ok(np.linalg.eigvals(data[0]))))

    def too_large(v, dv):
        if np.max(np.abs(dv)) > 0.5:
            return (f"corrector step too large ({np.max(np.abs(dv)):.3g}, scaled) at "
                    f"{prob.vary} = {v[-1] * prob.scale[-1]:.8g}")
        return None

    v, R, _, (Phi, yT, fl, T, J), _ = correct_on_hyperplane(
        evaluate, v_pred, row, target, max_iter=max_iter, accept=accept, too_large=too_large,
        where=lambda v: f"{prob.vary} = {v[-1] * prob.scale[-1]:.8g}")
    return _Pt(prob, v, R, Phi, yT, fl, T, J)


def _arc(prob: _Problem, pt: _Pt, t: np.ndarray, ds: float) -> _Pt:
    """The pseudo-arclength step ``ds`` along ``t`` from ``pt``, corrected on the hyperplane
    normal to ``t``."""
    pred = predict(pt.v, t, ds)
    new = _correct(prob, pred, t, float(t @ pred))
    if new.tangent @ t < 0:
        new.tangent = -new.tangent
    return new
