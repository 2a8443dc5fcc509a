"""The stationary density of the averaged amplitude on a quadrature grid.

The averaged amplitude ``da = [A(a) + D/(2 omega0^2 a)] dt + (sqrt(D)/omega0) dW`` has the
stationary density ``P(a) = a exp((2 omega0^2/D) int_0^a A)/Z`` (the zero-flux solution of
its Fokker-Planck equation; Gardiner, *Handbook of Stochastic Methods*, sec. 5.2.2).
:func:`stationary_density` samples ``ln P`` on a uniform grid of :data:`GRID` points that
spans where ``P`` is within ``exp(-CUT)`` of its peak: a density of width
``sigma = (D/(2 omega0^2 lambda))^(1/2)`` about the cycle ``a*`` is regridded onto its own
range, so that a narrow one (small ``D/mu``) is resolved as finely as a wide one.
:func:`response_cycle` finds the cycle at which the order-2 phase response is taken.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping

import numpy as np

from ..errors import NoCycleError

__all__ = ["GRID", "CUT", "stationary_density", "response_cycle"]

GRID = 20001  # quadrature points in a
CUT = 60.0  # ln P below its peak where the quadrature stops


def _log_density(A: Callable, grid: np.ndarray, w0: float, D: float
                 ) -> tuple[np.ndarray, np.ndarray]:
    """``(A(grid), ln P(grid))`` up to a constant (the trapezoid rule for ``int A``)."""
    with np.errstate(all="ignore"):
        Av = np.asarray(A(grid, 0.0), float) * np.ones_like(grid)
    Av[0] = 0.0 if not np.isfinite(Av[0]) else Av[0]
    cum = np.concatenate([[0.0], np.cumsum(0.5 * (Av[1:] + Av[:-1]) * np.diff(grid))])
    with np.errstate(divide="ignore"):
        return Av, np.log(grid) + 2 * w0**2 * cum / D


def _barrier(lnp: np.ndarray, a_u: float, a_star: float, D: float, order: int) -> None:
    """Refuse a density that leaks over the unstable root ``a_u > a*`` of ``A``: the
    averaged amplitude escapes past ``a_u`` to infinity unless ``ln P(a*) - ln P(a_u)``
    exceeds :data:`CUT` (then the density below ``a_u`` is stationary to ``exp(-CUT)``).
    The barrier scales as ``1/D``, hence the largest ``D`` that holds."""
    top = int(np.argmax(lnp))
    drop = float(lnp[top] - np.min(lnp[top:]))
    if drop > CUT:
        return
    where = ("its second-order rate mu A_1 + mu^2 A_2, a truncated series in mu,"
             if order >= 2 else "its rate A")
    raise NoCycleError(
        f"the averaged amplitude equation has an unstable cycle at a = {a_u:.4g} beyond the "
        f"stable one a* = {a_star:.4g} ({where} turns positive again), and the noise D = "
        f"{D:g} crosses it: ln P falls only {drop:.3g} between them (a stationary line needs "
        f"> {CUT:g}), so the averaged amplitude escapes and there is no line at this order; "
        f"give D below about {D * drop / CUT:.2g}"
        + (", or use --order 1" if order >= 2 else ""))


def stationary_density(A: Callable, a_star: float, lam: float, w0: float, D: float,
                       order: int) -> tuple[np.ndarray, np.ndarray]:
    """``(a, ln P(a))`` on a uniform grid where ``ln P`` is within :data:`CUT` of its peak.

    Parameters
    ----------
    A : callable
        The averaged amplitude rate ``A(a, psi)`` (numpy).
    a_star, lam : float
        The stable cycle and its relaxation rate ``-A'(a*)`` (the first grid's span).
    w0, D : float
        ``omega0`` and the noise intensity.
    order : int
        The averaging order (named in the refusal).

    Raises
    ------
    numerics.errors.NoCycleError
        ``A`` turns positive again at ``a_u > a*`` and ``ln P`` falls by less than
        :data:`CUT` between them: the noise escapes over the unstable cycle.
    """
    hi = a_star + 12 * math.sqrt(D / (2 * w0**2 * lam))
    while True:
        grid = np.linspace(0.0, hi, GRID)
        Av, lnp = _log_density(A, grid, w0, D)
        rise = np.flatnonzero((grid > a_star) & (Av > 0))
        if rise.size:
            # A changes sign again at a_u > a*: an unstable cycle (at order 2 the truncated
            # series' higher powers of a), beyond which P grows without bound
            grid, lnp = grid[:rise[0]], lnp[:rise[0]]
            _barrier(lnp, grid[-1], a_star, D, order)
            break
        if lnp[-1] < np.max(lnp) - CUT or hi > 1e3:
            break
        hi *= 1.5
    if not np.isfinite(np.max(lnp)):
        raise NoCycleError(f"the averaged amplitude's density P(a) is not finite on 0 < a < "
                           f"{grid[-1]:.4g} (cycle a* = {a_star:.4g}, D = {D:g}): its rate A "
                           "is not a number there; no line at this order")
    keep = lnp > np.max(lnp) - CUT
    while np.count_nonzero(keep) < GRID // 10:
        # a narrow density (small D/mu): the grid again, on its range (one step wider)
        i, j = np.flatnonzero(keep)[[0, -1]]
        grid = np.linspace(grid[max(i - 1, 1)], grid[min(j + 1, grid.size - 1)], GRID)
        lnp = _log_density(A, grid, w0, D)[1]
        keep = lnp > np.max(lnp) - CUT
    return grid[keep], lnp[keep]


def response_cycle(pd, subs: Mapping, a_star: float, order: int) -> float:
    """The cycle of the phase response's rate (``A`` to ``A_3`` at order 2), by Newton's
    method from the averaged cycle ``a*``: ``mu^3 A_3`` moves it by ``O(mu^2)`` (van der
    Pol: ``2 + mu^2/64``).  ``a*`` itself where the phase response has the order's rate."""
    import sympy as sp
    from kbm.symbols import a

    from ._evaluate import fn

    if pd.response_order <= order:
        return a_star
    rate = fn(pd.response_rate, subs, False)
    slope = fn(sp.diff(pd.response_rate, a), subs, False)
    r = a_star
    for _ in range(50):
        step = float(rate(r, 0.0)) / float(slope(r, 0.0))
        r -= step
        if not (math.isfinite(r) and 0.5 * a_star < r < 2 * a_star):
            break
        if abs(step) <= 1e-15 * r:
            if float(slope(r, 0.0)) < 0:
                return r
            break
    raise NoCycleError(f"the third-order amplitude rate mu A_1 + mu^2 A_2 + mu^3 A_3 (the "
                       f"phase response's) has no stable cycle near a* = {a_star:.4g}: the "
                       "averaging's series in mu does not hold at these values; give a "
                       "smaller mu, or use --order 1")
