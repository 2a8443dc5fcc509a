"""The stage-attached SEDF's stick-slip cycle in extended precision, where double precision
cannot resolve it (criterion 6 of :mod:`numerics.sliding.friction`).

While the stage passes the stuck slider of ``sedf_comoving``,

``x'' = -Omega^2 s - Delta sin(k x) + mu (1 - beta s^2) x'``,  ``s = x - v t``,  ``k = 2 pi/lam``,

its self-excitation multiplies any in-well error by ``e^G``, ``G = 2 mu/(3 v sqrt(beta))``:
where the rounding of double precision times ``e^G`` is a sizeable part of a well, the
compiled runs' slips are irregular at every tolerance.  Here the motion is integrated in
numpy's long double (on x86-64 the 80-bit format, rounding ``2^-63 = 1.1e-19``) by a
Taylor-series method of order :data:`ORDER` whose coefficients follow from the equations by
recursion: those of ``s^2``, ``(s^2) x'`` and, through ``(sin k x)' = k cos(k x) x'`` and
``(cos k x)' = -k sin(k x) x'``, of ``sin k x`` and ``cos k x`` are Cauchy products of
lower ones (Jorba and Zou).  The state is ``(x, x', s)`` with ``x`` moved back by whole
wells after each step (``s`` and the equations do not change), and the integrals of the
friction measures (the rows of :class:`numerics.sliding.window._Run`: ``G_+' = mu s^2
x'^2``, ``G_-' = mu x'^2``, ``W' = F x'``, ``J' = F``, ``F = -Omega^2 s``) are integrated
with it.  The step keeps the last two terms of the series below the rounding (relative to
``lam`` and to ``lam`` times the well frequency) and ``h`` at most :data:`MAX_PHASE` over
the well frequency.

The stuck slider crosses the *section* ``s = s_c`` (``s`` falling, ``|x'| < v_stick``)
once per stick, ``s_c`` midway between the end of the self-excited zone ``-1/sqrt(beta)``
and the saddle node's ``-Delta sqrt(1 - 1/eta^2)/Omega^2``.  The run starts in the same
stick halfway between ``-1/sqrt(beta)`` and ``s_c``, from the quasi-static state
``Delta sin(k x) = -Omega^2 s`` with its slow velocity ``v Omega^2/K`` (``K = Omega^2 +
Delta k cos k x``) and its damping's lag ``-mu (beta s^2 - 1) x'/K``: the stick damps the
rest (``O(v^2)``) before the section, and any disturbance of a cycle by about ``e^-G`` over
the rest of its stick and the next landing (the return map contracts).  :data:`CYCLES`
consecutive cycles from the first crossing, each one slip, are the window; they repeat
when they cross the same wells, their mean forces agree within ``steady_tol`` (each cycle
a half of criterion 4) and the energy returns.  A repeating cycle's time is ``n lam/v``
for ``n`` wells (``s`` returns).

References
----------
A. Jorba and M. Zou, "A software package for the numerical integration of ODEs by means of
high-order Taylor methods", *Experimental Mathematics* 14 (2005) 99-117; M. D'Acunto, eq. (3)
(the SEDF, here stage-attached).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from numerics.sliding.driven import DrivenSystem
from numerics.sliding.friction_records import FrictionPoint, FrictionSettings
from numerics.sliding.window import _stick_phases

__all__ = ["ORDER", "ROUNDING", "ROUNDING_LD", "UNRESOLVED", "CYCLES", "MAX_STEPS", "Cycles",
           "stick_slip_cycles", "extended_point", "beyond_double", "section", "gain"]

LD = np.longdouble
#: the Taylor series' order
ORDER = 28
#: double precision's rounding, relative (the least error of any run of the compiled slider)
ROUNDING = 2.0**-52
#: the stage-attached SEDF's rounding, amplified by ``e^G`` each time the stage passes the
#: stuck slider, above this many ``lam``: irregular slips at both tolerances may be rounding
#: error (criterion 6), and the cycle is measured in long double if its rounding is below it
UNRESOLVED = 1e-3
#: long double's rounding, relative (its machine epsilon; 2^-63 on x86-64, as double's 2^-52)
ROUNDING_LD = float(np.finfo(LD).eps)
#: the largest step times the well frequency ``sqrt(Omega^2 + Delta k)`` (where the in-well
#: oscillation is small enough for such a step): rounding in a mode of that frequency then
#: grows by at most ``MAX_PHASE^(ORDER+1)/(ORDER+1)! = 4e-9`` of itself per step
MAX_PHASE = 6.0
#: the consecutive cycles of the window
CYCLES = 2
#: the most Taylor steps per point (about 0.27 ms each: the cost stays a few seconds)
MAX_STEPS = 16_000
_PI = LD("3.14159265358979323846264338327950288")
_POWERS = np.arange(ORDER + 1).astype(LD)
_INV = np.array([LD(1) / LD(n + 1) for n in range(ORDER)], dtype=LD)


@dataclass(frozen=True, eq=False)
class Cycles:
    """The stick-slip cycles from section to section.

    Attributes
    ----------
    sections
        Per section crossing ``(t, x, x', G_+, G_-, W, J)`` (long double; ``x`` with the
        wells moved back added again).
    rows
        Samples ``(x, x', tau, G_+, G_-, W, J)`` at the multiples of ``dt`` from the first
        section to the last (``tau`` the time, ``x - v tau = s``).
    steps
        Taylor steps.
    """

    sections: np.ndarray
    rows: np.ndarray
    steps: int

    def wells(self, lam: float) -> list[int]:
        """The wells crossed by each cycle."""
        return [int(round(float(d))) for d in np.diff(self.sections[:, 1]) / LD(lam)]


class _Taylor:
    """The recursive Taylor coefficients of ``sedf_comoving`` in long double."""

    def __init__(self, system: DrivenSystem):
        p = system.params
        self.mu, self.beta, self.D = LD(p["mu"]), LD(p["beta"]), LD(p["Delta"])
        self.om2, self.v, self.lam = LD(p["Omega"]) ** 2, LD(p["v"]), LD(p["lam"])
        self.k = 2 * _PI / self.lam
        self.omega = math.sqrt(p["Omega"] ** 2 + p["Delta"] * 2 * math.pi / p["lam"])

    def series(self, x0: LD, u0: LD, s0: LD) -> np.ndarray:
        """Rows ``x, x', s, G_+, G_-, W, J`` of Taylor coefficients at ``(x0, x'0, s0)``
        (the integrals from 0)."""
        M = np.zeros((7, ORDER + 1), LD)
        x, u, s = M[0], M[1], M[2]
        A = np.zeros((3, ORDER + 1), LD)  # s^2, cos k x, sin k x: each times x' below
        q, C, S = A[0], A[1], A[2]
        x[0], u[0], s[0] = x0, u0, s0
        S[0], C[0] = np.sin(self.k * x0), np.cos(self.k * x0)
        mu, mub, D, om2, v = self.mu, self.mu * self.beta, self.D, self.om2, self.v
        ki = self.k * _INV
        for n in range(ORDER):
            q[n] = np.dot(s[:n + 1], s[n::-1])
            qu, cu, su = A[:, :n + 1] @ u[n::-1]
            un, i = u[n], _INV[n]
            s[n + 1] = (un - v) * i if n == 0 else un * i
            u[n + 1] = (mu * un - mub * qu - om2 * s[n] - D * S[n]) * i
            C[n + 1] = -su * ki[n]
            S[n + 1] = cu * ki[n]
        x[1:] = u[:ORDER] * _INV
        q[ORDER] = np.dot(s, s[::-1])
        uu = np.convolve(u, u)[:ORDER]
        M[3, 1:] = mu * np.convolve(q, uu)[:ORDER] * _INV
        M[4, 1:] = mu * uu * _INV
        M[5, 1:] = -om2 * np.convolve(s, u)[:ORDER] * _INV
        M[6, 1:] = -om2 * s[:ORDER] * _INV
        return M

    def step(self, M: np.ndarray) -> LD:
        """The step: the last two terms of ``x`` and ``x'`` below the rounding, relative to
        ``lam`` and ``lam`` times the well frequency; at most ``MAX_PHASE`` over it."""
        h = LD(MAX_PHASE / self.omega)
        tol = LD(ROUNDING_LD / 8) * self.lam
        for row, scale in ((0, LD(1)), (1, LD(self.omega))):
            for n in (ORDER - 1, ORDER):
                c = abs(M[row, n])
                if c > 0:
                    h = min(h, (tol * scale / c) ** (LD(1) / n))
        return h


def _at(M: np.ndarray, tau: LD) -> np.ndarray:
    """The series ``M`` (rows) at ``tau``."""
    return M @ (tau ** _POWERS)


def _grid(M: np.ndarray, tau: np.ndarray) -> np.ndarray:
    """The series ``M`` (rows, in double) at the times ``tau``: one row per time."""
    return (tau[:, None] ** _POWERS.astype(float)) @ M.T


def section(system: DrivenSystem) -> float | None:
    """The section ``s_c``: midway between ``-1/sqrt(beta)`` and the saddle node's
    extension ``-Delta sqrt(1 - 1/eta^2)/Omega^2``; ``None`` when the slider cannot stick
    beyond the self-excited zone (``eta <= 1``, or the saddle node within it).

    Examples
    --------
    >>> from numerics.sliding.driven import driven_system
    >>> p = {"mu": 0.1, "beta": 1, "Delta": 3, "lam": 1, "Omega": 1, "v": 2e-3}
    >>> round(section(driven_system("sedf_comoving", p, engine="scipy")), 4)
    -1.9979
    """
    p = system.params
    eta = 2 * math.pi * p["Delta"] / (p["Omega"] ** 2 * p["lam"])
    if eta <= 1:
        return None
    s_sn = p["Delta"] * math.sqrt(1 - 1 / eta ** 2) / p["Omega"] ** 2
    edge = 1 / math.sqrt(p["beta"])
    return -(edge + s_sn) / 2 if s_sn > edge else None


def stick_slip_cycles(system: DrivenSystem, dt: float, v_stick: float, cycles: int = CYCLES,
                      max_steps: int = MAX_STEPS) -> Cycles | str:
    """``cycles`` consecutive cycles between ``cycles + 1`` crossings of the section (the
    module docstring), sampled at the multiples of ``dt``; or why not.

    Parameters
    ----------
    system
        A ``sedf_comoving`` slider (:func:`~numerics.sliding.driven.driven_system`).
    dt
        The samples' spacing (the friction point's, a whole fraction of ``lam/v``).
    v_stick
        ``|x'|`` below it at a crossing: stuck (criterion 2).
    cycles, max_steps
        The cycles integrated; the most Taylor steps (:data:`MAX_STEPS`).

    Returns
    -------
    Cycles or str
        The cycles, or why there are none: no section (:func:`section`), or more than
        ``max_steps`` steps."""
    sc = section(system)
    if sc is None:
        return "the slider does not stick beyond the self-excited zone |s| < 1/sqrt(beta)"
    tay = _Taylor(system)
    k, om2, v, lam, D, sec = tay.k, tay.om2, tay.v, tay.lam, tay.D, LD(sc)
    s = (sec - LD(1 / math.sqrt(system.params["beta"]))) / 2  # the stick before the section
    x = np.arcsin(-om2 * s / D) / k  # quasi-static: Delta sin(k x) = -Omega^2 s
    stiff = om2 + D * k * np.cos(k * x)
    u = v * om2 / stiff  # its slow velocity, and the lag of its damping mu (beta s^2 - 1)
    x -= tay.mu * (tay.beta * s * s - 1) * u / stiff
    t, shift = (x - s) / v, 0  # s = x - v t
    acc = np.zeros(4, LD)  # G_+, G_-, W, J
    sections, rows, steps = [], [], 0
    while len(sections) <= cycles:
        if steps >= max_steps:
            return (f"{max(0, len(sections) - 1)} of {cycles} cycles within {max_steps} "
                    "Taylor steps")
        M = tay.series(x, u, s)
        h = tay.step(M)
        end = _at(M, h)
        steps += 1
        i = np.arange(math.floor(float(t) / dt) + 1, math.floor(float(t + h) / dt) + 1)
        if len(i):  # the samples at the multiples of dt
            val = _grid(M.astype(float), i * dt - float(t))
            val[:, 0] += shift * float(lam)
            val[:, 3:] += acc.astype(float)
            rows.append(np.column_stack([val[:, :2], i * dt, val[:, 3:]]))
        if s > sec >= end[2] and abs(end[1]) < v_stick:
            tc = h * (s - sec) / (s - end[2])
            for _ in range(4):  # Newton on s(tc) = s_c, s' = x' - v
                at = _at(M, tc)
                tc -= (at[2] - sec) / (at[1] - v)
            at = _at(M, tc)
            sections.append(np.array([t + tc, at[0] + shift * lam, at[1], *(acc + at[3:])],
                                     dtype=LD))
        x, u, s, t = end[0], end[1], end[2], t + h
        acc = acc + end[3:]
        n = int(np.floor(float(x / lam) + 0.5))
        x, shift = x - n * lam, shift + n
    rows = np.concatenate(rows)
    keep = (rows[:, 2] >= float(sections[0][0])) & (rows[:, 2] <= float(sections[-1][0]))
    return Cycles(sections=np.array(sections), rows=rows[keep], steps=steps)


def extended_point(system: DrivenSystem, s: FrictionSettings, base: dict, dt: float,
                   v_stick: float, min_stuck: int) -> FrictionPoint | str:
    """The point measured over :data:`CYCLES` cycles in long double, or why not.

    The window runs from the first section to the last; the mean force, dissipation and
    power balance are those of the sections' long-double integrals, the stuck intervals
    (criterion 2, :func:`~numerics.sliding.window._stick_phases`), static and peak force and
    the force's fluctuation those of the samples at the multiples of ``dt``.

    Parameters
    ----------
    system, s, base
        The slider, the criterion, the point's fixed fields (``model, params, eta,
        static_quasistatic``).
    dt, v_stick, min_stuck
        The samples' spacing, the stick velocity and the fewest samples of a stuck interval
        (criterion 2 of :mod:`numerics.sliding.friction`).

    Returns
    -------
    FrictionPoint or str
        The stick-slip point (steady when the cycles repeat, criterion 4; its note says
        how they compare), or why it was not measured (:func:`stick_slip_cycles`)."""
    cyc = stick_slip_cycles(system, dt, v_stick)
    if isinstance(cyc, str):
        return cyc
    lam, v, g = system.lam, system.v, system.gain_factor
    sec = cyc.sections
    wells = cyc.wells(lam)
    T = np.diff(sec[:, 0])
    halves = tuple(float(f) for f in np.diff(sec[:, 6]) / T)
    at = np.column_stack([sec[:, 1], sec[:, 2], sec[:, 0], sec[:, 3:]]).astype(float)
    span = float(sec[-1, 0] - sec[0, 0])
    dJ = float(sec[-1, 6] - sec[0, 6])
    gam, E = system.gamma(at), system.energy(at)
    dG, dE = float(gam[-1] - gam[0]), float(E[-1] - E[0])
    F, diss = dJ / span, dG / (v * span)
    flow = abs(g * float(sec[-1, 3] - sec[0, 3])) + abs(float(sec[-1, 4] - sec[0, 4]))
    scale = max(abs(F), flow / (v * span))
    run = _Samples(cyc.rows, system)
    stuck = _stick_phases(run, v_stick, min_stuck)
    force = system.omega ** 2 * (v * cyc.rows[:, 2] - cyc.rows[:, 0])
    peaks = [float(np.max(force[a:e + 1])) for a, e in stuck[:-1]]  # each before a slip
    if not peaks:
        return "no slip between the sections in the samples"
    stuck_time = sum(e - a for a, e in stuck) * dt
    agree = abs(halves[0] - halves[-1]) <= s.steady_tol * max(max(map(abs, halves)),
                                                              flow / (v * span))
    steady = (len(set(wells)) == 1 and agree
              and abs(dE) <= s.energy_tol * max(abs(v * dJ), flow))
    return FrictionPoint(
        **base, regime="stick-slip", steady=steady, mean_force=F,
        force_fluctuation=float(np.std(force)), static_force=float(np.mean(peaks)),
        peak_force=float(np.max(force)), dissipation_per_distance=diss,
        energy_residual=abs(F - diss) / scale,
        audit=abs(v * dJ - dG - dE) / max(abs(dG), 1e-300), stuck_fraction=stuck_time / span,
        wells_per_slip=sum(wells) / len(peaks), slips=len(peaks), halves=halves,
        window=(float(sec[0, 0]), float(sec[-1, 0])),
        steps=cyc.steps, note=_cycles_note(cyc, wells, T, lam / v, halves, section(system)))


@dataclass(frozen=True, eq=False)
class _Samples:
    """The samples as :func:`~numerics.sliding.window._stick_phases` reads a run."""

    y: np.ndarray
    system: DrivenSystem


def _cycles_note(cyc: Cycles, wells: list[int], T: np.ndarray, Tw: float, halves: tuple,
                 sec_s: float) -> str:
    """What the cycles were: wells, mean forces and how far apart, periods against ``n lam/v``."""
    rel = abs(halves[-1] - halves[0]) / max(abs(halves[0]), 1e-300)
    period = max(abs(float(t / (n * LD(Tw)) - 1)) for t, n in zip(T, wells)) if all(wells) \
        else math.inf
    same = ("they repeat: the same wells, mean forces within "
            f"{rel:.2g} of each other, periods n lam/v within {period:.2g}"
            if len(set(wells)) == 1 else "they do not repeat")
    return (f"{len(wells)} consecutive cycles between crossings of the stick's section s = "
            f"{float(sec_s):.4g} ({cyc.steps} Taylor steps of order {ORDER}): wells per slip "
            f"{', '.join(map(str, wells))}, mean forces "
            f"{', '.join(f'{h:.11g}' for h in halves)}; {same}")


def gain(system: DrivenSystem) -> float | None:
    """``G = 2 mu/(3 v sqrt(beta))``, the self-excitation's gain (its growth rate ``mu (1 -
    beta s^2)/2`` over ``|s| < 1/sqrt(beta)`` at ``s' = -v``) each time the stage passes the
    stuck ``sedf_comoving``; ``None`` for the other sliders."""
    p = system.params
    if system.model != "sedf_comoving":
        return None
    return 2 * p["mu"] / (3 * system.v * math.sqrt(p["beta"]))


def beyond_double(system: DrivenSystem, s: FrictionSettings, base: dict, pt: FrictionPoint,
                  said: str, dt: float, v_stick: float, min_stuck: int) -> FrictionPoint:
    """Criterion 6's irregular point ``pt`` (``said``: what the two compiled runs showed),
    where the rounding of double precision times ``e^G`` exceeds :data:`UNRESOLVED` ``lam``:
    the cycle measured in long double (:func:`extended_point`) if its rounding times ``e^G``
    does not, with a note that says why; otherwise ``pt`` with the note that it is not
    resolved (and why not in long double).  Every other point: ``pt``.

    Its slips land the slider near ``2/sqrt(beta)`` ahead of the stage, where the damping
    until the stage arrives equals that gain, so the exact in-well oscillation falls to
    about ``e^-G`` of its size at landing, below the rounding when ``G`` is large.

    Parameters
    ----------
    system, s, base
        The slider, the criterion, the point's fixed fields.
    pt
        The point as criterion 6 measured it in double precision (its note written).
    said
        What the two compiled runs showed, the start of the note of a point measured here.
    dt, v_stick, min_stuck
        As for :func:`extended_point`.

    Returns
    -------
    FrictionPoint
        ``pt`` itself (another slider, or ``G`` small), ``pt`` with the reason it is not
        resolved appended to its note, or the point in long double."""
    G = gain(system)
    if G is None or ROUNDING * math.exp(min(G, 700.0)) < UNRESOLVED:
        return pt
    eG = math.exp(min(G, 700.0))
    why = (f"; not resolved in double precision: the self-excitation multiplies the "
           f"integration error, at least the rounding {ROUNDING:.2g}, by exp(2 mu/(3 v "
           f"sqrt(beta))) = {eG:.2g} each time the stage passes the stuck slider "
           f"({ROUNDING * eG:.2g} lam)")
    ld = f"long double, rounding {ROUNDING_LD:.2g} x {eG:.2g} = {ROUNDING_LD * eG:.2g} lam"
    if ROUNDING_LD * eG >= UNRESOLVED:
        return replace(pt, note=f"{pt.note}{why}: the irregular slips may be rounding error; "
                                f"not measured in extended precision ({ld}, not below "
                                f"{UNRESOLVED:g} lam either)")
    ext = extended_point(system, s, base, dt, v_stick, min_stuck)
    if isinstance(ext, str):
        return replace(pt, note=f"{pt.note}{why}: the irregular slips may be rounding error; "
                                f"not measured in extended precision ({ld}): {ext}")
    return replace(ext, steps=pt.steps + ext.steps,
                   note=f"{said}{why}: the point as measured in extended precision instead "
                        f"({ld}): {ext.note}")
