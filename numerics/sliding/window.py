"""A run of the driven slider kept after its transient, and the friction measures of a
window of it (:mod:`numerics.sliding.friction`, criteria 2-4 and the measures): the stuck
intervals, the window's mean force, dissipation per distance and power balance, the
steadiness test of its two halves, and the stick-slip and sliding points.

References
----------
M. D'Acunto, eqs. (3), (4), (10)-(12) (the power balance ``v Delta J = Delta Gamma +
Delta E``).
"""

from __future__ import annotations

import math

import numpy as np

from numerics.sliding.driven import DrivenSystem
from numerics.sliding.friction_records import FrictionPoint, FrictionSettings


#: the sliders invariant under ``x -> x + lam, tau -> tau + lam/v`` (the paper's SEDF is not)
_TRANSLATION_INVARIANT = ("sedf_comoving", "cdc")


class _Run:
    """The samples kept after the transient (rows ``(x, x_dot, tau, G_+, G_-, W, J)``), in a
    buffer that doubles when full.

    With ``recentre`` (a translation-invariant slider) each block is integrated from the
    last state moved back by whole wells, ``x - n lam, tau - n lam/v``, and the samples moved
    forward again: the integrator's error, relative to ``|x|`` and ``tau``, then does not
    grow with the distance slid (criterion 6 of :mod:`numerics.sliding.friction`)."""

    def __init__(self, system: DrivenSystem, per_well: int, y0: np.ndarray, steps: int,
                 t_fast: float, recentre: bool = False):
        self.system, self.per_well, self.steps, self.t_fast = system, per_well, steps, t_fast
        self.failure = ""
        self._buf = np.empty((64 * per_well + 1, len(y0)))
        self._buf[0] = y0
        self._n = 1
        self.recentre = recentre and system.model in _TRANSLATION_INVARIANT
        self._own = (np.array(y0, dtype=float), 0)  # the integrator's last state, its shift

    @property
    def y(self) -> np.ndarray:
        return self._buf[:self._n]

    def discard(self) -> None:
        """Drop every sample but the last (after the transient)."""
        self._buf[0] = self._buf[self._n - 1]
        self._n = 1

    def extend(self, wells: int) -> None:
        lam, v = self.system.lam, self.system.v
        duration = wells * lam / v
        start, shift = self._buf[self._n - 1], 0
        if self.recentre:
            own, shift = self._own
            start = own.copy()
            n = round(start[0] / lam)
            start[0] -= n * lam
            start[2] -= n * lam / v
            shift += n
        blk = self.system.run(start, duration, wells * self.per_well,
                              max_steps=_step_limit(duration, self.t_fast), partial=True)
        self.failure = blk.message if blk.status else ""
        new = blk.y[1:][np.isfinite(blk.y[1:, 0])]
        if self.recentre and len(new):
            self._own = (new[-1].copy(), shift)
            new = new.copy()
            new[:, 0] += shift * lam
            new[:, 2] += shift * lam / v
        if self._n + len(new) > len(self._buf):
            grown = np.empty((2 * (self._n + len(new)), self._buf.shape[1]))
            grown[:self._n] = self._buf[:self._n]
            self._buf = grown
        self._buf[self._n:self._n + len(new)] = new
        self._n += len(new)
        self.steps += blk.steps


def _stuck_intervals(mask: np.ndarray, min_len: int) -> list[tuple[int, int]]:
    """``(start, end)`` sample indices of the runs of ``mask`` at least ``min_len`` long."""
    d = np.diff(np.concatenate([[0], mask.astype(np.int8), [0]]))
    starts, ends = np.nonzero(d == 1)[0], np.nonzero(d == -1)[0] - 1
    return [(int(a), int(b)) for a, b in zip(starts, ends) if b - a + 1 >= min_len]


