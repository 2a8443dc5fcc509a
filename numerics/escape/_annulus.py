"""One period annulus of the energy envelope (:mod:`numerics.escape.envelope`): the checks
of a noisy model before any averaging, the orbit integrals ``I``, ``Gamma`` and
``K = oint x^2 x' dx`` of an annulus fitted by piecewise Chebyshev series, and
:class:`AnnulusEnvelope`, the averaged energy process they give on it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from kbm.model.conservative import split_conservative
from kbm.errors import ModelError, ParameterError
from kbm.parameters.names import noise_intensity

from ..energy.portrait import Annulus, Portrait, phase_portrait
from ._orbits import graded_orbit_integrals, interior_saddles
from ._panels import Piecewise, adaptive_panels, gauss_on
from .noise_params import NoStationaryState

__all__ = ["AnnulusEnvelope", "MAX_INFLECTIONS", "prepared", "fitted", "orbit_values",
           "check_drift"]


def _integrands(h):
    """Half-orbit integrands (see :meth:`Annulus.orbit_integrals`): ``I``, ``Gamma``,
    ``K = oint x^2 x' dx`` (``dK/dE = oint x^2 dt``)."""
    return [lambda x, v, sq: 2.0 * v * v / sq,
            lambda x, v, sq: (h(x, v) - h(x, -v)) * v / sq,
            lambda x, v, sq: 2.0 * x * x * v * v / sq]


@dataclass(frozen=True, eq=False)
class AnnulusEnvelope:
    """The averaged energy process on one period annulus, as piecewise Chebyshev series.

    Attributes
    ----------
    annulus : numerics.energy.portrait.Annulus
    lo, hi : float
        The energy interval represented (``hi`` is a cut-off on the outer annulus).
    action, gamma, x2action : numerics.escape._panels.Piecewise
        ``I(E)``, ``Gamma(E)`` and ``K(E) = oint x^2 x' dx``: interpolants of the exact
        orbit quadratures on adaptive panels, graded towards a separatrix end.
    log_f : numerics.escape._panels.Piecewise
        ``ln f(E)`` (up to the constant fixed by the gluing).
    error : float
        Largest relative error of the orbit quadratures.
    """

    annulus: Annulus
    lo: float
    hi: float
    action: Piecewise
    gamma: Piecewise
    x2action: Piecewise
    log_f: Piecewise
    error: float

    def __repr__(self) -> str:
        return (f"AnnulusEnvelope({self.annulus.label!r}, E in [{self.lo:.4g}, {self.hi:.4g}]"
                f", {len(self.action.pieces)} panels)")

    def rule(self, a: float | None = None, b: float | None = None, n: int = 24):
        """Composite Gauss-Legendre nodes and weights on ``[a, b]`` (default the whole
        range), cut at the panels' break points."""
        a = self.lo if a is None else max(a, self.lo)
        b = self.hi if b is None else min(b, self.hi)
        br = self.action.breaks
        inner = br[(br > a) & (br < b)]
        return gauss_on(np.concatenate(([a], inner, [b])), n)

    def boundary(self, F, a: float, b: float) -> float:
        """``[F f]_a^b`` with ``f = exp(log_f)``."""
        return float(F(b) * np.exp(self.log_f(b)) - F(a) * np.exp(self.log_f(a)))


def orbit_values(annulus: Annulus, saddles, h, mu: float, D: float):
    """``E -> [I, Gamma, K, (mu/D) Gamma/I]`` by the spectral orbit quadrature (graded
    Gauss-Legendre when the orbits pass over ``saddles``), and the largest quadrature
    error met (a one-element list, updated)."""
    worst = [0.0]

    def values(E):
        if len(saddles):
            I, Gam, K = graded_orbit_integrals(annulus, saddles, E, _integrands(h))
        else:
            vals, err, _, _ = annulus.orbit_integrals(E, _integrands(h), tol=1e-13)
            worst[0] = max(worst[0], float(np.max(err)))
            I, Gam, K = vals
        return [I, Gam, K, mu * Gam / (D * I)]

    return values, worst


