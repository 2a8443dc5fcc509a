"""Energy-envelope stochastic averaging about the conservative orbits.

The noisy model ``x'' = -g(x) + mu h(x, x') + sqrt(2 D) xi(t)`` (unit mass,
``<xi(t) xi(t')> = delta(t - t')``) is split as in :mod:`kbm.conservative`.  With
``H = x'**2/2 + G(x)``, Ito's formula gives

``dH = [mu h x' + D] dt + sqrt(2 D) x' dW``.

Averaged over the conservative orbit of energy ``E`` (Stratonovich-Khasminskii
limit theorem; Freidlin-Wentzell energy averaging), ``E`` is a one-dimensional
diffusion ``dE = b(E) dt + sigma(E) dW`` on each period annulus with

``b(E) = [mu Gamma(E) + D T(E)] / T(E)``,   ``sigma**2(E) = 2 D I(E) / T(E)``,

``T(E) = oint dt`` the period, ``I(E) = oint x' dx`` the action (``dI/dE = T``) and
``Gamma(E) = oint h x' dt`` the work of the perturbation per cycle (paper eq. 10).
The stationary phase-space density is a function of ``E`` alone on each annulus,

``f(E) = exp( int mu Gamma(E) / (D I(E)) dE )``,

continuous at the separatrix energies where annuli meet (the gluing condition of
the process on the graph of the Hamiltonian; it follows from zero probability flux
on a tree).  The density of ``E`` on an annulus is ``T(E) f(E)`` (the period is the
phase area per unit energy).  For linear damping (``h = -x'``, ``Gamma = -I``)
``f = exp(-mu E/D) = exp(-E/kT)`` with ``kT = D/mu``: the Boltzmann distribution,
exactly, which is the check.

References
----------
R. L. Stratonovich, *Topics in the Theory of Random Noise*, vol. 2 (1967);
R. Z. Khasminskii, Theory Probab. Appl. 11 (1966) 390; M. I. Freidlin and
A. D. Wentzell, *Random Perturbations of Hamiltonian Systems*, Mem. AMS 523 (1994),
chapter 8 (energy on the graph, gluing conditions); P. Hanggi, P. Talkner and
M. Borkovec, Rev. Mod. Phys. 62 (1990) 251, section IV.A (energy diffusion).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from kbm.conservative import ConservativeSplit, split_conservative
from kbm.errors import ModelError, ParameterError

from ..energy.portrait import Annulus, Portrait, phase_portrait
from ._orbits import graded_orbit_integrals, interior_saddles
from ._panels import Piecewise, adaptive_panels, gauss_on
from .noise_params import NoStationaryState, check_mu, noise_level

__all__ = ["EnergyEnvelope", "AnnulusEnvelope", "energy_envelope", "origin_well_envelope",
           "noise_level",
           "boltzmann_moment", "NoStationaryState", "check_mu"]


def _integrands(h):
    """Half-orbit integrands (see :meth:`Annulus.orbit_integrals`): ``T``, ``I``,
    ``Gamma``, ``K = oint x^2 x' dx`` (``dK/dE = oint x^2 dt``)."""
    return [lambda x, v, sq: 2.0 / sq,
            lambda x, v, sq: 2.0 * v * v / sq,
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
    period_ : callable
        ``T(E)`` by orbit quadrature (logarithmic at a separatrix: never integrated).
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
    period_: object
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


@dataclass(frozen=True, eq=False)
class EnergyEnvelope:
    """Energy-envelope averaging of a noisy model on every period annulus.

    Attributes
    ----------
    split : kbm.conservative.ConservativeSplit
    portrait : numerics.energy.portrait.Portrait
    D : float
        The noise intensity.
    pieces : tuple of AnnulusEnvelope
        One per annulus, in the portrait's order.
    complete : bool
        ``False`` for :func:`origin_well_envelope`: the well at the origin alone (its
        ``ln f`` is 0 at the bottom), which the escape's MFPT needs; the stationary
        density's normalisation and moments then refuse.

    Notes
    -----
    Every integral over ``E`` is done by parts, ``int T f dE = [I f] - int I f' dE`` with
    ``I f' = (mu/D) Gamma f``, so that only ``I``, ``Gamma`` and ``K`` (continuous at a
    separatrix) enter, on the panels of their interpolants.  For linear damping the sum
    over the annuli of the boundary terms telescopes (``I`` of the annulus above a
    separatrix is the sum of the actions of the annuli below) and the result is the
    phase-space integral of ``exp(-H/kT)``: Boltzmann, to the interpolants' 1e-12.
    """

    split: ConservativeSplit
    portrait: Portrait
    D: float
    pieces: tuple
    complete: bool = True

    def __repr__(self) -> str:
        return (f"EnergyEnvelope({self.split.model.name}, D={self.D:g}, "
                f"{len(self.pieces)} annuli)")

    @property
    def mu(self) -> float:
        return float(self.split.mu)

    def piece(self, label: str = "central well") -> AnnulusEnvelope:
        """The annulus with this label (default: the well at the origin)."""
        for p in self.pieces:
            if p.annulus.label == label:
                return p
        raise ModelError(f"no annulus labelled {label!r}; the annuli are "
                         f"{[p.annulus.label for p in self.pieces]}")

    def drift(self, E, label: str = "central well") -> np.ndarray:
        """Ito drift ``b(E) = [mu Gamma + D T]/T`` of the averaged energy."""
        p = self.piece(label)
        T = p.annulus.period(np.atleast_1d(np.asarray(E, float)))
        return (self.mu * p.gamma(E) + self.D * T) / T

    def diffusion(self, E, label: str = "central well") -> np.ndarray:
        """``sigma**2(E) = 2 D I(E)/T(E)`` of the averaged energy."""
        p = self.piece(label)
        T = p.annulus.period(np.atleast_1d(np.asarray(E, float)))
        return 2 * self.D * p.action(E) / T

    def _by_parts(self, p: AnnulusEnvelope, F, a: float, b: float) -> float:
        """``int_a^b f dF/dE dE = [F f]_a^b - (mu/D) int_a^b F Gamma f / I dE``."""
        E, w = p.rule(a, b)
        f = np.exp(p.log_f(E))
        return p.boundary(F, a, b) - self.mu / self.D * float(
            np.sum(w * F(E) * p.gamma(E) / p.action(E) * f))

    def partition(self) -> float:
        """``Z = sum_k int T_k(E) f_k(E) dE``, the normalisation of the stationary density
        (integrated by parts, ``[I f] - (mu/D) int Gamma f dE``: no log singularity enters)."""
        if not self.complete:
            raise ModelError("this envelope holds the well at the origin only (the escape's, "
                             "origin_well_envelope): the stationary density needs every "
                             "annulus; build it with energy_envelope")
        total = 0.0
        for p in self.pieces:
            E, w = p.rule()
            total += p.boundary(p.action, p.lo, p.hi) - self.mu / self.D * float(
                np.sum(w * p.gamma(E) * np.exp(p.log_f(E))))
        return total

    def stationary_moment_v2(self) -> float:
        """Stationary ``<x'^2>``: ``sum_k int f_k(E) I_k(E) dE / Z`` (``oint x'^2 dt = oint x'
        dx = I``; for linear damping it is ``kT``, equipartition)."""
        num = 0.0
        for p in self.pieces:
            E, w = p.rule()
            num += float(np.sum(w * p.action(E) * np.exp(p.log_f(E))))
        return num / self.partition()

    def energy_bins(self, edges) -> np.ndarray:
        """The stationary density of ``E = x'^2/2 + G(x)`` averaged over each bin of ``edges``:
        ``sum_k int_bin T_k f_k dE / (Z width)``, by parts on each bin (``T = dI/dE``)."""
        edges = np.asarray(edges, float)
        out = np.zeros(edges.size - 1)
        for p in self.pieces:
            a = np.clip(edges[:-1], p.lo, p.hi)
            b = np.clip(edges[1:], p.lo, p.hi)
            for j in np.nonzero(b > a)[0]:
                out[j] += self._by_parts(p, p.action, float(a[j]), float(b[j]))
        return out / (self.partition() * np.diff(edges))

    def stationary_moment_x2(self) -> float:
        """Stationary ``<x^2>`` from the averaged density on the whole graph of annuli:
        ``sum_k int f_k(E) oint_k x^2 dt dE / sum_k int f_k(E) T_k(E) dE``.

        Both are integrated by parts, ``int T f dE = [I f] - int I f' dE`` and likewise
        with ``K`` for ``oint x^2 dt = dK/dE``, so that the logarithmic singularities of
        ``T`` and ``oint x^2 dt`` at the separatrices never enter a quadrature.
        """
        num = sum(self._by_parts(p, p.x2action, p.lo, p.hi) for p in self.pieces)
        return num / self.partition()


def _orbit_values(annulus: Annulus, saddles, h, mu: float, D: float):
    """``E -> [I, Gamma, K, (mu/D) Gamma/I]`` by the spectral orbit quadrature (graded
    Gauss-Legendre when the orbits pass over ``saddles``), and the largest quadrature
    error met (a one-element list, updated)."""
    worst = [0.0]

    def values(E):
        if len(saddles):
            I, Gam, K = graded_orbit_integrals(annulus, saddles, E, _integrands(h)[1:])
        else:
            vals, err, _, _ = annulus.orbit_integrals(E, _integrands(h)[1:], tol=1e-13)
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


def energy_envelope(model, params: dict, D: object, *, tol: float = 1e-12,
                    outer_span: float = 40.0) -> EnergyEnvelope:
    """Energy-envelope averaging of ``model`` with noise ``sqrt(2 D) xi``.

    Parameters
    ----------
    model : str or kbm.models.Oscillator
        An autonomous model (the sliders at ``v = 0``).
    params : dict
        Its parameters, ``mu`` included (``D`` is taken apart if present).
    D : float
        Noise intensity, ``> 0``.
    tol : float
        Relative tolerance of the piecewise interpolants of the orbit integrals.
    outer_span : float
        The outer annulus is cut at ``E_min + outer_span * D/mu`` (``outer_span``
        thermal energies for linear damping; the density is ``exp(-40)`` there).

    Returns
    -------
    EnergyEnvelope

    Raises
    ------
    kbm.errors.ParameterError
        ``D <= 0`` or not finite, ``mu <= 0``.
    kbm.errors.ModelError
        A driven or non-confining model.
    """
    split, portrait, h, mu, D = _prepared(model, params, D, outer_span)
    built = {id(a): _fitted(a, portrait, h, mu, D, outer_span, tol) for a in portrait.annuli}
    # ln f' = mu Gamma/(D I) on each annulus, glued continuously at the vertices
    pieces = {}

    def place(a, value_at, at_top):
        _, lo, hi, I, Gam, K, L, err = built[id(a)]
        shift = value_at - float(L(hi) if at_top else L(lo))
        pieces[id(a)] = AnnulusEnvelope(a, lo, hi, I, Gam, K, a.period, L + shift, err)
        for child in portrait.annuli:
            if child is not a and child.bounded and abs(child.energy_max - lo) <= 1e-9 * (
                    1 + abs(lo)) and set(child.wells) <= set(a.wells):
                place(child, float((L + shift)(lo)), True)

    top = built[id(portrait.outer)]
    _check_drift(float(top[6].deriv()(top[2])), top[2])
    place(portrait.outer, 0.0, False)
    ordered = tuple(pieces[id(a)] for a in portrait.annuli if id(a) in pieces)
    return EnergyEnvelope(split, portrait, D, ordered)


def origin_well_envelope(model, params: dict, D: object, *, tol: float = 1e-12,
                         outer_span: float = 40.0) -> EnergyEnvelope:
    """The envelope of :func:`energy_envelope` on the well at the origin alone: what the
    mean first-passage time over its barrier needs (:func:`numerics.escape.rate.
    averaged_escape` uses differences of ``ln f`` inside the well only, so the gluing to
    the other annuli drops out; ``ln f`` is 0 at the bottom here).  The same checks as
    :func:`energy_envelope` (the outer annulus' drift at its top from one orbit
    quadrature), the same interpolants of the well's orbit integrals; the other annuli
    (the bands over the saddles, the costly ones: 2.3 of 2.5 s for the CDC at Delta = 3)
    are not built.  Without a bounded well at the origin it is :func:`energy_envelope`
    (which :func:`numerics.escape.rate.central_well` then explains).

    Returns
    -------
    EnergyEnvelope
        ``complete`` False: its :meth:`~EnergyEnvelope.partition` and moments refuse.
    """
    split, portrait, h, mu, D = _prepared(model, params, D, outer_span)
    well = [a for a in portrait.annuli if a.bounded and len(a.wells) == 1
            and round(a.wells[0], 9) == 0.0]
    if not well:
        return energy_envelope(model, params, D, tol=tol, outer_span=outer_span)
    outer = portrait.outer
    top = outer.energy_min + outer_span * D / mu
    values, _ = _orbit_values(outer, interior_saddles(outer, portrait.equilibria), h, mu, D)
    _check_drift(float(np.ravel(values(np.array([top]))[3])[0]), top)
    a, lo, hi, I, Gam, K, L, err = _fitted(well[0], portrait, h, mu, D, outer_span, tol)
    piece = AnnulusEnvelope(a, lo, hi, I, Gam, K, a.period, L, err)
    return EnergyEnvelope(split, portrait, D, (piece,), complete=False)


def _prepared(model, params: dict, D: object, outer_span: float) -> tuple:
    """``(split, portrait, h, mu, D)`` after the checks of :func:`energy_envelope`."""
    D = noise_level(D)
    if D == 0:
        raise ParameterError("D = 0: the averaged energy process needs noise; give D > 0")
    params = {k: v for k, v in dict(params).items() if k != "D"}
    split = split_conservative(model, params)
    if split.conservative:
        raise NoStationaryState("the model has no damping (h = 0): with noise its energy grows "
                         "without bound and there is no stationary state")
    mu = float(split.mu)
    if not mu > 0:
        raise ParameterError(f"mu = {mu:g}: the small parameter of x'' = -g(x) + mu h must "
                             "be > 0 (mu <= 0 turns the damping into a drive); give mu > 0")
    portrait = phase_portrait(split)
    h = split.numpy_functions()[3]
    _check_outer_cost(split, portrait, portrait.outer.energy_min + outer_span * D / mu, D / mu)
    return split, portrait, h, mu, D


def _fitted(a: Annulus, portrait: Portrait, h, mu: float, D: float, outer_span: float,
            tol: float) -> tuple:
    """``(annulus, lo, hi, I, Gamma, K, ln f, error)`` of one annulus: the interpolants of
    its orbit integrals on adaptive panels, ``ln f`` 0 at ``lo``."""
    lo = a.energy_min
    hi = a.energy_max if a.bounded else lo + outer_span * D / mu
    values, worst = _orbit_values(a, interior_saddles(a, portrait.equilibria), h, mu, D)
    breaks, (I, Gam, K, r) = adaptive_panels(
        values, lo, hi, singular_lo=len(a.wells) > 1, singular_hi=a.bounded, tol=tol)
    return (a, lo, hi, Piecewise(breaks, I), Piecewise(breaks, Gam),
            Piecewise(breaks, K), Piecewise(breaks, r).integ(), worst[0])


def _check_drift(rate: float, E: float) -> None:
    """Refuse a positive ``mu Gamma/(D I)`` at the outer annulus' top energy ``E``."""
    if not rate < 0:
        raise NoStationaryState(
            f"no stationary state: the averaged energy drift mu Gamma(E)/T(E) is not negative "
            f"at large energy (mu Gamma/(D I) = {rate:.3g} at E = "
            f"{E:.4g}): the damping feeds energy in and the noise is not balanced; "
            "choose parameters whose damping is positive at large amplitude")


def boltzmann_moment(split: ConservativeSplit, kT: float, power: int = 2) -> float:
    """``<x**power>`` of the Boltzmann density ``exp(-G(x)/kT)`` by adaptive quadrature.

    Independent of any averaging: the exact stationary density of
    ``x'' + mu x' + g(x) = sqrt(2 D) xi`` with ``kT = D/mu`` (Gibbs; Risken,
    *The Fokker-Planck Equation*, section 10.1).
    """
    from scipy.integrate import quad

    G = split.numpy_functions()[2]
    # the confining part dominates: integrate to where G/kT exceeds 60
    L = 1.0
    while float(G(np.array(L))) / kT < 60 or float(G(np.array(-L))) / kT < 60:
        L *= 1.5
    Gmin = min(float(G(np.array(z))) for z in np.linspace(-L, L, 2001))

    def w(z):
        return math.exp(-(float(G(np.array(z))) - Gmin) / kT)

    num = quad(lambda z: z**power * w(z), -L, L, limit=400, epsabs=0, epsrel=1e-11)[0]
    den = quad(w, -L, L, limit=400, epsabs=0, epsrel=1e-11)[0]
    return num / den
