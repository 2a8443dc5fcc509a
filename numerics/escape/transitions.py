"""Simulated transitions to the next wells: the quantity of the Fokker-Planck escape rate.

:func:`numerics.fokker_planck.kramers_escape` gives the rate of transitions from the well
at the origin to the next wells (the slowest decay rate with a sink at the next wells'
bottoms ``x_wl < x_l < 0 < x_r < x_wr``; flux over population).  Its simulated
counterpart is the first passage to the lines ``x = x_wl``, ``x = x_wr`` of trajectories
started in the well's *quasi-stationary* state, the density that decays as
``exp(-r t)`` without changing shape: from it the waiting time is exactly exponential
with mean ``1/r`` (the mean first-passage time from the quasi-stationary state is the
inverse of the lowest eigenvalue; Hanggi, Talkner and Borkovec, Rev. Mod. Phys. 62 (1990)
251, sec. II.C and VII), so the censoring-correct estimate ``k / sum_i min(tau_i, t_end)``
(:func:`numerics.escape.simulate.censored_rate`) is the FP rate's like quantity.

The start: for linear damping the quasi-stationary state is the Boltzmann density
``exp(-(v^2/2 + G(x))/kT)`` inside the well (``x_l < x < x_r``) up to a layer at the
barrier that holds a fraction ``~exp(-E_b/kT)`` of it (:class:`WellBoltzmann`); each start
is drawn exactly from it (the position by inverting the cumulative density, the velocity
Gaussian).  That layer is not small at a low barrier: at E_b/kT = 3.1 (CDC, Delta = 3,
D = 0.35 mu) the starts in it leave at once and the rate from ``t = 0`` was 4 % (mu = 0.2)
and 10 % (mu = 0.02) above the Fokker-Planck rate, 5.8 standard errors at 20000 and 4000
trajectories.  So the rate counts only what happens after the well's relaxation time,
``settle = 2 max(1/gamma, gamma/omega_0^2)`` (``gamma = D/kT``; energy relaxation at low
friction, spatial at high friction): the trajectories still in the well then are in the
quasi-stationary state and, the waiting time being memoryless from it, their waiting
times after ``settle`` are exponential with the same rate (left truncation; Lawless,
*Statistical Models and Methods for Lifetime Data*).  Not from the bottom: a trajectory
from ``x = x' = 0`` first needs about a relaxation time of the well (``~1/mu`` at low
friction) to reach the thermal energies, so its first-passage time is not exponential and
its mean exceeds ``1/r``.  Without linear
damping there is no Boltzmann density; the trajectories then start at the bottom (``start
= "bottom"``, reported) and the rate is low by about ``r`` times that relaxation time.

The trajectories draw their increments from the streams of :mod:`numerics.noise.seeds`
with the spawn-key prefix :data:`WELLS_STREAM` (independent of the saddle run of the same
root seed); trajectory ``i``'s start comes from the first child of that same
``SeedSequence(seed, spawn_key=(1, i))``, so a run's numbers depend on ``(seed, i)``
alone.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from kbm.errors import ModelError, ParameterError

from ..errors import NumericsError
from .simulate import SimulatedEscape, censored_rate

__all__ = ["WellBoltzmann", "simulated_transitions", "WELLS_STREAM"]

#: spawn-key prefix of the transition runs' trajectory streams
WELLS_STREAM = (1,)


@dataclass(frozen=True)
class WellBoltzmann:
    """The Boltzmann density ``exp(-(v^2/2 + G(x))/kT)`` restricted to ``x_l < x < x_r``.

    Attributes
    ----------
    grid, cdf : numpy.ndarray
        Positions and the cumulative density there (trapezoidal on ``points`` nodes, from 0
        to 1); a position is ``x = cdf^{-1}(u)`` by linear interpolation (a piecewise
        uniform density whose cell masses are the trapezoidal ones).
    kT : float
    """

    grid: np.ndarray
    cdf: np.ndarray
    kT: float

    @classmethod
    def of(cls, split, kT: float, saddles, points: int = 8193) -> WellBoltzmann:
        """The well between ``saddles = (x_l, x_r)`` of ``split`` (its ``G``) at ``kT``."""
        xl, xr = map(float, saddles)
        if not (math.isfinite(kT) and kT > 0):
            raise ParameterError(f"kT = {kT}: the Boltzmann start needs kT > 0")
        if not xl < 0 < xr:
            raise ModelError(f"saddles {saddles}: need x_l < 0 < x_r")
        G = split.numpy_functions()[2]
        grid = np.linspace(xl, xr, int(points))
        e = np.asarray(G(grid), float)
        w = np.exp(-(e - e.min()) / kT)
        c = np.concatenate([[0.0], np.cumsum(0.5 * (w[1:] + w[:-1]) * np.diff(grid))])
        return cls(grid, c / c[-1], float(kT))

    def draw(self, seed: int, first: int, count: int, stream: tuple = ()) -> np.ndarray:
        """``(count, 2)`` starts ``(x, x')`` of trajectories ``first .. first+count-1``, each
        from the first child of ``SeedSequence(seed, spawn_key=(*stream, i))``."""
        out = np.empty((count, 2))
        for j in range(count):
            ss = np.random.SeedSequence(int(seed), spawn_key=(*stream, first + j))
            rng = np.random.default_rng(ss.spawn(1)[0])
            u, z = rng.random(), rng.standard_normal()
            out[j] = float(np.interp(u, self.cdf, self.grid)), math.sqrt(self.kT) * z
        return out


def simulated_transitions(split, D: float, saddles, *, kT: float | None, trajectories: int,
                          t_end: float, dt: float, seed: int = 0, wells=None,
                          workers: int | None = None,
                          settle: float | None = None) -> SimulatedEscape:
    """The rate of transitions to the next wells from ``trajectories`` Langevin runs.

    Parameters
    ----------
    split : kbm.model.conservative.ConservativeSplit
    D : float
        Noise intensity.
    saddles : (x_l, x_r)
        The saddles bounding the well at the origin (the Boltzmann start lives between).
    kT : float or None
        ``D/mu`` for linear damping (start from the well's Boltzmann density); ``None``:
        start at the bottom.
    trajectories : int
    t_end, dt : float
        Longest run and time step.
    seed : int
    wells : (x_wl, x_wr), optional
        The lines; by default the next wells' bottoms
        (:func:`numerics.fokker_planck._model.next_wells`, where the FP sink sits).
    workers : int, optional
    settle : float, optional
        Count the waiting times after this time only (of the trajectories still in the well
        then).  By default ``2 max(1/gamma, gamma/omega_0^2)`` with ``gamma = D/kT`` from
        the Boltzmann start (at most ``t_end/4``), 0 from the bottom.

    Returns
    -------
    SimulatedEscape
        With ``start`` ``"boltzmann"`` or ``"bottom"``, ``settle`` and ``settled``.

    Raises
    ------
    numerics.errors.NumericsError
        No trajectory reached a next well.
    """
    if trajectories < 2:
        raise ParameterError("at least 2 trajectories are needed for a standard error")
    if wells is None:
        from ..fokker_planck._model import next_wells

        wells = next_wells(split.numpy_functions()[0], saddles)
    wl, wr = map(float, wells)
    if not wl < saddles[0] < 0 < saddles[1] < wr:
        raise ModelError(f"the next wells' bottoms {wells} must lie outside the saddles "
                         f"{tuple(saddles)}")
    start = None if kT is None else WellBoltzmann.of(split, kT, saddles)
    from ._passage import first_passages

    times, escaped = first_passages(split, D, (wl, wr), trajectories=trajectories,
                                    t_end=t_end, dt=dt, seed=seed, start=start,
                                    stream=WELLS_STREAM, workers=workers)
    times, escaped = np.asarray(times, float), np.asarray(escaped, bool)
    if settle is None:
        settle = 0.0 if kT is None else _relaxation_time(split, D, kT, t_end)
    alive = times > settle
    try:
        r, se = censored_rate(times[alive] - settle, escaped[alive])
    except NumericsError as exc:
        raise NumericsError(f"{exc} (transitions to the next wells at x = {wl:.6g}, "
                            f"{wr:.6g})") from None
    k = int(np.count_nonzero(escaped))
    return SimulatedEscape(r, se, k, int(trajectories) - k, times, float(t_end), float(dt),
                           int(seed), "bottom" if start is None else "boltzmann",
                           float(settle), int(np.count_nonzero(alive)))


def _relaxation_time(split, D: float, kT: float, t_end: float) -> float:
    """``2 max(1/gamma, gamma/omega_0^2)``, ``gamma = D/kT``, at most ``t_end/4``."""
    gamma = D / kT
    w2 = float(split.numpy_functions()[1](np.array(0.0)))
    return min(2.0 * max(1.0 / gamma, gamma / w2), t_end / 4.0)
