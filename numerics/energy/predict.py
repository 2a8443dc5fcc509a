"""Every limit cycle of a model predicted by strongly nonlinear averaging.

:func:`predict_cycles` splits the model into ``x'' = -g(x) + mu h(x, x')``
(:mod:`kbm.model.conservative`), finds the period annuli of ``x'' + g(x) = 0``
(:mod:`~numerics.energy.portrait`), the roots of the energy balance
``Gamma(E) = 0`` on each (:mod:`~numerics.energy.balance`, order 1) and, for
``order >= 2``, refines each either by successive approximation of the energy
along the cycle in the position variable (``scheme="position"``, the default,
:mod:`~numerics.energy.position`) or by averaging in energy-angle variables
(``scheme="energy-angle"``, :mod:`~numerics.energy.averaging`).  Both have
period errors ``O(mu**(order + 1))`` as ``mu -> 0``; only the position scheme
stays valid when the energy's swing over a cycle is comparable to its distance
to a separatrix (the energy-angle series in ``mu`` then diverges).

References
----------
S. Coppola and R. H. Rand, Acta Mechanica 81 (1990); the paper's eq. (10).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
import sympy as sp

from kbm.model.conservative import ConservativeSplit, split_conservative
from kbm.errors import OrderError
from kbm.symbols import xdot as _xdot

from .averaging import _extrema, average
from .position import PositionError, position_cycle
from .balance import _scan_energies, balance_cycles, gamma_function
from .orbits import sample_orbits
from .portrait import phase_portrait

__all__ = ["PredictedCycle", "EnergyPrediction", "predict_cycles"]


def _num(v):
    v = float(v)
    return v if math.isfinite(v) else None


def _readonly(a) -> np.ndarray:
    a = np.array(a)
    a.setflags(write=False)
    return a


@dataclass(frozen=True, eq=False)
class PredictedCycle:
    """A limit cycle predicted by energy averaging.

    Attributes
    ----------
    amplitude_max, amplitude_min : float
        Largest and smallest ``x`` on the cycle.
    amplitude_first_harmonic : float
        ``2 |c_1|`` (KBM's ``a``).
    period, frequency : float
        ``T`` and ``2 pi/T``.
    energy : float
        ``E*`` (order 1), ``eps*``, the energy of the averaged variables
        (energy-angle scheme), or the time average of the energy over the
        computed cycle (position scheme).
    stable : bool
    annulus : str
        The label of the period annulus.
    order : int
    floquet_multiplier : float
        The predicted non-trivial multiplier.
    harmonics : numpy.ndarray
        Read-only complex ``c_m``, ``m = 0..15``, of ``x = sum c_m e^{i m omega t}``
        (time 0 at the maximum of the conservative orbit).
    error : float
        Estimate of the numerical (not asymptotic) relative error.
    separatrix_margin : float
        Distance of the cycle's energy to the nearest bounding separatrix over
        the energy's swing ``mu oint |h v| dt`` in one period (``inf`` when none).
        Below ~1 the expansion beyond first order breaks down (the orders do not
        improve on each other); see :class:`~numerics.energy.balance.BalanceCycle`.
    period_sensitivity : float
        ``mu oint |h v| dt |dT/dE| / T`` at the energy-balance root: the relative
        change of the period across one cycle's energy swing.  Above ~1 the
        mu-expansion beyond first order is not to be trusted (measured: energy-angle
        order 2 is worse than order 1 for the sliders at 1.2 and 1.3, better at
        0.03-0.46); the position scheme is not affected.
    scheme : str
        ``"energy balance"``, ``"position"`` or ``"energy-angle"``: how the cycle was
        computed.
    term_size : float
        Classical KBM only (NaN otherwise): the largest of the relative frequency shift
        ``|sum mu^n B_n|/omega0``, the waveform correction ``max |sum mu^n u_n|/a`` and
        the ratios ``|mu^n B_n|/|mu^(n-1) B_(n-1)|`` of successive orders at the root.
        The expansion assumes all of them small; above :data:`KBM_TERM_LIMIT` the cycle
        is not to be trusted.
    """

    amplitude_max: float
    amplitude_min: float
    amplitude_first_harmonic: float
    period: float
    frequency: float
    energy: float
    stable: bool
    annulus: str
    order: int
    floquet_multiplier: float
    harmonics: np.ndarray = field(repr=False)
    error: float = 0.0
    separatrix_margin: float = float("inf")
    period_sensitivity: float = 0.0
    scheme: str = "energy balance"
    term_size: float = math.nan

    def to_json(self) -> dict:
        """Strict-JSON dict (non-finite numbers become ``None``)."""
        out = {k: _num(getattr(self, k)) for k in
               ("amplitude_max", "amplitude_min", "amplitude_first_harmonic", "period",
                "frequency", "energy", "floquet_multiplier", "error", "separatrix_margin",
                "period_sensitivity")}
        out.update(stable=bool(self.stable), annulus=self.annulus, order=int(self.order),
                   scheme=self.scheme,
                   harmonics=[[_num(c.real), _num(c.imag)] for c in self.harmonics])
        if math.isfinite(self.term_size):
            out["term_size"] = self.term_size
        return out


@dataclass(frozen=True, eq=False)
class EnergyPrediction:
    """The cycles of a model at given parameters, predicted to ``order``.

    Attributes
    ----------
    model : str
    params : Mapping[str, float]
        ``mu`` and the scaled parameters used.
    order : int
    cycles : tuple of PredictedCycle
        Sorted by energy.
    reason : str
        Why there is no cycle, or why a refinement lost an energy-balance cycle
        (empty when every energy-balance cycle was refined).
    annuli : tuple of dict
        Label and energy range of every annulus.
    equilibria : tuple of dict
        Position, kind and energy of every equilibrium.
    """

    model: str
    params: Mapping[str, float]
    order: int
    cycles: tuple
    reason: str = ""
    annuli: tuple = ()
    equilibria: tuple = ()
    method: str = "energy averaging"
    warning: str = ""

    def to_json(self) -> dict:
        """Strict-JSON dict with key ``cycles`` (and ``warning`` when the list is not to be
        trusted)."""
        out = {"model": self.model, "params": {k: _num(v) for k, v in self.params.items()},
               "order": self.order, "method": self.method,
               "cycles": [c.to_json() for c in self.cycles], "reason": self.reason,
               "annuli": list(self.annuli), "equilibria": list(self.equilibria)}
        if self.warning:
            out["warning"] = self.warning
        return out


def _n_theta(annulus, E) -> int:
    """Samples per period resolving the orbit at ``E`` to 1e-12, doubled for products."""
    X = sample_orbits(annulus, [E], 2048).X[0]
    s = np.abs(np.fft.rfft(X))
    m_max = int(np.max(np.nonzero(s > 1e-12 * np.max(s))[0]))
    n = 64
    while n < 2048 and n * 7 // 16 <= m_max:
        n *= 2
    return 2 * n


def _refine(c1, mu, order, n_energy, rate_order):
    """Order-``order`` cycle near the energy-balance root ``c1`` (None if no root)."""
    a = c1.annulus
    E1 = c1.energy
    d = E1 - a.energy_min if not a.bounded else min(E1 - a.energy_min, a.energy_max - E1)
    w, center, best = 0.1 * d, E1, None
    nt = _n_theta(a, min(E1 + 0.5 * d, E1 + 1e3 * d))
    for _ in range(8):
        lo = max(center - w, a.energy_min + 0.02 * d)
        hi = center + w if not a.bounded else min(center + w, a.energy_max - 0.02 * d)
        av = average(a, mu, rate_order, (lo, hi), n_energy=n_energy, n_theta=nt)
        r = av.roots()
        if not len(r):
            if w >= 0.5 * d:
                break
            w = min(2 * w, 0.5 * d)
            continue
        eps = float(r[np.argmin(np.abs(r - center))])
        if best is None or av.error < best[0].error:
            best = (av, eps)
        if av.error <= 1e-7:
            break
        # unresolved: recentre on the root and halve the interval
        center, w = eps, 0.5 * w
    if best is None:
        return None
    av, eps = best
    freq = float(av.frequency(eps, order))
    T = 2 * np.pi / freq
    slope = float(av.rate(eps, derivative=1))
    xw = av.waveform(eps, order)
    harm = np.fft.rfft(xw) / len(xw)
    xmax, xmin = _extrema(xw)
    return PredictedCycle(xmax, xmin, float(2 * abs(harm[1])), T, freq, eps, slope < 0,
                          a.label, order, float(np.exp(T * slope)), _readonly(harm[:16]),
                          float(av.error), c1.separatrix_margin, c1.period_sensitivity,
                          "energy-angle")


def _position(c1, functions, hv, mu, order, **kwargs):
    """The cycle after ``order`` integrations of the position scheme (see its module), and
    the :class:`PositionCycle` (``kwargs`` go to :func:`position_cycle`)."""
    p = position_cycle(c1.annulus, functions, hv, mu, c1.energy, order, **kwargs)
    T = p.period
    return PredictedCycle(p.x_max, p.x_min, float(2 * abs(p.harmonics[1])), T, 2 * np.pi / T,
                          p.mean_energy, p.floquet_multiplier < 1, c1.annulus.label, order,
                          p.floquet_multiplier, _readonly(p.harmonics), p.error,
                          c1.separatrix_margin, c1.period_sensitivity, "position"), p


def _first_order(c):
    """The energy-balance root ``c`` as a :class:`PredictedCycle`."""
    return PredictedCycle(c.x_max, c.x_min, c.amplitude_first_harmonic, c.period,
                          2 * np.pi / c.period, c.energy, c.stable, c.annulus.label, 1,
                          c.floquet_multiplier, _readonly(c.harmonics), c.error,
                          c.separatrix_margin, c.period_sensitivity)


def predict_cycles(model, params: Mapping[str, object] | None = None, *, order: int = 1,
                   potential=None, n_energy: int = 24, rate_order: int | None = None,
                   scheme: str | None = None, split: ConservativeSplit | None = None
                   ) -> EnergyPrediction:
    """Predict every limit cycle on every period annulus by energy averaging.

    Parameters
    ----------
    model : kbm.model.builtins.Oscillator or str
        An autonomous model (or a built-in name).
    params : Mapping[str, object]
        ``mu`` and the model's parameters (physical names such as ``Delta``,
        ``lam`` are accepted).
    order : int
        1: energy balance ``Gamma(E) = 0``; ``>= 2``: refined to that order in mu
        (period error ``O(mu**(order + 1))``; one order more when ``h`` is odd in
        ``x'`` and ``order`` even, by the symmetry ``t, x', mu -> -t, -x', -mu``).
        For ``h`` not odd in ``x'``, order 1 is also refined (one integration, or
        the energy-angle ``rate_order = 2``).
    potential : str or sympy.Expr, optional
        A potential ``V(x)`` for the conservative part (see
        :func:`kbm.model.conservative.split_conservative`).
    n_energy : int
        Chebyshev nodes in energy (energy-angle scheme).
    scheme : {"position", "energy-angle"}, optional
        ``"position"`` (default): ``order`` successive integrations of
        ``dE/dx = mu h(x, x')`` along the cycle, each closed by a generalised
        energy balance, without expanding in ``mu`` (:mod:`~numerics.energy.position`);
        valid up to the separatrices.  ``"energy-angle"`` (default when
        ``rate_order`` is given): the near-identity transformation in
        energy-angle variables (:mod:`~numerics.energy.averaging`), the KBM
        normal form for linear ``g``; its series in ``mu`` diverges when
        ``period_sensitivity`` exceeds about 1.
    split : kbm.model.conservative.ConservativeSplit, optional
        The split of ``model`` at ``params`` if already made (e.g. by a
        :class:`kbm.model.conservative.SplitLine` along a parameter); else it is made here.
    rate_order : int, optional
        Order of the averaged rate ``sum mu**n M_n`` whose root gives ``eps*``
        (``order >= 2`` only; default ``order + 1``).  With the first-harmonic
        gauge ``M_{N+1}`` shifts ``eps*`` by ``O(mu**N)``, and ``omega'(eps) != 0``
        turns that into an ``O(mu**N)`` period change: with ``rate_order = order``
        (the KBM convention) the order-2 period is no better than the order-1 one
        for the sliders; one order more in the rate makes the period error
        ``O(mu**(order + 1))``.  Frequency and waveform use orders ``<= order``.
        Energy-angle scheme only.

    Returns
    -------
    EnergyPrediction
        The cycles sorted by energy; when empty, ``reason`` says why.

    Raises
    ------
    kbm.errors.OrderError
        If ``order < 1``, or ``rate_order`` is given with the position scheme.
    ValueError
        For an unknown ``scheme``.
    kbm.errors.ModelError, kbm.errors.ParameterError
        From the split (non-autonomous model, ``mu`` missing or zero, a
        potential that does not confine).
    """
    if not isinstance(order, (int, np.integer)) or order < 1:
        raise OrderError(f"order must be an integer >= 1, got {order!r}")
    if scheme is None:
        scheme = "position" if rate_order is None else "energy-angle"
    if scheme not in ("position", "energy-angle"):
        raise ValueError(f"scheme must be 'position' or 'energy-angle', got {scheme!r}")
    if scheme == "position" and rate_order is not None:
        raise OrderError("rate_order applies to the energy-angle scheme only")
    rate_order = order + 1 if rate_order is None else int(rate_order)
    if rate_order < order:
        raise OrderError(f"rate_order = {rate_order} must be >= order = {order}")
    if split is None:
        split = split_conservative(model, params, potential=potential)
    portrait = phase_portrait(split)
    info = dict(model=split.model.name, params={"mu": split.mu, **split.params}, order=int(order),
                annuli=tuple(a.summary() for a in portrait.annuli),
                equilibria=tuple({"x": e.x, "kind": e.kind, "energy": e.energy}
                                 for e in portrait.equilibria))
    if split.conservative:
        return EnergyPrediction(cycles=(), reason="conservative: every orbit is periodic, "
                                "no isolated cycle (h = 0)", **info)
    first = balance_cycles(portrait)
    if not first:
        pos, neg, searched = [], [], []
        for a in portrait.annuli:
            E, _ = _scan_energies(a, 96, 1e4 * (1 + abs(a.energy_min)))
            sg = np.sign(gamma_function(a, tol=1e-9)(E)[0])
            (pos if np.sum(sg > 0) > np.sum(sg < 0) else neg).append(a.label)
            searched.append(f"{a.label}: E from {E[0]:.4g} to {E[-1]:.4g}")
        where = ("searched: Gamma(E) at 96 energies on each annulus (" + "; ".join(searched)
                 + ") and at every extremum between them that turns towards 0")
        if not pos:
            reason = (f"no root of Gamma(E) found, Gamma < 0 wherever evaluated: the orbits "
                      f"there lose energy ({where})")
        elif not neg:
            reason = (f"no root of Gamma(E) found, Gamma > 0 wherever evaluated: the orbits "
                      f"there gain energy ({where})")
        else:
            reason = ("no root of Gamma(E) found: orbits gain energy in "
                      f"{', '.join(pos)} and lose it in {', '.join(neg)}, so the motion "
                      "approaches a separatrix or an equilibrium (no isolated cycle of "
                      f"the averaged equation; {where})")
        return EnergyPrediction(cycles=(), reason=reason, **info)
    odd = sp.expand(split.h + split.h.subs(_xdot, -_xdot)) == 0
    hv = split.h_velocity_function()

    def hvf(x, v):
        return np.broadcast_to(np.asarray(hv(x, v), float), np.broadcast(x, v).shape)

    cycles, lost = [], []
    for c in first:
        if order == 1 and (odd or rate_order == 1):
            cycles.append(_first_order(c))
        elif scheme == "position":
            try:
                cycles.append(_position(c, portrait.functions, hvf, split.mu, int(order))[0])
            except PositionError as e:
                lost.append(f"{c.annulus.label} (x_max {c.x_max:.6g}): {e}")
        else:
            p = _refine(c, split.mu, int(order), n_energy, rate_order)
            if p is not None:
                cycles.append(p)
            else:
                lost.append(f"{c.annulus.label} (x_max {c.x_max:.6g}): the averaged rate "
                            "has no root near the energy-balance cycle")
    cycles.sort(key=lambda c: (c.energy, c.amplitude_max))
    reason = "; ".join(lost)
    return EnergyPrediction(cycles=tuple(cycles), reason=reason, **info)
