"""The paper's own KBM formulas, eqs. (5)-(9) as printed, as a predicted cycle.

:func:`paper_prediction` takes :mod:`kbm.output.paper` literally: ``a*`` is a root of
eq. (7), the frequency eq. (6) at ``a*``, the orbit ``x = a cos psi + mu f + mu^2
g`` (eqs. 5, 8, 9).  It is one of the ``extra`` rows of :func:`numerics.compare`.

References
----------
M. D'Acunto, "Friction force for self-excited systems", eqs. (5)-(9).
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import sympy as sp
from scipy.optimize import brentq

from kbm.output import paper
from kbm.errors import ParameterError
from kbm.output.evaluate import numpy_function
from kbm.parameters.bound import BoundModel
from kbm.model.builtins import Oscillator, get_model

from numerics.comparison.prediction import (Prediction, cycle_measures, dissipation_functions,
                                            reconstruct)

__all__ = ["paper_prediction"]


def _physical(model: Oscillator, vals: Mapping[str, sp.Expr]) -> dict[str, float]:
    """``mu, beta, Delta, k`` of the paper from resolved scaled values (Omega must be 1)."""
    if model.name != "sedf":
        raise ParameterError("the paper's formulas (eqs. 5-9) are for the sedf model only")
    if float(vals.get("Omega", 1)) != 1.0:
        raise ParameterError("the paper's formulas (eqs. 5-9) assume Omega = 1")
    m = float(vals["mu"])
    return {"mu": m, "beta": float(vals["beta"]), "Delta": float(vals["delta"]) * m,
            "k": float(vals["k"])}


def paper_prediction(values: Mapping[str, object] | BoundModel, *,
                     target_amplitude: float | None = None,
                     n_samples: int = 1024, n_harmonics: int = 16, a_max: float = 20.0,
                     n_grid: int = 20000) -> Prediction:
    """The cycle of the paper's eqs. (5)-(9) taken literally (:mod:`kbm.output.paper`), for sedf.

    ``a*`` is the root of eq. (7) closest to ``target_amplitude``, the frequency
    is eq. (6) at ``a*``, ``x = a cos psi + mu f + mu^2 g`` (eqs. 5, 8, 9) and the
    multiplier ``exp(T d(a')/da)``.
    """
    label = "paper eqs. (5)-(9)"
    model = get_model("sedf")
    if isinstance(values, BoundModel):
        if values.name != "sedf":
            raise ParameterError("the paper's formulas (eqs. 5-9) are for the sedf model only")
        vals = values.values
    else:
        vals = model.resolve(dict(values))
    ph = _physical(model, vals)
    syms = [paper.mu, paper.beta, paper.Delta, paper.k]
    pv = [ph["mu"], ph["beta"], ph["Delta"], ph["k"]]
    rate = numpy_function(paper.amplitude_rate(), [paper.a, *syms])
    drate = numpy_function(sp.diff(paper.amplitude_rate(), paper.a), [paper.a, *syms])
    phase = numpy_function(paper.phase_rate(), [paper.a, *syms])
    xfun = numpy_function(paper.displacement(), [paper.a, paper.psi, *syms])
    grid = np.linspace(a_max / n_grid, a_max, n_grid)
    g = rate(grid, *pv) / grid
    roots = [brentq(lambda s: float(rate(s, *pv)) / s, grid[i], grid[i + 1], xtol=1e-15)
             for i in np.nonzero(np.sign(g[:-1]) * np.sign(g[1:]) < 0)[0]]
    if not roots:
        return Prediction(label=label, order=0, success=False, source="paper",
                          message=f"eq. (7) has no root 0 < a <= {a_max}")
    if target_amplitude is None:
        st = [r for r in roots if drate(r, *pv) < 0] or roots
        root = max(st)
    else:
        root = min(roots, key=lambda r: abs(r - target_amplitude))
    slope = float(drate(root, *pv))
    omega = float(phase(root, *pv))
    if omega <= 0:
        return Prediction(label=label, order=0, success=False, amplitude=root, source="paper",
                          message=f"eq. (6) gives the frequency {omega:.4g} <= 0 at a* = {root:.6g}")
    T = 2 * np.pi / omega

    def x_of_psi(p):
        return xfun(root, p, *pv)

    psi, xs, vs = reconstruct(x_of_psi, omega, n_samples=n_samples)
    fp, fm, factor = dissipation_functions(model, vals)
    xmax, harm, gp, gm, gam = cycle_measures(x_of_psi, psi, xs, vs, T, fp, fm, factor,
                                              n_harmonics)
    msg = f"a* = {root:.10g}; eq. (7) has {len(roots)} root(s) in (0, {a_max}]"
    return Prediction(label=label, order=0, success=True, message=msg, amplitude=root,
                      amplitude_max=xmax, frequency=omega, period=T, harmonics=harm,
                      dA_da=slope, stable=slope < 0, floquet_multiplier=float(np.exp(T * slope)),
                      dissipation=gam, gamma_plus=gp, gamma_minus=gm, psi=psi, x=xs, xdot=vs,
                      source="paper")
