"""The one branch problem of :mod:`numerics.shooting`: a periodic orbit of a ``2N``-dimensional
flow and a parameter, continued by pseudo-arclength (Doedel, *Lecture notes on numerical
analysis of nonlinear equations*, sec. 2).

:class:`BranchProblem` holds what every branch does (the corrector, accepted by the standard
of :mod:`numerics.shooting.acceptance`; the arclength step; the point at a parameter); a
case gives the residual, its Jacobian, the test and the point:

- :class:`OrbitProblem`, any ``N``, in scaled unknowns ``v = u/scale``: autonomous
  ``u = (y0, T, p)``, equations ``phi_T(y0; p) - y0 = 0`` and ``xdot_1(0) = 0``; forced
  (``theta = nu t``) ``u = (y0, p)`` with ``T = m 2 pi/nu(p)``.  The Jacobian holds
  ``Phi - I``, the field at the end (for ``T``) and a central difference in ``p``; every
  point has all ``2N`` multipliers;
- :class:`numerics.shooting.planar.PlanarProblem`, ``N = 1`` with the section ``xdot = 0``
  eliminated, ``u = (x0, T, p)``, and its compiled corrector;
- the forced response of one degree of freedom (:mod:`numerics.shooting.forced_branch`).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Callable

import numpy as np

from numerics.errors import ConvergenceError
from numerics.shooting.acceptance import accepted, orbit_scale, trivial_ok
from numerics.shooting.arclength import correct_on_hyperplane, null_vector, predict
from numerics.shooting.orbit import multipliers, peak

if TYPE_CHECKING:  # the symbolic model: imported on use (issue 39)
    from kbm.model.coupled import CoupledOscillators

__all__ = ["BranchProblem", "OrbitProblem", "OrbitPoint"]


class BranchProblem:
    """The corrector and the steps of a branch.  A case defines ``evaluate(v) -> (R, dR/dv,
    data)``, ``accept(v, R, dv, data, it)`` (the point is converged), ``too_large(v, dv)``
    (a message, or ``None``), ``point(v, R, dv, data, it)`` (the converged point, with
    ``v``, ``u`` and a unit ``tangent``) and, unless :meth:`where` serves, the place named
    in errors.  The parameter is the last unknown, ``u[-1] = v[-1] * pscale``."""

    #: the bound on Newton's corrections of one point
    max_iter = 10
    #: the hyperplane of a step is ``t . v = t . prediction`` (else ``t . v_pt + ds``)
    through_prediction = True
    pscale = 1.0

    def where(self, v) -> str:
        return f"{self.vary} = {v[-1] * self.pscale:.8g}"

    def correct(self, v_pred, row, target: float, max_iter: int | None = None):
        """Newton on ``R(v) = 0, row . v = target`` from ``v_pred``: the accepted point."""
        v, R, dv, data, it = correct_on_hyperplane(
            self.evaluate, v_pred, row, target,
            max_iter=self.max_iter if max_iter is None else max_iter, accept=self.accept,
            too_large=self.too_large, where=self.where)
        return self.point(v, R, dv, data, it)

    def fix(self, v, max_iter: int | None = None, target: float | None = None):
        """The point corrected from ``v`` at the parameter ``target`` (default ``v[-1]``)."""
        row = np.zeros(len(v))
        row[-1] = 1.0
        return self.correct(v, row, v[-1] if target is None else target, max_iter)

    def arc(self, pt, ds: float, t=None, previous=None):
        """Predict ``ds`` along ``t`` (default the tangent of ``pt``; with ``previous``, the
        unknowns and unit tangent of the point before, the cubic Hermite predictor of
        :func:`numerics.shooting.arclength.predict`) and correct on the hyperplane normal
        to ``t``; the new point's tangent is oriented along ``t``."""
        t = pt.tangent if t is None else t
        pred = predict(pt.v, t, ds, previous)
        target = float(t @ pred) if self.through_prediction else float(t @ pt.v) + ds
        new = self.correct(pred, t, target)
        if new.tangent @ t < 0:
            new.tangent = -new.tangent
        return new

    def at_parameter(self, a, b, p: float, max_iter: int | None = None):
        """The point of the branch at ``p`` between ``a`` and ``b`` (``p`` between theirs),
        from the chord, its tangent oriented as ``a``'s."""
        s = (p - a.u[-1]) / (b.u[-1] - a.u[-1])
        new = self.fix(a.v + s * (b.v - a.v), max_iter, p / self.pscale)
        if new.tangent @ a.tangent < 0:
            new.tangent = -new.tangent
        return new


