"""The cost of a driven-slider run with an explicit integrator: the stiffness of its damping.

The damping force of the SEDF, ``D = mu (beta x^2 - 1) x'`` (paper eq. 3), has
``|dD/dx'| = mu |beta x^2 - 1| <= mu (beta x^2 + 1)``, and an explicit Runge-Kutta method
is stable only for steps ``h <= c/|dD/dx'|`` (``c`` the length of its stability interval on
the negative real axis: about 6 for DOP853, measured ``|dD/dx'| h = 6.4`` at ``mu = 1e3,
1e4``; E. Hairer, G. Wanner, *Solving ODEs II*, sec. IV.2).  The spring drags the slider
behind the stage (``x <= v t`` while the friction force ``Omega^2 (v t - x)`` is positive)
and the self-excitation alone keeps ``|x|`` near the van der Pol amplitude ``2/sqrt(beta)``,
so ``beta x^2 + 1 <~ beta (v t)^2 + 5`` and in the lab frame the damping grows like
``(v t)^2``: a run to ``T`` needs about

``N = int_0^T mu (beta (v t)^2 + 5) dt / c = mu (beta v^2 T^3/3 + 5 T) / c``

steps.  Measured (``kbm slide sedf -p Delta=3 -p beta=1 -p v=0.01``, 0.3 ms a step):
13 442 steps to ``T = 1500``, 51 606 to 3000, 205 818 to 6000, against ``N`` = 1 900,
15 000, 120 000 (the steps are set by the accuracy, ``|dD/dx'| h`` = 1.3-1.8, until the
cubic term dominates); at ``mu = 1e4, v = 0.1, T = 15``: 47 119 against 144 000.  For the
CDC ``|dD/dx'| = mu``; for ``sedf_comoving`` ``x - v t`` stays within
``max(Delta/Omega^2, 2/sqrt(beta))``.  Implicit methods (Radau, BDF, LSODA) have no such
bound.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping

from numerics.errors import IntegrationError

__all__ = ["STABILITY_INTERVAL", "stiff_steps", "stiff_t_end", "StepGuard", "damping_rate",
           "damping_text"]

#: length of the real stability interval of the explicit methods (step ``h <= c/|lambda|``)
STABILITY_INTERVAL = {"DOP853": 6.0, "RK45": 3.3, "RK23": 2.5}


def _lambda_integral(model: str, p: Mapping[str, float], t_end: float) -> float:
    """``int_0^T |dD/dx'| dt`` on the envelope of ``|x|`` of the module docstring."""
    mu, beta, v, T = p["mu"], p.get("beta", 0.0), p.get("v", 0.0), t_end
    if model == "cdc":
        return mu * T
    if model == "sedf_comoving":
        d = p.get("Delta", 0.0) / p["Omega"] ** 2
        return mu * (max(beta * d * d, 4.0) + 1) * T
    return mu * (beta * v * v * T**3 / 3 + 5 * T)


def stiff_steps(model: str, p: Mapping[str, float], t_end: float, method: str) -> float:
    """Steps an explicit ``method`` needs for stability alone up to ``t_end`` (0 if implicit).

    Parameters
    ----------
    model
        ``"sedf"``, ``"cdc"`` or ``"sedf_comoving"``.
    p
        The physical parameters (``mu, beta, Delta, Omega, v``).
    t_end
        Final time.
    method
        The :func:`scipy.integrate.solve_ivp` method.

    Returns
    -------
    float
        ``int_0^T |dD/dx'| dt / c`` (module docstring).
    """
    c = STABILITY_INTERVAL.get(method)
    return 0.0 if c is None else _lambda_integral(model, p, t_end) / c


def stiff_t_end(model: str, p: Mapping[str, float], method: str, steps: float,
                t_end: float) -> float:
    """The largest final time (below ``t_end``) whose stability steps stay within ``steps``."""
    lo, hi = 0.0, t_end
    for _ in range(60):
        mid = (lo + hi) / 2
        lo, hi = (mid, hi) if stiff_steps(model, p, mid, method) <= steps else (lo, mid)
    return lo


class _Exhausted(Exception):
    """Raised inside the right-hand side when the evaluation budget is spent."""

    def __init__(self, t: float, y):
        super().__init__()
        self.t, self.y = t, y


class StepGuard:
    """A right-hand side that stops the integration after ``steps`` steps' worth of calls.

    ``solve_ivp`` has no bound on its steps; this wrapper counts the evaluations of ``rhs``
    (``evals_per_step`` a step: 12 for DOP853 and 3 more for its dense output) and raises
    :class:`numerics.errors.IntegrationError` from :meth:`run` with the time reached, the
    steps taken and the damping's ``|dD/dx'|`` there, so a run never hangs.
    """

    def __init__(self, rhs: Callable, steps: int, method: str, evals_per_step: int = 16):
        self.rhs, self.steps, self.method = rhs, int(steps), method
        self.limit, self.calls = self.steps * evals_per_step, 0

    def __call__(self, t, y):
        self.calls += 1
        if self.calls > self.limit:
            raise _Exhausted(float(t), y)
        return self.rhs(t, y)

    def run(self, solve: Callable, t_end: float, stiffness: Callable[[float, float], float]):
        """``solve(self)``; on an exhausted budget an :class:`IntegrationError` with numbers."""
        try:
            return solve(self)
        except _Exhausted as e:
            x = float(e.y[0])
            lam = stiffness(e.t, x)
            raise IntegrationError(
                f"the integration stopped at t = {e.t:.6g} of t_end = {t_end:g} after about "
                f"{self.steps:.3g} steps (the limit of this run): at x = {x:.4g} the damping "
                f"has |dD/dx'| = {lam:.3g}, so an explicit step is at most about "
                f"{STABILITY_INTERVAL.get(self.method, 6.0) / max(lam, 1e-300):.3g}; lower mu "
                "or t_end") from None


def damping_text(model: str) -> str:
    """``|dD/dx'|`` of ``model`` in words, for the messages (the CDC's is constant)."""
    if model == "cdc":
        return "|dD/dx'| = mu"
    if model == "sedf_comoving":
        return "|dD/dx'| = mu |beta (x - v t)^2 - 1|"
    return "|dD/dx'| = mu |beta x^2 - 1| (growing with |x| ~ v t)"


def damping_rate(model: str, p: Mapping[str, float]) -> Callable[[float, float], float]:
    """``|dD/dx'|`` at ``(t, x)``: ``mu |beta x^2 - 1|`` (``x - v t`` for sedf_comoving)."""
    mu, beta, v = p["mu"], p.get("beta", 0.0), p.get("v", 0.0)
    if model == "cdc":
        return lambda t, x: mu
    if model == "sedf_comoving":
        return lambda t, x: mu * abs(beta * (x - v * t) ** 2 - 1)
    return lambda t, x: mu * abs(beta * x * x - 1)