#: the most inflections of ``G`` an orbit of the outer annulus may cross at its top energy
#: (each needs its own quadrature panels: about 0.1-0.3 s apiece on a loaded machine)
MAX_INFLECTIONS = 200


def _check_outer_cost(split, portrait: Portrait, top: float, kT: float) -> None:
    """Refuse, with the numbers, an outer annulus whose top orbit crosses more than
    :data:`MAX_INFLECTIONS` inflections of ``G`` (the noise then dwarfs the barriers and
    the orbit quadratures would take minutes)."""
    xm, xp = (float(np.ravel(t)[0]) for t in portrait.outer.turning_points(np.array([top])))
    curv = np.sign(split.numpy_functions()[1](np.linspace(xm, xp, 40001)))
    count = int(np.count_nonzero(np.diff(curv[curv != 0])))
    if count <= MAX_INFLECTIONS:
        return
    Gs = [e.energy for e in portrait.equilibria if e.kind == "saddle"]
    Gc = [e.energy for e in portrait.equilibria if e.kind == "center"]
    barrier = (f"the largest barrier {max(Gs) - min(Gc):.3g} is {kT / (max(Gs) - min(Gc)):.3g}"
               " times smaller than D/mu") if Gs and Gc else "the potential has no barrier"
    raise ModelError(
        f"energy envelope refused: D/mu = {kT:.4g} puts the top of the outer annulus at E = "
        f"{top:.4g}, where an orbit spans x in [{xm:.4g}, {xp:.4g}] across {count} "
        f"inflections of G (> {MAX_INFLECTIONS}: minutes of orbit quadratures); {barrier}. "
        "Lower D (or raise mu), or use the simulation")


def prepared(model, params: dict, D: object, outer_span: float) -> tuple:
    """``(split, portrait, h, mu, D)`` after the checks of
    :func:`numerics.escape.envelope.energy_envelope`."""
    D = noise_intensity(D, "the averaged energy process needs noise")
    params = {k: v for k, v in dict(params).items() if k != "D"}
    split = split_conservative(model, params)
    if split.conservative:
        name = model if isinstance(model, str) else getattr(model, "name", "the model")
        raise NoStationaryState(f"{name} has no damping (its F does not depend on x'): with "
                                "noise its energy grows without bound, so there is no "
                                "stationary state and no escape rate; choose a model with "
                                "damping (cdc, or sedf at v = 0)")
    mu = float(split.mu)
    if not mu > 0:
        raise ParameterError(f"mu = {mu:g}: the small parameter of x'' = -g(x) + mu h must "
                             "be > 0 (mu <= 0 turns the damping into a drive); give mu > 0")
    portrait = phase_portrait(split)
    h = split.numpy_functions()[3]
    _check_outer_cost(split, portrait, portrait.outer.energy_min + outer_span * D / mu, D / mu)
    return split, portrait, h, mu, D


def fitted(a: Annulus, portrait: Portrait, h, mu: float, D: float, outer_span: float,
            tol: float) -> AnnulusEnvelope:
    """One annulus's envelope: the interpolants of its orbit integrals on adaptive panels,
    ``ln f`` 0 at ``lo``."""
    lo = a.energy_min
    hi = a.energy_max if a.bounded else lo + outer_span * D / mu
    values, worst = orbit_values(a, interior_saddles(a, portrait.equilibria), h, mu, D)
    breaks, (I, Gam, K, r) = adaptive_panels(
        values, lo, hi, singular_lo=len(a.wells) > 1, singular_hi=a.bounded, tol=tol)
    return AnnulusEnvelope(a, lo, hi, Piecewise(breaks, I), Piecewise(breaks, Gam),
                           Piecewise(breaks, K), Piecewise(breaks, r).integ(), worst[0])


def check_drift(rate: float, E: float) -> None:
    """Refuse a positive ``mu Gamma/(D I)`` at the outer annulus' top energy ``E``."""
    if not rate < 0:
        raise NoStationaryState(
            f"no stationary state: the averaged energy drift mu Gamma(E)/T(E) is not negative "
            f"at large energy (mu Gamma/(D I) = {rate:.3g} at E = "
            f"{E:.4g}): the damping feeds energy in and the noise is not balanced; "
            "choose parameters whose damping is positive at large amplitude")
