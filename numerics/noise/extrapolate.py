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

The two-level estimator (:func:`two_level_moments`) writes ``R = E_h + (4/3)(E_{h/2} -
E_h)`` and takes the two terms from independent ensembles: ``E_h`` from plain BAOAB (one
force evaluation per step), the correction from a smaller coupled ensemble, its size set
by the measured variance ratio (Giles, Oper. Res. 56 (2008) 607: trajectories in
proportion to ``sqrt(V_l/C_l)``).  Its cost per unit of statistical error is that of BAOAB
times ``(1 + sqrt(V_1 C_1/(V_0 C_0)))^2``, not three times it.

The correction is antithetic by default (Giles & Szpruch, Ann. Appl. Probab. 24 (2014)
1585; kernel ``step_antithetic_stats``): the coarse step takes ``g_1 + g_2`` and two fine
runs take ``(g_1, g_2)`` and ``(g_2, g_1)``; the mean of the fine runs minus the coarse one
has the same expectation ``E_{h/2} - E_h`` (both fine runs are BAOAB at ``h/2``), but the
part of the difference linear in ``g_1 - g_2`` (the noise inside a coarse step that the
coarse run cannot see) cancels.  On the quartic benchmark at ``h = 0.32`` the variance of
the difference falls from 0.027 to 0.0011 of ``E_h``'s, at five force evaluations per coarse
step instead of three, so that the cost factor falls from about 2 to about 1.2.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from kbm.errors import ParameterError

from ..errors import NumericsError
from .langevin import LangevinSystem, steps_of
from .seeds import trajectory_states

__all__ = ["RichardsonMoment", "richardson_moments", "TwoLevelMoment", "two_level_moments",
           "ORDER", "CORRECTION_STREAM", "COUPLINGS"]

#: the spawn-key prefix of the correction level's trajectories (the main ensemble uses none,
#: the step pilot ``2**31 - 1``)
CORRECTION_STREAM = 2**31 - 2

#: the correction level's couplings and their force evaluations per coarse step: the
#: synchronous pair (``h`` and ``h/2`` on one path) and the antithetic triple (``h`` and two
#: ``h/2`` runs with the fine increments swapped; the default)
COUPLINGS = {"synchronous": 3, "antithetic": 5}

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


def _run(system: LangevinSystem, kernel: str, h: float, n_burn: int, n_run: int,
         states) -> np.ndarray:
    """The per-trajectory sums of the compiled kernel ``kernel`` (``step_pair_stats``,
    ``step_antithetic_stats``, ``step_gauss_stats``) from rest; a diverged trajectory
    raises :class:`numerics.errors.NumericsError`."""
    rows = getattr(system.kernels, kernel)(system._p(), system.sigma,
                                           np.zeros((len(states), 2)), 0.0, float(h), n_burn,
                                           n_run, states, system.omega0)
    if not np.all(np.isfinite(rows)):
        raise NumericsError(f"a trajectory diverged at h = {h:g}: take a smaller step")
    return rows


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
    rows = _run(system, "step_pair_stats", h, n_burn, n_run,
                trajectory_states(seed, 0, trajectories))
    return {"x2": _moment(rows[:, 0], rows[:, 2]), "a2": _moment(rows[:, 1], rows[:, 3])}


@dataclass(frozen=True)
class TwoLevelMoment:
    """One stationary moment by the two-level Richardson estimator.

    Attributes
    ----------
    coarse, coarse_stderr : float
        ``E_h`` of the plain ensemble (level 0) and its standard error.
    correction, correction_stderr : float
        ``(4/3)(E_{h/2} - E_h)`` of the coupled ensemble (level 1) and its standard error.
    value, stderr : float
        ``coarse + correction`` (weak order 4) and ``sqrt(coarse_stderr^2 +
        correction_stderr^2)`` (the levels are independent).
    variance_ratio : float
        ``V_1/V_0``: the per-trajectory variance of the correction over that of ``E_h``.
    """

    coarse: float
    coarse_stderr: float
    correction: float
    correction_stderr: float
    value: float
    stderr: float
    variance_ratio: float


def _pair_rows(system: LangevinSystem, h: float, n_burn: int, n_run: int, seed: int,
               first: int, count: int) -> np.ndarray:
    """The per-trajectory corrections ``(4/3)(E_{h/2} - E_h)`` (columns ``x^2``, ``a^2``) of
    trajectories ``first .. first+count-1`` of the correction stream."""
    rows = _run(system, "step_pair_stats", h, n_burn, n_run,
                trajectory_states(seed, first, count, stream=(CORRECTION_STREAM,)))
    return 4.0 / 3.0 * (rows[:, 2:4] - rows[:, 0:2])


def _antithetic_rows(system: LangevinSystem, h: float, n_burn: int, n_run: int, seed: int,
                     first: int, count: int) -> np.ndarray:
    """The per-trajectory antithetic corrections ``(4/3)((E_{h/2} + E'_{h/2})/2 - E_h)``
    (columns ``x^2``, ``a^2``; ``E'`` the run with each coarse step's two fine increments
    swapped) of trajectories ``first .. first+count-1`` of the correction stream."""
    rows = _run(system, "step_antithetic_stats", h, n_burn, n_run,
                trajectory_states(seed, first, count, stream=(CORRECTION_STREAM,)))
    return 4.0 / 3.0 * (0.5 * (rows[:, 2:4] + rows[:, 4:6]) - rows[:, 0:2])


