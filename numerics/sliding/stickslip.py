"""Stick-slip analysis of a driven slider (:func:`numerics.slide`).

Slip criterion (documented, adjustable): the slider *slips* while ``|x'|`` exceeds
``v_threshold`` (default ``max(5 v, 0.02 Omega lambda)``: five times the stage
velocity, and at least 2% of the natural velocity scale); runs of slipping closer
together than one natural period ``2 pi/Omega`` belong to one slip (the ring-down
after a jump is part of it).  For each slip: start and end times, the number of
wells crossed (the change of the nearest minimum ``round(x/lambda)``
of the periodic potential), the peak spring force in the
stick phase before it (the static friction of that slip), and the energy
dissipated during it, ``Gamma(t_end) - Gamma(t_start)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from kbm.errors import ParameterError
from kbm.output.strict_json import Rendered, json_fields

from numerics.sliding.potential import saddle_node
from numerics.sliding.reference import SlideResult

__all__ = ["Slip", "StickSlip", "analyze"]

#: points per solver step at which |x'| is compared with the threshold (then root finding)
_SUBDIVISIONS = 8


def _fine_grid(sol) -> np.ndarray:
    """The solver's step points, each step cut into :data:`_SUBDIVISIONS` pieces."""
    ts = np.asarray(sol.t, dtype=float)
    frac = np.arange(_SUBDIVISIONS) / _SUBDIVISIONS
    fine = (ts[:-1, None] + np.diff(ts)[:, None] * frac[None, :]).ravel()
    return np.append(fine, ts[-1])