def _stick_phases(run: _Run, v_stick: float, min_len: int) -> list[tuple[int, int]]:
    """The stick phases of the run: ``(start, end)`` sample indices of the intervals with
    ``|x_dot| < v_stick`` for at least ``min_len`` samples, two of them joined when the
    motion between them ends in the well it started from (``round(x/lam)`` the same at
    both ends).  Such a motion is an oscillation in the well, not a slip: the in-well
    oscillation of the stage-attached SEDF, self-excited while the stage passes within
    ``1/sqrt(beta)``, or one whose amplitude hovers at ``v_stick``, crosses no well; counted
    as slips they would enter the mean static force and the wells per slip (criterion 2)."""
    stuck = _stuck_intervals(np.abs(run.y[:, 1]) < v_stick, min_len)
    well = np.round(run.y[:, 0] / run.system.lam)
    phases: list[tuple[int, int]] = []
    for a, e in stuck:
        if phases and well[phases[-1][1]] == well[a]:
            phases[-1] = (phases[-1][0], e)
        else:
            phases.append((a, e))
    return phases


def _slip_pattern(run: _Run, stuck: list[tuple[int, int]]) -> list[tuple[int, float]]:
    """The slips of the run, one per stick phase but the last: the wells each crosses (to
    the next phase) and the spring force at its onset (the phase's end)."""
    y, lam = run.y, run.system.lam
    ends = [e for _, e in stuck[:-1]]
    F = _force(run, ends)
    return [(round(y[nxt, 0] / lam) - round(y[e, 0] / lam), float(f))
            for e, (nxt, _), f in zip(ends, stuck[1:], F)]


def _settling(pattern: list[tuple[int, float]], force_tol: float, max_period: int = 8,
              cycles: int = 3) -> int | None:
    """How many of the first slips of ``pattern`` (wells crossed, onset force) come before
    the motion repeats: the smallest period ``p <= max_period`` slips for which the slips
    from some index on each match the slip ``p`` later (the same wells, onset forces within
    ``force_tol``) over at least ``cycles`` periods reaching the last slip; that index, or
    ``None`` when no period repeats (an irregular stick-slip, or too few slips to tell:
    nothing dropped, and :func:`numerics.sliding.friction.friction_point` checks the point
    at a tighter tolerance)."""
    n = len(pattern)

    def same(a: tuple[int, float], b: tuple[int, float]) -> bool:
        return a[0] == b[0] and abs(a[1] - b[1]) <= force_tol

    for p in range(1, max_period + 1):
        i = n - 1
        while i - p >= 0 and same(pattern[i], pattern[i - p]):
            i -= 1
        start = max(0, i - p + 1)
        if n - start >= max(cycles * p, p + cycles):
            return start
    return None


def _force(run: _Run, at=slice(None)) -> np.ndarray:
    """The spring force ``Omega^2 (v t - x)`` at the samples ``at`` (all by default)."""
    Om2 = run.system.omega**2
    return Om2 * (run.system.v * run.y[at, 2] - run.y[at, 0])


def _window_means(run: _Run, i0: int, i1: int) -> dict:
    """Mean force, dissipation per distance, residuals over samples ``i0..i1``."""
    sys_, y = run.system, run.y
    T = y[i1, 2] - y[i0, 2]
    dJ = y[i1, 6] - y[i0, 6]
    dG = float(sys_.gamma(y[i1])[0] - sys_.gamma(y[i0])[0])
    dE = float(sys_.energy(y[i1])[0] - sys_.energy(y[i0])[0])
    F = dJ / T
    D = dG / (sys_.v * T)
    flow = _flow(run, i0, i1) / (sys_.v * T)
    F_s = _force(run)[i0:i1 + 1]
    scale = max(abs(F), flow)
    return dict(mean_force=float(F), dissipation_per_distance=float(D),
                energy_residual=float(abs(F - D) / scale) if scale else math.inf,
                audit=float(abs(sys_.v * dJ - dG - dE) / max(abs(dG), 1e-300)),
                force_fluctuation=float(np.std(F_s)), peak_force=float(np.max(F_s)),
                window=(float(y[i0, 2]), float(y[i1, 2])))