def two_level_moments(system: LangevinSystem, h: float, *, trajectories: int, t_end: float,
                      burn_in: float, seed: int = 0,
                      coarse: dict[str, tuple[float, float]] | None = None,
                      pilot: int | None = None,
                      coupling: str = "antithetic") -> tuple[dict[str, TwoLevelMoment], dict]:
    """``<x^2>`` and ``<a^2>`` to weak order 4 at the cost of little more than BAOAB at ``h``:
    ``E_h`` from a plain ensemble plus ``(4/3)(E_{h/2} - E_h)`` from a smaller coupled one.

    Level 0 is ``trajectories`` BAOAB trajectories at ``h`` with Gaussian increments (the
    root seed's streams ``(i,)``; kernel ``step_gauss_stats``), or the values ``coarse`` of
    such an ensemble run elsewhere.  Both levels use Gaussian increments: the
    three-point increments of the toolkit's main ensembles give BAOAB another ``h^2``
    coefficient, so ``E_h`` of a three-point ensemble plus the Gaussian pair's correction
    would keep an ``O(h^2)`` bias.  Level 1 runs the antithetic triple (``coupling =
    "antithetic"``, five force evaluations per coarse step) or the synchronous pair
    (``"synchronous"``, :func:`richardson_moments`' kernel, three) on the streams
    ``(CORRECTION_STREAM, i)``: first ``pilot`` trajectories (default ``max(8,
    ceil(trajectories/32))`` antithetic, ``max(8, ceil(trajectories/16))`` synchronous),
    which measure ``V_1``; then, by Giles' allocation at the cost ``C_1`` per step
    (:data:`COUPLINGS`), ``m_1 = ceil(trajectories sqrt(V_1 C_0/(V_0 C_1)))`` in all (the
    larger over the two moments, at least the pilot, at most ``trajectories``).  Every
    trajectory's numbers depend on ``(seed, i)`` alone, so the result does not depend on how
    it is split.

    Parameters
    ----------
    system : LangevinSystem
        BAOAB (``scheme="baoab"``).
    h : float
        The step of level 0 (level 1 runs ``h`` and ``h/2``).
    trajectories : int
        Level 0's trajectories (at least 2).
    t_end, burn_in : float
        The averaging time and burn-in of every trajectory, whole numbers of ``h``.
    seed : int
        The root seed.
    coarse : dict, optional
        ``{"x2": (mean, stderr), "a2": (mean, stderr)}`` of level 0 when it was run
        already (Gaussian increments, the same ``h``, ``t_end``, ``burn_in`` and
        ``trajectories``).
    pilot : int, optional
        The trajectories of level 1 that measure its variance (at least 2).
    coupling : {"antithetic", "synchronous"}
        The correction level's coupling (:data:`COUPLINGS`).

    Returns
    -------
    (dict, dict)
        ``{"x2": TwoLevelMoment, "a2": TwoLevelMoment}`` and the levels' sizes
        ``{"coarse": trajectories, "correction": m_1, "pilot": pilot, "steps": ...,
        "coupling": coupling}`` (``steps``: the force evaluations of both levels, burn-in
        included).

    Raises
    ------
    kbm.errors.ParameterError
        Kloeden-Platen, fewer than 2 trajectories (or pilot trajectories), times that are
        not whole numbers of steps, an unknown coupling.
    numerics.errors.NumericsError
        When a trajectory diverges.
    """
    if coupling not in COUPLINGS:
        raise ParameterError(f"coupling = {coupling!r}: choose one of "
                             f"{', '.join(COUPLINGS)}")
    if system.scheme != "baoab":
        raise ParameterError("the two-level Richardson estimator needs BAOAB's even "
                             "expansion: build the system with scheme 'baoab'")
    if not isinstance(trajectories, int) or trajectories < 2:
        raise ParameterError(f"trajectories = {trajectories}: at least 2 are needed for a "
                             "standard error")
    cost = COUPLINGS[coupling]
    rows_of = _antithetic_rows if coupling == "antithetic" else _pair_rows
    share = 32 if coupling == "antithetic" else 16
    m_p = max(8, math.ceil(trajectories / share)) if pilot is None else pilot
    if not isinstance(m_p, int) or m_p < 2:
        raise ParameterError(f"pilot = {pilot}: at least 2 trajectories are needed for the "
                             "correction's variance")
    n_run = steps_of(t_end, h)
    n_burn = 0 if burn_in == 0 else steps_of(burn_in, h)
    keys = ("x2", "a2")
    if coarse is None:
        sums = _run(system, "step_gauss_stats", h, n_burn, n_run,
                    trajectory_states(seed, 0, trajectories))
        coarse = {k: (float(sums[:, c].mean()),
                      float(sums[:, c].std(ddof=1) / math.sqrt(trajectories)))
                  for c, k in enumerate(keys)}
    var0 = {k: coarse[k][1] ** 2 * trajectories for k in keys}
    corr = rows_of(system, h, n_burn, n_run, seed, 0, m_p)
    var1 = {k: float(corr[:, c].var(ddof=1)) for c, k in enumerate(keys)}
    want = max(math.ceil(trajectories * math.sqrt(var1[k] / (cost * var0[k])))
               if var0[k] > 0 else trajectories for k in keys)
    m_1 = max(m_p, min(trajectories, want))
    if m_1 > m_p:
        corr = np.vstack([corr, rows_of(system, h, n_burn, n_run, seed, m_p, m_1 - m_p)])
    out = {}
    for c, k in enumerate(keys):
        mean, se = float(corr[:, c].mean()), float(corr[:, c].std(ddof=1) / math.sqrt(m_1))
        out[k] = TwoLevelMoment(coarse[k][0], coarse[k][1], mean, se, coarse[k][0] + mean,
                                math.hypot(coarse[k][1], se),
                                float(corr[:, c].var(ddof=1)) / var0[k] if var0[k] > 0
                                else math.inf)
    sizes = {"coarse": trajectories, "correction": m_1, "pilot": m_p,
             "steps": (trajectories + cost * m_1) * (n_burn + n_run), "coupling": coupling}
    return out, sizes
