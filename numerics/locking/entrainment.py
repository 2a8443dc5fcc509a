"""Entrainment of a self-excited oscillator: the locking boundary, predicted and true.

A forced self-excited oscillator (forced van der Pol) is *locked* to the drive when it has a
stable periodic response of the drive's period.  The predicted boundary is the largest
detuning with a stable fixed point of the order-``N`` slow flow; the true one the largest
detuning with a stable periodic response (Floquet multipliers inside the unit circle).
Both are found by bisection in ``sigma`` from a locked detuning (``sigma = 0``); the true
response is followed by shooting from the neighbouring one, so that a fold (saddle-node,
where the response disappears) and a loss of stability (Neimark-Sacker, the slow flow's
Hopf) both end the locked range.  :func:`locked_by_simulation` is an independent check by
long integration: the stroboscopic points ``y(k T)`` converge when locked and drift when not.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from kbm.expansion.forced_result import SlowFlow
from kbm.slowflow.steady import fixed_points

from numerics.errors import NumericsError
from numerics.shooting.forced_branch import guess_from
from numerics.shooting.forced_orbit import ForcedOrbit, periodic_response
from numerics.flow.forced_system import ForcedSystem

__all__ = ["predicted_boundary", "true_boundary", "locked_by_simulation", "LockingBoundary",
           "start_orbit"]


@dataclass(frozen=True)
class LockingBoundary:
    """The edge of the locked range: detuning and the last locked response there."""

    sigma: float
    amplitude: float


def _stable_fp(sf: SlowFlow, s: float, amplitudes):
    st = [f for f in fixed_points(sf, s, amplitudes) if f.stable]
    return max(st, key=lambda f: f.amplitude) if st else None


def predicted_boundary(sf: SlowFlow, sigma_max: float, *, amplitudes=(1e-2, 4.0),
                       tol: float = 1e-8) -> LockingBoundary:
    """The largest ``0 < sigma < sigma_max`` with a stable fixed point (bisection).

    Raises
    ------
    numerics.errors.NumericsError
        If ``sigma = 0`` is not locked or ``sigma_max`` is.
    """
    if _stable_fp(sf, 0.0, amplitudes) is None:
        raise NumericsError("no stable fixed point of the slow flow at sigma = 0: not locked")
    if _stable_fp(sf, sigma_max, amplitudes) is not None:
        raise NumericsError(f"still locked at sigma = {sigma_max}; give a larger sigma_max")
    lo, hi = 0.0, float(sigma_max)
    while hi - lo > tol:
        mid = 0.5 * (lo + hi)
        if _stable_fp(sf, mid, amplitudes) is not None:
            lo = mid
        else:
            hi = mid
    return LockingBoundary(lo, _stable_fp(sf, lo, amplitudes).amplitude)


def true_boundary(system: ForcedSystem, start: ForcedOrbit, sigma_max: float, *,
                  tol: float = 1e-7) -> LockingBoundary:
    """The largest detuning above ``start.sigma`` with a stable periodic response, followed
    from ``start`` (a stable response) by bisection; each trial shoots from the last locked
    response."""
    if not start.stable:
        raise NumericsError(f"the response at sigma = {start.sigma} is not stable")
    last = start
    hi = float(sigma_max)
    while hi - last.sigma > tol:
        mid = 0.5 * (last.sigma + hi)
        try:
            o = periodic_response(system, mid, last.y0)
            ok = o.stable and abs(o.amplitude - last.amplitude) < 0.2 * last.amplitude + 0.05
        except NumericsError:
            ok = False
        if ok:
            last = o
        else:
            hi = mid
    return LockingBoundary(last.sigma, last.amplitude)


def locked_by_simulation(system: ForcedSystem, sigma: float, y0, *,
                         periods: int = 3000) -> bool:
    """Whether a long integration from ``y0`` stays locked to the drive.

    The stroboscopic points ``y(kT)`` (``T`` the drive's period) of a locked response
    converge, those of a drifting (quasi-periodic) one turn round the origin: locked when
    the unwrapped polar angle of the points changes by less than ``pi/2`` over the second
    half of ``periods`` drive periods."""
    y = np.array(y0, dtype=float)
    w = system.resonance.q / system.resonance.p * system.nu(sigma)
    angles = []
    for _ in range(periods):
        y = system.flow(y, sigma, extended=False)[-1][:2]
        angles.append(np.arctan2(-y[1] / w, y[0]))
    ang = np.unwrap(np.array(angles))[periods // 2:]
    return float(np.ptp(ang)) < np.pi / 2


def start_orbit(system: ForcedSystem, sf: SlowFlow, amplitudes=(1e-2, 4.0)) -> ForcedOrbit:
    """The stable response at ``sigma = 0`` from the slow flow's stable fixed point."""
    fp = _stable_fp(sf, 0.0, amplitudes)
    if fp is None:
        raise NumericsError("no stable fixed point of the slow flow at sigma = 0")
    return periodic_response(system, 0.0, guess_from(system, fp.amplitude, fp.phase, 0.0))
