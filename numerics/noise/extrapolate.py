"""Richardson (Talay-Tubaro) extrapolation of stationary moments over the step.

BAOAB's stationary averages have the expansion ``E_h = E + c_2 h^2 + c_4 h^4 + ...`` in
even powers of the step (a symmetric splitting; measured by
:mod:`numerics.noise.invariant` on an exact case: the ``h^3`` coefficient is below its
resolution).  The pair ``h``, ``h/2`` run on one Brownian path (Gaussian increments, the two
fine ones summing to the coarse one; the kernel ``step_pair_stats``) gives

``R(h) = (4 E_{h/2} - E_h)/3 = E - c_4 h^4/4 + O(h^6)``

(Talay & Tubaro, Stoch. Anal. Appl. 8 (1990) 483), at three force evaluations per coarse
step.  The two runs stay close, so the correction ``(E_{h/2} - E_h)/3`` has a small
variance and the error of ``R`` is nearly that of ``E_{h/2}`` alone.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from kbm.errors import ParameterError

from ..errors import NumericsError
from .langevin import LangevinSystem, steps_of
from .seeds import trajectory_states

__all__ = ["RichardsonMoment", "richardson_moments", "ORDER"]

#: the weak order of the extrapolated pair (BAOAB's even expansion; tests measure it)
ORDER = 4


@dataclass(frozen=True)
class RichardsonMoment:
    """One stationary moment at the steps ``h`` and ``h/2`` and extrapolated.

    Attributes
    ----------
    coarse, fine, extrapolated : float
        ``E_h``, ``E_{h/2}`` and ``R = (4 E_{h/2} - E_h)/3``.
    stderr : float
        The standard error of ``R`` over trajectories.
    correction, correction_stderr : float
        ``R - E_{h/2} = (E_{h/2} - E_h)/3`` (the bias of ``E_{h/2}`` removed) and its
        standard error (small: the two runs share their noise).
    """

    coarse: float
    fine: float
    extrapolated: float
    stderr: float
    correction: float
    correction_stderr: float

    def as_dict(self) -> dict:
        return {"coarse": self.coarse, "fine": self.fine, "extrapolated": self.extrapolated,
                "stderr": self.stderr, "correction": self.correction,
                "correction_stderr": self.correction_stderr}


def _moment(coarse: np.ndarray, fine: np.ndarray) -> RichardsonMoment:
    m = coarse.size
    rich = (4.0 * fine - coarse) / 3.0
    corr = (fine - coarse) / 3.0
    return RichardsonMoment(float(coarse.mean()), float(fine.mean()), float(rich.mean()),
                            float(rich.std(ddof=1) / math.sqrt(m)), float(corr.mean()),
                            float(corr.std(ddof=1) / math.sqrt(m)))


def richardson_moments(system: LangevinSystem, h: float, *, trajectories: int, t_end: float,
                       burn_in: float, seed: int = 0) -> dict[str, RichardsonMoment]:
    """``<x^2>`` and ``<a^2>`` at the steps ``h`` and ``h/2`` and extrapolated (weak order 4
    for BAOAB: :data:`ORDER`).

    Parameters
    ----------
    system : LangevinSystem
        BAOAB (``scheme="baoab"``): the even expansion is BAOAB's.
    h : float
        The coarse step; ``t_end`` and ``burn_in`` whole numbers of it.
    trajectories : int
        At least 2 (a standard error).
    t_end, burn_in : float
        The averaging time per trajectory and the time discarded before it.
    seed : int
        Root seed (one spawned stream per trajectory).

    Returns
    -------
    dict
        ``{"x2": RichardsonMoment, "a2": RichardsonMoment}``.

    Raises
    ------
    kbm.errors.ParameterError
        Kloeden-Platen (its expansion has odd terms), fewer than 2 trajectories, times
        that are not whole numbers of steps.
    numerics.errors.NumericsError
        When a trajectory diverges.
    """
    if system.scheme != "baoab":
        raise ParameterError("Richardson extrapolation to order 4 needs BAOAB's even expansion: "
                             "build the system with scheme 'baoab'")
    if trajectories < 2:
        raise ParameterError(f"trajectories = {trajectories}: at least 2 are needed for a "
                             "standard error")
    n_run = steps_of(t_end, h)
    n_burn = 0 if burn_in == 0 else steps_of(burn_in, h)
    states = trajectory_states(seed, 0, trajectories)
    rows = system.kernels.step_pair_stats(system._p(), system.sigma,
                                          np.zeros((trajectories, 2)), 0.0, float(h), n_burn,
                                          n_run, states, system.omega0)
    if not np.all(np.isfinite(rows)):
        raise NumericsError(f"a trajectory diverged at h = {h:g}: take a smaller step")
    return {"x2": _moment(rows[:, 0], rows[:, 2]), "a2": _moment(rows[:, 1], rows[:, 3])}
