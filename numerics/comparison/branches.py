"""Analytic branches of limit cycles over one parameter: KBM roots and the energy balance.

- :func:`kbm_branch`: the roots ``a*(p)`` of the averaged amplitude equation
  ``A(a) = sum_{n<=N} mu**n A_n(a) = 0`` (classical KBM of order ``N``,
  :func:`kbm.derive`, :mod:`kbm.slowflow.averaged`) on a grid of the parameter, with the folds
  located by solving ``A/a = 0`` and ``d(A/a)/da = 0`` together (Newton in ``(a, p)``;
  at a root of ``A/a`` this is ``dA/da = 0``);
- :func:`energy_branch`: the cycles of the energy balance ``Gamma(E) = 0``
  (:func:`numerics.energy.predict_cycles`, order 1) on the same grid, its folds
  located by bisection on the number of cycles.

``p`` may be any name :func:`kbm.parameters.bound.bind` accepts (``mu``, a model parameter, a
physical one such as ``Delta``): each grid value is bound afresh.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from kbm import derive
from kbm.slowflow.averaged import averaged_rates
from kbm.errors import KBMError
from kbm.parameters.bound import bind
from kbm.model.builtins import Oscillator

from kbm.output.strict_json import finite
from numerics.errors import ConvergenceError

__all__ = ["AnalyticCurve", "AnalyticFold", "kbm_branch", "energy_branch"]


@dataclass(frozen=True)
class AnalyticFold:
    """A fold of an analytic branch: two predicted cycles merge at ``parameter``."""

    parameter: float
    amplitude: float


@dataclass(frozen=True, eq=False)
class AnalyticCurve:
    """The predicted cycles over a grid of the parameter.

    Attributes
    ----------
    method : str
        ``"kbm"`` (``amplitude`` is the first-harmonic amplitude ``a*``) or ``"energy"``
        (``amplitude`` is the largest ``x`` of the conservative orbit).
    order : int
    parameter : str
    points : tuple of tuple
        ``(parameter, amplitude, period, stable)`` of every predicted cycle.
    folds : tuple of AnalyticFold
    """

    method: str
    order: int
    parameter: str
    points: tuple[tuple[float, float, float, bool], ...]
    folds: tuple[AnalyticFold, ...]

    def to_json(self) -> dict:
        """``method, order, points, folds``."""
        return finite({"method": self.method, "order": self.order,
                       "points": [{"parameter": p, "amplitude": a, "period": T, "stable": s}
                                  for p, a, T, s in self.points],
                       "folds": [{"parameter": f.parameter, "amplitude": f.amplitude}
                                 for f in self.folds]})


def _grid(bounds, n: int) -> np.ndarray:
    lo, hi = float(bounds[0]), float(bounds[1])
    return np.linspace(lo, hi, int(n))


class _Rates:
    """``A/a`` and its slope at ``(a, p)``, the parameters bound per ``p``."""

    def __init__(self, model, params, vary, order):
        self.res = derive(model, order)
        self.rates = averaged_rates(self.res, order=order)
        self.model, self.params, self.vary = model, dict(params), vary

    def values(self, p: float) -> dict:
        vals = bind(self.model, {**self.params, self.vary: p}).floats
        return {k: vals[k] for k in (*self.res.params, "mu")}

    def _args(self, p):
        v = self.values(p)
        return v["mu"], [v[k] for k in self.res.params]

    def g(self, a: float, p: float) -> tuple[float, float]:
        m, pars = self._args(p)
        A, dA = float(self.rates.rate(a, m, *pars)), float(self.rates.slope(a, m, *pars))
        return A / a, (dA - A / a) / a


def _kbm_fold(r: _Rates, a: float, p: float, scale: float) -> AnalyticFold:
    """Newton on ``(A/a, d(A/a)/da) = 0`` in ``(a, p)``, derivatives by central differences."""
    for _ in range(50):
        f = np.array(r.g(a, p))
        ha, hp = 1e-6 * max(1.0, abs(a)), 1e-6 * scale
        J = np.column_stack([(np.array(r.g(a + ha, p)) - np.array(r.g(a - ha, p))) / (2 * ha),
                             (np.array(r.g(a, p + hp)) - np.array(r.g(a, p - hp))) / (2 * hp)])
        da, dp = np.linalg.solve(J, -f)
        a, p = a + da, p + dp
        if abs(da) < 1e-13 * max(1.0, abs(a)) and abs(dp) < 1e-13 * scale:
            return AnalyticFold(float(p), float(a))
    raise ConvergenceError(f"the fold of the averaged equation near a = {a:.6g}, "
                           f"{r.vary} = {p:.6g} did not converge")


def kbm_branch(model: Oscillator | str, params: Mapping[str, object] | None, vary: str,
               bounds: tuple[float, float], *, order: int = 1, n: int = 201,
               a_max: float = 20.0) -> AnalyticCurve:
    """Roots of the order-``order`` KBM amplitude equation over ``vary`` in ``bounds``.

    Parameters
    ----------
    model, params
        The model and the other parameter values (``mu`` included).
    vary : str
        The parameter to vary (any name :func:`kbm.parameters.bound.bind` accepts).
    bounds : tuple of float
        ``(FROM, TO)``.
    order : int
        KBM order (``A_1..A_order``).
    n : int
        Grid points.
    a_max : float
        Largest amplitude looked for (:meth:`kbm.slowflow.averaged.AveragedRates.cycles`).

    Returns
    -------
    AnalyticCurve
        Method ``"kbm"``; a fold wherever the number of roots changes between grid
        points, solved to ``1e-13`` from the merging pair.

    Examples
    --------
    >>> c = kbm_branch("(-nu + x**2 - x**4)*xdot", {"mu": 0.1}, "nu", (0.0, 0.2), n=21)
    >>> round(c.folds[0].parameter, 12)
    0.125
    """
    if isinstance(model, str) and not _is_builtin(model):
        from kbm import custom_model

        model = custom_model(model)
    r = _Rates(model, params or {}, vary, order)
    scale = max(1.0, abs(float(bounds[0])), abs(float(bounds[1])))
    pts, rows = [], []
    for p in _grid(bounds, n):
        cyc = r.rates.cycles(r.values(float(p)), a_max=a_max)
        rows.append((float(p), cyc))
        pts.extend((float(p), c.amplitude, c.period, bool(c.stable)) for c in cyc)
    folds = []
    for (p1, c1), (p2, c2) in zip(rows, rows[1:]):
        if len(c1) == len(c2):
            continue
        more, pm = (c1, p1) if len(c1) > len(c2) else (c2, p2)
        for x, y in zip(more, more[1:]):  # a stable and an unstable root side by side merge
            if x.stable != y.stable:
                try:
                    f = _kbm_fold(r, 0.5 * (x.amplitude + y.amplitude), pm, scale)
                except (ConvergenceError, np.linalg.LinAlgError):
                    continue
                if min(p1, p2) - 1e-9 * scale <= f.parameter <= max(p1, p2) + 1e-9 * scale and \
                        all(abs(f.parameter - g.parameter) > 1e-10 * scale for g in folds):
                    folds.append(f)
    return AnalyticCurve("kbm", r.rates.order, vary, tuple(pts), tuple(folds))


def _is_builtin(name: str) -> bool:
    from kbm.model.builtins import model_names

    return name in model_names()


def _energy_fold(line, vary: str, lo: float, hi: float, pair) -> float | None:
    """The fold of the energy balance: the ``p`` in ``[lo, hi]`` where the extremum of
    ``q = Gamma`` (``Gamma/(E - E_c)`` in a well) between the merging pair's energies is 0.
    ``None`` when the bracket does not hold a sign change of that extremum.  ``line`` is
    the branch's :class:`kbm.model.conservative.SplitLine` (the model split once along
    ``vary``)."""
    from scipy.optimize import brentq, minimize_scalar

    from numerics.energy.balance import gamma_function
    from numerics.energy.portrait import phase_portrait

    e1, e2 = sorted((pair[0].energy, pair[1].energy))
    width = max(e2 - e1, 1e-9 * max(1.0, abs(e1)))

    def extremum(p):
        portrait = phase_portrait(line(float(p)))
        ann = next((a for a in portrait.annuli if a.label == pair[0].annulus), None)
        if ann is None:
            raise ConvergenceError(f"annulus {pair[0].annulus!r} gone at {vary} = {p}")
        g = gamma_function(ann, tol=1e-13)
        well = len(ann.wells) == 1
        a_lo = max(e1 - 2 * width, ann.energy_min + 1e-12 * max(1.0, abs(ann.energy_min)))
        a_hi = e2 + 2 * width
        if ann.bounded:
            a_hi = min(a_hi, ann.energy_max)

        def q(e):
            val = g(np.array([e]))[0][0]
            return val / (e - ann.energy_min) if well else val

        sign = 1.0 if q(a_lo) > 0 else -1.0
        res = minimize_scalar(lambda e: sign * q(e), bounds=(a_lo, a_hi), method="bounded",
                              options={"xatol": 1e-14 * max(1.0, abs(a_hi))})
        return float(res.fun)

    try:
        f_lo, f_hi = extremum(lo), extremum(hi)
        if f_lo * f_hi >= 0:
            return None
        return float(brentq(extremum, lo, hi, xtol=1e-15, rtol=1e-15))
    except (KBMError, ValueError, RuntimeError):
        return None


def energy_branch(model: Oscillator | str, params: Mapping[str, object] | None, vary: str,
                  bounds: tuple[float, float], *, n: int = 81) -> AnalyticCurve:
    """Cycles of the energy balance (order 1) over ``vary`` in ``bounds``.

    Folds are bracketed by bisection on where the number of predicted cycles changes
    between grid points, then solved as ``Gamma = dGamma/dE = 0``: the parameter where the
    extremum of ``Gamma`` between the merging pair touches zero (Brent's method on that
    extremum's value; :func:`_energy_fold`).  The amplitude is the merging pair's mean at
    the last grid point with both.

    Returns
    -------
    AnalyticCurve
        Method ``"energy"``; ``amplitude`` is the largest ``x`` of the predicted cycle.
    """
    from kbm.model.conservative import SplitLine
    from numerics.energy.predict import predict_cycles  # scipy.integrate: on use (issue 39)

    params = dict(params or {})
    try:  # split once along the parameter (the values that move with it kept as symbols)
        line = SplitLine(model, params, vary, float(bounds[0]))
    except KBMError:
        line = None

    def cycles(p):
        try:
            split = None if line is None else line(float(p))
            return predict_cycles(model, {**params, vary: float(p)}, order=1,
                                  split=split).cycles
        except KBMError:
            return ()

    pts, rows = [], []
    for p in _grid(bounds, n):
        cyc = cycles(p)
        rows.append((float(p), cyc))
        pts.extend((float(p), c.amplitude_max, c.period, bool(c.stable)) for c in cyc)
    folds = []
    width = float(bounds[1]) - float(bounds[0])
    for (p1, c1), (p2, c2) in zip(rows, rows[1:]):
        if len(c1) == len(c2) or abs(len(c1) - len(c2)) % 2:
            continue  # a pair appears or disappears at a fold; odd changes are annulus ends
        lo, hi, nlo = p1, p2, len(c1)
        for _ in range(60):
            if hi - lo < 1e-8 * width:
                break
            mid = 0.5 * (lo + hi)
            if len(cycles(mid)) == nlo:
                lo = mid
            else:
                hi = mid
        more = c1 if len(c1) > len(c2) else c2
        pair = next(((x, y) for x, y in zip(more, more[1:]) if x.stable != y.stable
                     and x.annulus == y.annulus), None)
        amp = math.nan if pair is None else 0.5 * (pair[0].amplitude_max
                                                   + pair[1].amplitude_max)
        pf = 0.5 * (lo + hi)
        if pair is not None:
            pf = (_energy_fold(line, vary, lo, hi, pair)
                  if line is not None else None) or pf
        folds.append(AnalyticFold(pf, float(amp)))
    return AnalyticCurve("energy", 1, vary, tuple(pts), tuple(folds))