class OrbitProblem(BranchProblem):
    """``R(u)``, its Jacobian and the multipliers, for one model and one parameter."""

    def __init__(self, model: CoupledOscillators, params: dict, vary: str, rtol: float,
                 make_flow: Callable):
        self.model, self.params, self.vary, self.rtol = model, params, vary, rtol
        #: ``(model, values) -> flow`` (:func:`numerics.flow.coupled_flow.coupled_flow`): the flow
        #: with ``monodromy``, ``rhs``, ``states``, ``nu`` and ``at(**values)``
        self.make_flow = make_flow
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

    def start(self, u0: np.ndarray, width: float) -> "OrbitPoint":
        """The first point of a branch: ``u0`` corrected at its parameter, the scales set
        from it (the states by their largest ``|y0|``, ``T`` by itself, ``p`` by ``width``)."""
        n2 = 2 * self.n
        self.scale = np.concatenate([np.full(n2, max(1.0, float(np.max(np.abs(u0[:n2]))))),
                                     u0[n2:-1], [width]])
        return self.fix(u0 / self.scale, max_iter=20)

    def flow(self, p: float):
        fl = self._flows.get(p)
        if fl is None:
            if len(self._flows) > 32:
                self._flows.clear()
            if self._base is None:
                self._base = self.make_flow(self.model, {**self.params, self.vary: p})
            if self.vary in self._base.values:
                fl = self._base.at(**{self.vary: p})
            else:  # a physical name (Delta): its scaled values are bound again
                fl = self.make_flow(self.model, {**self.params, self.vary: p})
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

    @property
    def pscale(self) -> float:
        return self.scale[-1]

    def evaluate(self, v):
        R, Phi, yT, fl, T = self.residual(v)
        J = self.jacobian(v, Phi, yT, fl, T)
        return R, J, (Phi, yT, fl, T, J)

    def accept(self, v, R, dv, data, it) -> bool:
        # the acceptance standard (numerics.shooting.acceptance), and the accuracy of the
        # point: a scaled correction below 1e-8
        scale = orbit_scale((v * self.scale)[:2 * self.n])
        return bool(accepted(float(np.max(np.abs(R))), float(np.max(np.abs(dv * self.scale))),
                             self.rtol, scale) and np.max(np.abs(dv)) < 1e-8
                    and (self.forced or trivial_ok(np.linalg.eigvals(data[0]))))

    def too_large(self, v, dv) -> str | None:
        if np.max(np.abs(dv)) > 0.5:
            return (f"corrector step too large ({np.max(np.abs(dv)):.3g}, scaled) at "
                    f"{self.where(v)}")
        return None

    def point(self, v, R, dv, data, it) -> "OrbitPoint":
        return OrbitPoint(self, v, R, *data)


class OrbitPoint:
    """A converged point: ``u``, the tangent and what the tests need."""

    def __init__(self, prob: OrbitProblem, v, R, Phi, yT, fl, T, J):
        self.v, self.T = v, T
        self.u = v * prob.scale
        self.res = float(np.max(np.abs(R)))
        self.mults, self.rest = multipliers(Phi, autonomous=not prob.forced)
        self.Phi = Phi
        n = prob.n
        ys = fl.states(self.u[:2 * n], T, 512, rtol=prob.rtol)[:-1]
        self.amps = tuple(peak(np.abs(ys[:, i])) for i in range(n))
        self.tangent = null_vector(J)
