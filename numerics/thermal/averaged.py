"""Averaged stationary predictions of a noisy model, put in the form of the simulation.

Two averaging methods apply to the autonomous models:

* **amplitude averaging** (first-order Stratonovich-Khasminskii, :mod:`kbm.noise.stochastic`)
  for ``x'' + omega0^2 x = mu F + sqrt(2 D) xi`` with ``D`` of order ``mu``: the
  stationary amplitude density ``P(a)``; ``<a^2>`` and ``<x^2> = <a^2>/2`` (the phase
  is uniform);
* **energy-envelope averaging** (:mod:`numerics.escape.envelope`) about the
  conservative orbits, for the strong periodic potential of the sliders (sedf, cdc at
  ``v = 0``): the stationary density of ``E`` on the graph of period annuli,
  ``<x^2>`` and ``<x'^2>``.

A driven slider (``v != 0``) has no averaged stationary state here: its prediction is
``None`` with the reason.  For linear damping the Boltzmann moment ``<x^2>`` of
``exp(-G/kT)`` by quadrature is given too: exact, owing nothing to averaging.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from kbm.errors import KBMError, ModelError
from kbm.model.builtins import SLIDERS

from ..escape.noise_params import NoStationaryState

__all__ = ["AveragedStationary", "averaged_stationary", "AMPLITUDE", "ENERGY"]

AMPLITUDE = "amplitude averaging (Stratonovich-Khasminskii, first order)"
ENERGY = "energy-envelope averaging (Stratonovich-Khasminskii, Freidlin-Wentzell)"


@dataclass(frozen=True, eq=False)
class AveragedStationary:
    """The averaged stationary state.

    Attributes
    ----------
    method : str
        Which averaging (:data:`AMPLITUDE` or :data:`ENERGY`).
    variable : str
        ``"a"`` (amplitude) or ``"E"`` (energy): the variable of :meth:`bins`.
    x2, a2 : float
        ``<x^2>`` and ``<x^2 + (x'/omega0)^2>``.
    boltzmann_x2 : float or None
        ``<x^2>`` of the Boltzmann density (linear damping only).
    support : (float, float)
        Where the density lives (its mass outside is below 1e-4 on each side).
    bins : callable
        ``bins(edges)``: the density averaged over each bin.
    """

    method: str
    variable: str
    x2: float
    a2: float
    boltzmann_x2: float | None
    support: tuple
    bins: Callable

    def __repr__(self) -> str:
        return (f"AveragedStationary({self.method}: <x^2> = {self.x2:.6g}, <a^2> = "
                f"{self.a2:.6g})")


def _amplitude(model, params: dict, D: float) -> AveragedStationary:
    from kbm.noise.stochastic import stochastic_average

    sa = stochastic_average(model, params)
    name = model if isinstance(model, str) else model.name
    if sa.log_density is None and not sa.reason.startswith("the integral of A_1"):
        raise NoStationaryState(f"{name} has no stationary state with noise: {sa.reason} "
                                "(first-order averaging); add damping, e.g. a positive "
                                "zeta or mu")
    vals = dict(params, D=D)
    try:
        a2 = float(sa.moment(2, vals))
    except ModelError as exc:
        raise NoStationaryState(f"{name}: no averaged stationary state at these values: "
                                f"{exc}") from None
    # the support: where P(a) is above 1e-12 of its largest value on a wide grid
    hi = 4.0 * math.sqrt(a2) + 1.0
    grid = np.linspace(0.0, hi, 4001)
    dens = np.asarray(sa.density(grid, vals), float)
    cdf = np.cumsum(dens) * (grid[1] - grid[0])
    top = float(grid[min(np.searchsorted(cdf, 1 - 1e-4) + 1, grid.size - 1)])
    lo = float(grid[max(np.searchsorted(cdf, 1e-4) - 1, 0)])

    def bins(edges):
        # every bin's 16 Gauss-Legendre nodes in one call: the density's support and
        # normalisation are found once, not once a bin
        edges = np.asarray(edges, float)
        x, w = np.polynomial.legendre.leggauss(16)
        a = edges[:-1, None] + np.diff(edges)[:, None] * (x + 1) / 2
        dens = np.asarray(sa.density(a, vals), float)
        return np.array([np.sum(w * row) / 2 for row in dens])

    return AveragedStationary(AMPLITUDE, "a", a2 / 2, a2, _boltzmann(model, params, D),
                              (lo, top), bins)


def _energy(model, params: dict, D: float, omega0: float) -> AveragedStationary:
    from kbm.model.conservative import NotConfiningError
    from numerics.escape.envelope import energy_envelope

    try:
        env = energy_envelope(model, params, D)
    except NotConfiningError as exc:
        raise NoStationaryState(f"{model} has no stationary state: {exc}") from None
    x2 = env.stationary_moment_x2()
    v2 = env.stationary_moment_v2()
    lo = min(p.lo for p in env.pieces)
    hi = max(p.hi for p in env.pieces)
    grid = np.linspace(lo, hi, 2001)
    cdf = np.cumsum(env.energy_bins(grid) * np.diff(grid))
    top = float(grid[min(np.searchsorted(cdf, 1 - 1e-4) + 1, grid.size - 1)])
    return AveragedStationary(ENERGY, "E", x2, x2 + v2 / omega0**2,
                              _boltzmann(model, params, D), (lo, top), env.energy_bins)


def _boltzmann(model, params: dict, D: float) -> float | None:
    """``<x^2>`` of ``exp(-G/kT)`` when the damping is linear (``h = -c x'``, ``kT = D/(mu c)``)."""
    import sympy as sp

    from kbm.model.conservative import split_conservative
    from kbm.symbols import xdot

    from ..escape.envelope import boltzmann_moment

    try:
        split = split_conservative(model, params)
    except KBMError:
        return None
    c = sp.cancel(-split.h / xdot)
    if c.free_symbols and c.is_polynomial(*c.free_symbols):
        # a polynomial not constant (cancel's canonical form: the SEDF's beta x^2 - 1) stays
        # so; sp.simplify (which imports sympy.physics, 0.5 s) for the other forms
        return None
    c = sp.simplify(-split.h / xdot)
    if c.free_symbols or not c.is_number or not (c > 0) or split.mu <= 0:
        return None
    return boltzmann_moment(split, D / (float(split.mu) * float(c)))


def averaged_stationary(model, params: dict, D: float, omega0: float,
                        ) -> tuple[AveragedStationary | None, str]:
    """The averaged stationary state and the reason when there is none.

    Parameters
    ----------
    model : str or kbm.model.builtins.Oscillator
    params : dict
        Parameter values (``D`` apart).
    D : float
        Noise intensity (``> 0``).
    omega0 : float
        The linear frequency of ``a^2 = x^2 + (x'/omega0)^2``.

    Returns
    -------
    (AveragedStationary or None, str)
        The prediction, or ``None`` and why no averaging applies.
    """
    name = model if isinstance(model, str) else model.name
    if D == 0:
        return None, "D = 0: the deterministic model has no stationary density"
    v = params.get("v", 0)
    if name in SLIDERS and float(v) != 0:
        return None, (f"v = {v}: the driven slider is not autonomous; no averaged stationary "
                      "state (the simulation alone; its x follows the stage, x ~ v t, so the "
                      "simulated <x^2> and <a^2> grow with --t-end and the burn-in: no "
                      "stationary moments; the steady sliding state is kbm friction's)")
    try:
        if name in SLIDERS:
            return _energy(name, {k: val for k, val in params.items() if k != "v"}, D,
                           omega0), ""
        return _amplitude(model, params, D), ""
    except NoStationaryState:
        raise
    except KBMError as exc:
        return None, f"no averaged prediction: {exc}"
