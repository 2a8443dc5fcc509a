"""Simulated escapes from the well at the origin: first passages of Langevin trajectories.

Each trajectory starts at the bottom of the well (``x = x' = 0``) and runs until ``|x|``
reaches the saddle bounding the well on its side (the top of the barrier; beyond it the
conservative flow leaves the well) or until ``t_end`` (censored).  The rate is the
censoring-correct maximum-likelihood estimate for exponential waiting times,

``r = k / sum_i min(tau_i, t_end)``,  standard error ``r/sqrt(k)``

(``k`` escapes; Lawless, *Statistical Models and Methods for Lifetime Data*, 2nd ed.,
section 2.2).  Without censoring ``1/r`` is the sample mean first-passage time, the
quantity the averaged MFPT predicts.  The trajectories come from the Langevin
integrator of :mod:`numerics.noise`, one seed per trajectory spawned from one
``numpy.random.SeedSequence``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from kbm.errors import ParameterError

from ..errors import NumericsError

__all__ = ["SimulatedEscape", "censored_rate", "simulated_escape"]


@dataclass(frozen=True)
class SimulatedEscape:
    """First passages over the barrier.

    Attributes
    ----------
    rate, stderr : float
        Censoring-correct rate and its standard error.
    escaped, censored : int
        Trajectories that escaped before ``t_end`` and those that did not.
    times : numpy.ndarray
        ``min(tau_i, t_end)`` per trajectory.
    t_end, dt : float
    seed : int
    start : str
        Where the trajectories start: ``"bottom"`` (``x = x' = 0``) or ``"boltzmann"`` (the
        well's Boltzmann density, :mod:`numerics.escape.transitions`).
    settle : float
        The rate counts the waiting times after ``t = settle`` of the trajectories still
        in the well then (0: from the start; :mod:`numerics.escape.transitions`).
    settled : int or None
        How many trajectories were still in the well at ``settle``.
    """

    rate: float
    stderr: float
    escaped: int
    censored: int
    times: np.ndarray
    t_end: float
    dt: float
    seed: int
    start: str = "bottom"
    settle: float = 0.0
    settled: int | None = None

    def __repr__(self) -> str:
        return (f"SimulatedEscape(rate={self.rate:.4g} +- {self.stderr:.2g}, "
                f"{self.escaped} escaped, {self.censored} censored)")


def censored_rate(times, escaped) -> tuple[float, float]:
    """``(k / sum t_i, rate / sqrt(k))`` for waiting times ``t_i`` of which those with
    ``escaped`` true ended in an escape (the others are censored).

    Raises
    ------
    numerics.errors.NumericsError
        No escape at all (then only a bound, ``rate < 3/sum t`` at 95 %, is known).
    """
    t = np.asarray(times, float)
    k = int(np.count_nonzero(escaped))
    total = float(np.sum(t))
    if k == 0:
        raise NumericsError(f"no trajectory escaped in a total time {total:.4g}: the rate is "
                            f"below {3 / total:.3g} (95 %); run longer (--t-end)")
    r = k / total
    return r, r / math.sqrt(k)


def simulated_escape(split, D: float, saddles, *, trajectories: int, t_end: float, dt: float,
                     seed: int = 0) -> SimulatedEscape:
    """Escape times of ``trajectories`` Langevin runs from the well bottom.

    Parameters
    ----------
    split : kbm.model.conservative.ConservativeSplit
        The model (``x'' = -g + mu h + sqrt(2 D) xi``).
    D : float
        Noise intensity.
    saddles : tuple of float
        ``(x_l, x_r)``: escape when ``x <= x_l`` or ``x >= x_r``.
    trajectories : int
    t_end, dt : float
        Longest run and time step.
    seed : int
        Root of the ``SeedSequence``.

    Raises
    ------
    numerics.errors.NumericsError
        When the Langevin integrator (:mod:`numerics.noise`) is not available, or no
        trajectory escaped.
    """
    if trajectories < 2:
        raise ParameterError("at least 2 trajectories are needed for a standard error")
    try:
        from ._passage import first_passages
    except ImportError as exc:  # the integrator lives in numerics.noise
        raise NumericsError("the Langevin integrator (numerics.noise) is not in this build: "
                            f"no simulated escapes ({exc})") from None
    times, escaped = first_passages(split, D, saddles, trajectories=trajectories, t_end=t_end,
                                    dt=dt, seed=seed)
    r, se = censored_rate(times, escaped)
    k = int(np.count_nonzero(escaped))
    return SimulatedEscape(r, se, k, int(trajectories) - k, np.asarray(times), float(t_end),
                           float(dt), int(seed))
