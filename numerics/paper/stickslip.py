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

from numerics.paper.potential import saddle_node
from numerics.paper.sliding import SlideResult

__all__ = ["Slip", "StickSlip", "analyze"]


@dataclass(frozen=True)
class Slip:
    """One slip event."""

    t_start: float
    t_end: float
    wells: int
    peak_force: float
    energy_dissipated: float
    x_start: float
    x_end: float

    def to_json(self) -> dict:
        return {"t_start": self.t_start, "t_end": self.t_end, "wells": self.wells,
                "peak_force": self.peak_force, "energy_dissipated": self.energy_dissipated}


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
        return {"model": self.model, "params": dict(self.params), "window": list(self.window),
                "peak_force": self.peak_force, "mean_force": self.kinetic_friction,
                "slips": [s.to_json() for s in self.slips],
                "gamma_plus": self.gamma_plus, "gamma_minus": self.gamma_minus,
                "gamma": self.gamma, "energy_residual": self.energy_residual,
                "delta_W": self.delta_W, "criterion": self.criterion}


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
    t, xd, F = res.t, res.xdot, res.force
    active = np.abs(xd) > vth
    slips: list[Slip] = []
    idx = np.nonzero(active)[0]
    groups: list[list[int]] = []
    for i in idx:
        if groups and t[i] - t[groups[-1][-1]] < Tn:
            groups[-1].append(i)
        else:
            groups.append([i])
    prev_end = 0
    for g in groups:
        i0, i1 = g[0], g[-1]
        ts, te = float(t[i0]), float(t[i1])
        seg = F[prev_end:i0 + 1]
        peak = float(np.max(seg)) if seg.size else float(F[i0])
        prev_end = i1
        if not (t0 <= ts <= t1):
            continue
        xs_, xe_ = float(res.x[i0]), float(res.x[i1])
        slips.append(Slip(t_start=ts, t_end=te,
                          wells=int(round(xe_ / lam) - round(xs_ / lam)),
                          peak_force=peak,
                          energy_dissipated=res.gamma_at(te) - res.gamma_at(ts),
                          x_start=xs_, x_end=xe_))
    mask = res.window(t0, t1)
    Fw = F[mask]
    y0, y1 = res.sol.sol(t0), res.sol.sol(t1)
    gp, gm = float(y1[2] - y0[2]), float(y1[3] - y0[3])
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
