"""The cost of a driven-slider run with an explicit integrator: the stiffness of its damping.

An explicit Runge-Kutta method is stable only for steps ``h <= c/|dD/dx'|``, with ``D`` the
damping force of ``x'' + D(x, x', t) + ... = 0`` and ``c`` the length of the method's
stability interval on the negative real axis (about 6 for DOP853, measured ``|dD/dx'| h =
6.4`` at ``mu = 1e3, 1e4``; E. Hairer, G. Wanner, *Solving ODEs II*, sec. IV.2), so a run to
``T`` needs about ``N = int_0^T |dD/dx'| dt / c`` steps.

``dD/dx' = -mu dF/dx'`` is derived from the model's one symbolic definition (sympy's
derivative of ``F``, :func:`damping_derivative`, memoised per model like the compiled
equations of :mod:`numerics.sliding.driven`): its part attached to the stage
(:attr:`~kbm.model.oscillator.Oscillator.stage_relative`, measured by the spring's extension
``x - v t``) and the rest, measured by the lab-frame ``x``.  Along a run ``|dD/dx'|`` is bounded
by its largest value on the envelope of the motion (:func:`damping_envelope`, on a grid of 33
points a side, its ends included), in mean squares:

- the position: ``x^2 <~ R^2 = (v t)^2 + A^2``: the spring drags the slider behind the stage
  (``x <= v t`` while the friction force ``Omega^2 (v t - x)`` is positive) and the
  self-excitation alone keeps it within its cycle's amplitude ``A``;
- the spring's extension ``z = x - v t``: ``|z| <~ max(d, A)`` (``d`` the largest pinning force
  over the spring's stiffness, ``Delta/Omega^2``) if the spring can pull the slider through
  the stage-attached damping at the stage velocity (``max over z < 0 of omega0^2 |z| + mu
  F_stage(z, x' = v)`` above the pinning force), else the lag grows with the stage and
  ``z^2 <~ R^2``;
- the velocity: ``x'^2 <~ v^2 + (A omega0)^2``.

``A`` is the first-order KBM amplitude of the cycle: the stable positive root of the
first-order amplitude rate ``A_1(a)`` of :func:`kbm.derive` (where the mean power of the
dissipative force over ``x = a cos phi`` turns from gain to loss; 0 for none).  For the SEDF (paper eq. 3) ``|dD/dx'| = mu |beta x^2 -
1|`` is largest at ``|x| = R`` and ``A = 2/sqrt(beta)``, so

``N = int_0^T mu (beta (v t)^2 + 3) dt / c = mu (beta v^2 T^3/3 + 3 T) / c``;

for the CDC (eq. 12) ``N = mu T/c``; for ``sedf_comoving`` ``mu (beta max(d, A)^2 - 1) T/c``
when it follows the stage (``Omega^4/(4 mu beta v) + mu v >= Delta``), else the SEDF's.

Measured (``slide`` at ``beta = 1, Omega = 1``, ``Delta = 3`` unless said, DOP853 at ``rtol =
1e-10``, 30 runs; ``path`` the stability integral ``int |dD/dx'| dt / c`` along the run itself;
``old`` the earlier rule: every coefficient by its modulus on ``x^2 <~ (v t)^2 + A^2``, ``mu
(beta v^2 T^3/3 + 5 T)/c`` for the SEDF, and ``|x - v t| <~ max(d, A)`` always):

=========================  ======  ======  ======  =======  ======
model, mu, v, T            steps   path    N       steps/N  old
=========================  ======  ======  ======  =======  ======
sedf 1e4, 0.1, 15          47119   50051   93750   0.50     143750
sedf 1e4, 1, 3             9531    9998    30000   0.32     40000
sedf 1e3, 1, 5             1704    1673    9444    0.18     11111
sedf 100, 0.1, 15          1205    547     938     1.3      1438
sedf 0.1, 0.01, 1500       13442   1075    1950    6.9      2000
sedf 0.1, 0.01, 6000       205817  100772  120300  1.7      120500
cdc 1e4, 0.1, 15           23463   25000   25000   0.94     25000
sedf_comoving 1e4, 0.1, 15 33661   34639   200000  0.17     250000
sedf_comoving 10, 0.1, 100 6116    4529    6056    1.0      1667
sedf_comoving 3, 0.1, 100  4005    618     1817    2.2      500
sedf_comoving 0.1, 0.01,   12178   125     200     61       250
1500
sedf_comoving 0.1, 0.01,   20089   35      75      268      125
1500, Delta = 0.5
=========================  ======  ======  ======  =======  ======

``N`` is above the path in all 30 runs (at least 1.19 times; the old rule was below it for the
held-back ``sedf_comoving`` at ``mu = 10`` and 3, by 2.7 and 1.2 times).  Where the stability
limits the step (``|dD/dx'| h = 6.4`` at large ``mu``) the steps are 0.2-0.6 of ``N`` (the
slider lags the stage, and a relaxation cycle averages ``|beta x^2 - 1|`` to 2, not 3: 0.33
with the old rule); where the accuracy limits it (small ``mu``, ``|dD/dx'| h`` = 0.005-1.3) the
steps exceed ``N``, up to 7 times for the SEDF and 270 times for a weak stage-attached
damping, which no stability bound sees (the run's own step budget, :class:`StepGuard`, stops
those).  Implicit methods (Radau, BDF, LSODA) have no such bound.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping

import numpy as np

from kbm.model.builtins import Oscillator

from numerics.errors import IntegrationError
from numerics.sliding.damping import amplitude, damping_derivative, follows_stage, scaled_values

__all__ = ["STABILITY_INTERVAL", "stiff_steps", "stiff_t_end", "StepGuard", "damping_envelope"]

#: length of the real stability interval of the explicit methods (step ``h <= c/|lambda|``)
STABILITY_INTERVAL = {"DOP853": 6.0, "RK45": 3.3, "RK23": 2.5}

#: points a side of the envelope's grid (odd: the ends and 0 are on it)
GRID = 33
#: Gauss-Legendre nodes of ``int_0^T`` (exact for the polynomial envelopes up to degree 15)
_GL = np.polynomial.legendre.leggauss(8)


def damping_envelope(model: str | Oscillator, p: Mapping[str, float]
                     ) -> Callable[[np.ndarray], np.ndarray]:
    """The bound of ``|dD/dx'|`` at times ``t`` on the envelope of the motion (module docstring).

    Parameters
    ----------
    model
        As in :func:`damping_derivative`.
    p
        The physical parameters (``mu, beta, Delta, Omega, v``, ...).

    Returns
    -------
    callable
        ``t -> max |dD/dx'|`` over ``|x|, |x - v t| <= sqrt((v t)^2 + A^2)`` and ``|x'| <=
        sqrt(v^2 + (A omega0)^2)`` (a grid of :data:`GRID` points a side, the ends
        included; a single point for a variable ``dD/dx'`` does not depend on).
    """
    d = damping_derivative(model)
    vals = scaled_values(model, p)
    v = float(p.get("v", 0.0))
    amp = amplitude(d, vals)
    w = d.omega(vals)
    vel = math.sqrt(v * v + (amp * w) ** 2)
    follows = follows_stage(d, vals, v, w)
    u = [np.linspace(-1.0, 1.0, GRID) if used else np.zeros(1) for used in d.states]

    def bound(t: np.ndarray) -> np.ndarray:
        r = np.sqrt((v * np.asarray(t, dtype=float)) ** 2 + amp**2)[:, None, None, None]
        rz = max(d.pinning(vals) / w**2, amp) if follows else r
        x, xdot, z = (r * u[0][:, None, None], vel * u[1][:, None], rz * u[2])
        vals_grid = np.broadcast_to(np.abs(d.grid(vals, x, xdot, z)), np.broadcast_shapes(
            x.shape, np.shape(xdot), z.shape))
        return vals_grid.reshape(len(r), -1).max(axis=1)
    return bound


def _lambda_integral(model: str | Oscillator, p: Mapping[str, float], t_end: float,
                     envelope: Callable | None = None) -> float:
    """``int_0^T |dD/dx'| dt`` on the envelope of the module docstring (Gauss-Legendre)."""
    nodes, weights = _GL
    bound = envelope or damping_envelope(model, p)
    half = t_end / 2
    return float(half * np.dot(weights, bound(half * (nodes + 1))))


def stiff_steps(model: str | Oscillator, p: Mapping[str, float], t_end: float,
                method: str) -> float:
    """Steps an explicit ``method`` needs for stability alone up to ``t_end`` (0 if implicit).

    Parameters
    ----------
    model
        A slider's name (``"sedf"``, ``"cdc"``, ``"sedf_comoving"``) or an
        :class:`~kbm.model.oscillator.Oscillator` (:func:`damping_derivative`).
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


def stiff_t_end(model: str | Oscillator, p: Mapping[str, float], method: str, steps: float,
                t_end: float) -> float:
    """The largest final time (below ``t_end``) whose stability steps stay within ``steps``."""
    c = STABILITY_INTERVAL.get(method)
    if c is None:
        return t_end
    envelope = damping_envelope(model, p)
    lo, hi = 0.0, t_end
    for _ in range(60):
        mid = (lo + hi) / 2
        fits = _lambda_integral(model, p, mid, envelope) / c <= steps
        lo, hi = (mid, hi) if fits else (lo, mid)
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

    def run(self, solve: Callable, t_end: float, stiffness: Callable[[float, object], float]):
        """``solve(self)``; on an exhausted budget an :class:`IntegrationError` with numbers
        (``stiffness(t, y)`` the damping's ``|dD/dx'|`` at the state ``y`` reached)."""
        try:
            return solve(self)
        except _Exhausted as e:
            x = float(e.y[0])
            lam = stiffness(e.t, e.y)
            raise IntegrationError(
                f"the integration stopped at t = {e.t:.6g} of t_end = {t_end:g} after about "
                f"{self.steps:.3g} steps (the limit of this run): at x = {x:.4g} the damping "
                f"has |dD/dx'| = {lam:.3g}, so an explicit step is at most about "
                f"{STABILITY_INTERVAL.get(self.method, 6.0) / max(lam, 1e-300):.3g}; lower mu "
                "or t_end") from None