def _flow(run: _Run, i0: int, i1: int) -> float:
    """The energy that flows through the non-conservative forces over samples ``i0..i1``,
    ``gain G_+ + G_-`` (the dissipation of the CDC; for the SEDF the damping and the
    self-excitation both count, though their difference, the net dissipation, may be 0)."""
    y, g = run.y, run.system.gain_factor
    return float(abs(g * (y[i1, 3] - y[i0, 3])) + abs(y[i1, 4] - y[i0, 4]))


def _steady(run: _Run, i0: int, im: int, i1: int, s: FrictionSettings) -> tuple[bool, tuple]:
    """Whether the halves' mean forces agree and the stored energy returns (criterion 4),
    both relative to the larger of the mean force and the energy flow per distance."""
    f1 = _window_means(run, i0, im)["mean_force"]
    f2 = _window_means(run, im, i1)["mean_force"]
    sys_, y = run.system, run.y
    T = y[i1, 2] - y[i0, 2]
    flow = _flow(run, i0, i1)
    scale = max(abs(f1), abs(f2), flow / (sys_.v * T), 1e-300)
    dE = abs(float(sys_.energy(y[i1])[0] - sys_.energy(y[i0])[0]))
    work = max(abs(sys_.v * (y[i1, 6] - y[i0, 6])), flow)
    return bool(abs(f1 - f2) <= s.steady_tol * scale and dE <= s.energy_tol * work), (f1, f2)


def _step_limit(duration: float, t_fast: float) -> int:
    """At most 2000 steps per fast period (a run that needs more is stiff: a runaway)."""
    return int(2000 * duration / t_fast) + 100_000


def _stick_slip(run: _Run, base: dict, stuck, onsets: list[int], dt: float,
                s: FrictionSettings) -> FrictionPoint:
    i0, i1 = onsets[0], onsets[-1]
    lam = run.system.lam
    F = _force(run)
    by_end = {e: a for a, e in stuck}
    starts = sorted(a for a, _ in stuck)
    peaks, wells = [], []
    for j, e in enumerate(onsets[:-1]):
        a = by_end[e]
        peaks.append(float(np.max(F[a:e + 1])))
        nxt = next(st for st in starts if st > e)
        wells.append(round(run.y[nxt, 0] / lam) - round(run.y[e, 0] / lam))
    stuck_time = sum(max(0, min(e, i1) - max(a, i0)) for a, e in stuck) * dt
    m = _window_means(run, i0, i1)
    steady, halves = _steady(run, i0, onsets[len(onsets) // 2], i1, s)
    return FrictionPoint(**base, regime="stick-slip", steady=steady, halves=halves,
                         static_force=float(np.mean(peaks)),
                         stuck_fraction=float(stuck_time / (m["window"][1] - m["window"][0])),
                         wells_per_slip=float(np.mean(wells)), slips=len(onsets) - 1,
                         steps=run.steps, **m)


def _sliding(run: _Run, base: dict, wells: int, extra: int, s: FrictionSettings) -> FrictionPoint:
    pw = run.per_well
    i0 = len(run.y) - 1 - (wells + extra) * pw
    ends = np.arange(i0 + wells * pw, i0 + (wells + extra) * pw + 1, pw)
    E = run.system.energy(run.y[ends])
    i1 = int(ends[np.argmin(np.abs(E - run.system.energy(run.y[i0])[0]))])
    m = _window_means(run, i0, i1)
    half = i0 + ((i1 - i0) // pw // 2) * pw
    steady, halves = _steady(run, i0, half, i1, s)
    reverses = bool(np.min(run.y[i0:i1 + 1, 1]) < 0)
    regime = ("smooth sliding" if not reverses else
              "self-oscillating sliding" if run.system.has_source else "oscillating sliding")
    return FrictionPoint(**base, regime=regime, steady=steady, halves=halves, stuck_fraction=0.0,
                         steps=run.steps, **m)