def _fine_samples(sol, tt: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``x`` and ``x'`` at the times ``tt`` from the dense output."""
    xs, vs = np.empty(len(tt)), np.empty(len(tt))
    for i in range(0, len(tt), 200_000):  # bounded memory on long runs
        y = sol.sol(tt[i:i + 200_000])
        xs[i:i + 200_000], vs[i:i + 200_000] = y[0], y[1]
    return xs, vs


def _slip_intervals(res: SlideResult, vth: float, Tn: float):
    """``(t_start, t_end)`` of each slip (``|x'| = vth`` located on the dense output), and
    the fine grid with ``x`` on it.

    ``|x'| - vth`` is evaluated at :data:`_SUBDIVISIONS` points per solver step (the steps
    resolve the motion, so no excursion above the threshold hides between them), runs
    closer than ``Tn`` are merged, and the first and last crossings of each run are
    found by Brent's method on the dense output (to ~1e-12 in time).  A slip still
    going at the end of the run ends at the final time.
    """
    from scipy.optimize import brentq

    sol = res.sol
    tt = _fine_grid(sol)
    xs, vs = _fine_samples(sol, tt)
    g = np.abs(vs) - vth

    def excess(tau):
        return abs(float(sol.sol(tau)[1])) - vth

    def root(a, b):
        return float(brentq(excess, a, b, xtol=1e-13, rtol=4 * np.finfo(float).eps))

    idx = np.nonzero(g > 0)[0]
    groups: list[list[int]] = []
    for i in idx:
        if groups and tt[i] - tt[groups[-1][1]] < Tn:
            groups[-1][1] = i
        else:
            groups.append([i, i])
    out = []
    for i0, i1 in groups:
        ts = float(tt[0]) if i0 == 0 else root(tt[i0 - 1], tt[i0])
        te = float(tt[-1]) if i1 == len(tt) - 1 else root(tt[i1], tt[i1 + 1])
        out.append((ts, te))
    return out, tt, xs


@dataclass(frozen=True)
class Slip(Rendered):
    """One slip event (``complete`` is false for a slip still going at the end of the run,
    whose ``t_end`` is the final time)."""

    t_start: float
    t_end: float
    wells: int
    peak_force: float
    energy_dissipated: float
    x_start: float
    x_end: float
    complete: bool = True

    layout = ("t_start", "t_end", "wells", "peak_force", "energy_dissipated", "complete")


@dataclass(frozen=True, eq=False)
class StickSlip:
    """Friction measures of one run over a window ``[t0, t1]``.

    Attributes
    ----------
    slips
        The slip events that start in the window.
    static_friction
        Spring force at the onset of each slip (the peak of the stick phase).
    kinetic_friction
        Time average of the spring force over the window.
    peak_force
        Largest spring force in the window.
    gamma_plus, gamma_minus, gamma
        Paper eq. (11) over the window.
    energy_residual
        The run's energy audit residual (integration error).
    delta_W
        Quasi-static slip energy of the potential (one well), ``None`` if there is
        no stick-slip (``Delta k <= Omega^2``).
    criterion
        The slip criterion used, in words.
    """

    model: str
    params: dict
    window: tuple[float, float]
    slips: tuple[Slip, ...]
    static_friction: tuple[float, ...]
    kinetic_friction: float
    peak_force: float
    gamma_plus: float
    gamma_minus: float
    gamma: float
    energy_residual: float
    delta_W: float | None
    criterion: str

    def to_json(self) -> dict:
        """The keys of ``kbm slide --json``."""
        return {**json_fields(self, "model", "params", "window", "peak_force"),
                "mean_force": self.kinetic_friction,
                **json_fields(self, "slips", "gamma_plus", "gamma_minus", "gamma",
                              "energy_residual", "delta_W", "criterion")}


def analyze(res: SlideResult, *, window: tuple[float, float] | None = None,
            v_threshold: float | None = None) -> StickSlip:
    """Slips, static and kinetic friction, and the dissipation of a driven run.

    Parameters
    ----------
    res
        The output of :func:`numerics.slide`.
    window
        ``(t0, t1)`` for the averages (default: the whole run).
    v_threshold
        Velocity above which the slider counts as slipping (default
        ``max(5 v, 0.02 Omega lambda)``).
    """
    p = res.params
    v, Om, lam = p.get("v", 0.0), p["Omega"], p["lam"]
    t0, t1 = window if window is not None else (float(res.t[0]), float(res.t[-1]))
    if not t1 > t0:
        raise ParameterError(f"the window must have t1 > t0, got {window}")
    vth = v_threshold if v_threshold is not None else max(5 * v, 0.02 * Om * lam)
    if vth <= 0:
        raise ParameterError(f"v_threshold must be > 0, got {vth}")
    Tn = 2 * math.pi / Om
    slips: list[Slip] = []
    prev_end = 0.0
    intervals, t, xf = _slip_intervals(res, vth, Tn)
    F = Om**2 * (v * t - xf)
    for ts, te in intervals:
        stick = (t >= prev_end) & (t <= ts)
        f_start = float(Om**2 * (v * ts - res.sol.sol(ts)[0]))
        peak = max(float(np.max(F[stick])) if stick.any() else f_start, f_start)
        prev_end = te
        if not (t0 <= ts <= t1):
            continue
        xs_, xe_ = float(res.sol.sol(ts)[0]), float(res.sol.sol(te)[0])
        slips.append(Slip(t_start=ts, t_end=te,
                          wells=int(round(xe_ / lam) - round(xs_ / lam)),
                          peak_force=peak,
                          energy_dissipated=res.gamma_at(te) - res.gamma_at(ts),
                          x_start=xs_, x_end=xe_, complete=te < float(t[-1])))
    mask = res.window(t0, t1)
    Fw = res.force[mask]
    y0, y1 = res.sol.sol(t0), res.sol.sol(t1)
    gp, gm = float(y1[3] - y0[3]), float(y1[4] - y0[4])
    gamma = res.gain_factor * gp - gm
    sn = saddle_node(p["Delta"], lam, Om, n_wells=1)
    kinetic = float(np.trapezoid(Fw, res.t[mask]) / (res.t[mask][-1] - res.t[mask][0])) \
        if mask.sum() > 1 else float("nan")
    return StickSlip(
        model=res.model, params=dict(p), window=(t0, t1), slips=tuple(slips),
        static_friction=tuple(s.peak_force for s in slips), kinetic_friction=kinetic,
        peak_force=float(np.max(Fw)), gamma_plus=gp,
        gamma_minus=gm, gamma=float(gamma), energy_residual=res.energy_residual,
        delta_W=None if sn is None else sn.delta_W[0],
        criterion=(f"slipping while |x'| > {vth:.4g}; runs closer than one natural period "
                   f"2 pi/Omega = {Tn:.4g} form one slip"))
