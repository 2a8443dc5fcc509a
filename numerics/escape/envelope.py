"""Energy-envelope stochastic averaging about the conservative orbits.

The noisy model ``x'' = -g(x) + mu h(x, x') + sqrt(2 D) xi(t)`` (unit mass,
``<xi(t) xi(t')> = delta(t - t')``) is split as in :mod:`kbm.model.conservative`.  With
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
exactly, which is the check.  The checks of the model and the fits of one annulus's orbit
integrals are in :mod:`numerics.escape._annulus`.

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
from dataclasses import dataclass, replace

import numpy as np
from kbm.model.conservative import ConservativeSplit
from kbm.errors import ModelError

from ..energy.portrait import Portrait
from ._annulus import AnnulusEnvelope, check_drift, fitted, orbit_values, prepared
from ._orbits import interior_saddles

__all__ = ["EnergyEnvelope", "energy_envelope", "origin_well_envelope", "no_origin_well",
           "boltzmann_moment"]


@dataclass(frozen=True, eq=False)
class EnergyEnvelope:
    """Energy-envelope averaging of a noisy model on every period annulus.

    Attributes
    ----------
    split : kbm.model.conservative.ConservativeSplit
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
        ``sum_k int_bin T_k f_k dE / (Z width)``, by parts on each bin (``T = dI/dE``; the
        bins' rules evaluated together, each bin's sum as :meth:`_by_parts`'s)."""
        edges = np.asarray(edges, float)
        out = np.zeros(edges.size - 1)
        for p in self.pieces:
            a = np.clip(edges[:-1], p.lo, p.hi)
            b = np.clip(edges[1:], p.lo, p.hi)
            bins = np.nonzero(b > a)[0]
            if not bins.size:
                continue
            rules = [p.rule(float(a[j]), float(b[j])) for j in bins]
            E = np.concatenate([r[0] for r in rules])
            w = np.concatenate([r[1] for r in rules])
            ends = np.concatenate([a[bins], b[bins]])
            at = p.action(ends) * np.exp(p.log_f(ends))
            terms = w * p.action(E) * p.gamma(E) / p.action(E) * np.exp(p.log_f(E))
            cut = np.cumsum([0] + [r[0].size for r in rules])
            for i, j in enumerate(bins):
                out[j] += float(at[i + bins.size] - at[i]) - self.mu / self.D * float(
                    np.sum(terms[cut[i]:cut[i + 1]]))
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


def energy_envelope(model, params: dict, D: object, *, tol: float = 1e-12,
                    outer_span: float = 40.0) -> EnergyEnvelope:
    """Energy-envelope averaging of ``model`` with noise ``sqrt(2 D) xi``.

    Parameters
    ----------
    model : str or kbm.model.builtins.Oscillator
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
    split, portrait, h, mu, D = prepared(model, params, D, outer_span)
    built = {id(a): fitted(a, portrait, h, mu, D, outer_span, tol) for a in portrait.annuli}
    # ln f' = mu Gamma/(D I) on each annulus, glued continuously at the vertices
    pieces = {}

    def place(a, value_at, at_top):
        p = built[id(a)]
        lo = p.lo
        L = p.log_f + (value_at - float(p.log_f(p.hi if at_top else lo)))
        pieces[id(a)] = replace(p, log_f=L)
        for child in portrait.annuli:
            if child is not a and child.bounded and abs(child.energy_max - lo) <= 1e-9 * (
                    1 + abs(lo)) and set(child.wells) <= set(a.wells):
                place(child, float(L(lo)), True)

    top = built[id(portrait.outer)]
    check_drift(float(top.log_f.deriv()(top.hi)), top.hi)
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
    are not built.

    Raises
    ------
    kbm.errors.ModelError
        Without a bounded well at the origin, the reason of :func:`no_origin_well`, before
        any annulus is fitted; a growing energy as :func:`energy_envelope`.

    Returns
    -------
    EnergyEnvelope
        ``complete`` False: its :meth:`~EnergyEnvelope.partition` and moments refuse.
    """
    split, portrait, h, mu, D = prepared(model, params, D, outer_span)
    well = [a for a in portrait.annuli if a.bounded and len(a.wells) == 1
            and round(a.wells[0], 9) == 0.0]
    outer = portrait.outer
    top = outer.energy_min + outer_span * D / mu
    values, _ = orbit_values(outer, interior_saddles(outer, portrait.equilibria), h, mu, D)
    check_drift(float(np.ravel(values(np.array([top]))[3])[0]), top)
    if not well:  # before any annulus is fitted (the whole envelope took 6-7 s to say it)
        raise no_origin_well(portrait)
    piece = fitted(well[0], portrait, h, mu, D, outer_span, tol)
    return EnergyEnvelope(split, portrait, D, (piece,), complete=False)


def no_origin_well(portrait: Portrait) -> ModelError:
    """Why the phase portrait has no bounded well at the origin, in one line: no centre
    there, or the well around it reaches infinity (no barrier)."""
    if not [e for e in portrait.equilibria if e.kind == "center" and abs(e.x) < 1e-9]:
        return ModelError("the origin is not the bottom of a well (the potential's curvature "
                          "g'(0) there is <= 0): there is no well at the origin to escape "
                          "from; choose parameters with x = 0 a stable rest point (the "
                          "sliders: Delta >= 0 and lam > 0)")
    return ModelError("the well at the origin has no barrier (the potential has a single "
                      "well): nothing to escape over; choose parameters with side wells "
                      "(e.g. a larger Delta)")


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
