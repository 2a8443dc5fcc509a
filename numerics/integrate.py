"""Direct integration of any model defined in :mod:`kbm` (autonomous or driven).

The right-hand side and its Jacobian are lambdified once from the symbolic
model (:mod:`numerics._compile`).  ``method="auto"`` uses DOP853 (explicit,
8th order) unless the problem is stiff — the largest eigenvalue of the Jacobian
at the start times the time span of one linear period exceeds
:data:`numerics.cycle.STIFF_THRESHOLD` — and then Radau (implicit) with the
analytic Jacobian.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np
from scipy.integrate import solve_ivp

from kbm.models import Oscillator

from ._compile import compile_model
from .cycle import STIFF_THRESHOLD
from .errors import IntegrationError

__all__ = ["integrate"]


def integrate(model: Oscillator | str, params: Mapping[str, object] | None,
              y0: Sequence[float], t_span: tuple[float, float], *, method: str = "auto",
              rtol: float = 1e-10, atol: float = 1e-12, t_eval=None, dense_output: bool = True):
    """Integrate ``x'' = -omega0^2 x + mu F(x, x') + drive(t)`` from ``y0 = (x, x')``.

    Returns
    -------
    scipy.integrate.OdeResult
        With ``method_used`` added (``"DOP853"`` or ``"Radau"`` under ``"auto"``).

    Raises
    ------
    numerics.errors.IntegrationError
        If the integrator fails or the state becomes non-finite (with the time).

    Examples
    --------
    >>> sol = integrate("vdp", {"mu": 100}, [2.0, 0.0], (0.0, 1.0))
    >>> sol.method_used
    'Radau'
    """
    cm = compile_model(model, params)
    x0, v0 = float(y0[0]), float(y0[1])
    if method == "auto":
        stiff = cm.stiffness(x0, v0) * 2 * math.pi / cm.omega0
        method = "Radau" if stiff > STIFF_THRESHOLD else "DOP853"
    kw = {"jac": cm.jac} if method in ("Radau", "BDF", "LSODA") else {}
    with np.errstate(all="ignore"):
        sol = solve_ivp(cm.rhs, t_span, [x0, v0], method=method, rtol=rtol, atol=atol,
                        t_eval=t_eval, dense_output=dense_output, **kw)
    if sol.status < 0 or not np.all(np.isfinite(sol.y[:, -1])):
        raise IntegrationError(f"{method} failed at t = {sol.t[-1]:.6g}: {sol.message}")
    sol.method_used = method
    return sol
