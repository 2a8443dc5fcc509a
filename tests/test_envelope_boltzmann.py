"""The energy-envelope density is the Boltzmann density for linear damping, to 1e-8, at any
potential and temperature (issue 36, finding 1).

For ``x'' + c mu x' + g(x) = sqrt(2 D) xi`` the stationary density is ``exp(-H/kT)``,
``kT = D/(c mu)`` (Gibbs; Risken, *The Fokker-Planck Equation*, sec. 10.1), whatever the
potential.  The references here owe nothing to the envelope: ``<x^2>`` by adaptive
quadrature of ``x^2 exp(-G/kT)``, and the mass below an energy ``E``,
``M(E) = sqrt(2 pi kT) int exp(-G/kT) erf(sqrt((E - G)_+ / kT)) dx``, by adaptive
quadrature with the turning points ``G(x) = E`` as break points.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from scipy.integrate import quad
from scipy.optimize import brentq
from scipy.special import erf

from kbm.model.builtins import Oscillator
from kbm.symbols import x, xdot
from numerics.escape import boltzmann_moment, energy_envelope


def _mass_below(G, E, kT, L):
    """``int exp(-G/kT) sqrt(2 pi kT) erf(sqrt((E-G)_+/kT)) dx`` over ``[-L, L]``."""
    grid = np.linspace(-L, L, 4001)
    d = G(grid) - E
    roots = [brentq(lambda z: float(G(np.array(z))) - E, grid[i], grid[i + 1], xtol=1e-15)
             for i in np.nonzero(np.sign(d[:-1]) * np.sign(d[1:]) < 0)[0]]

    def f(z):
        Gz = float(G(np.array(z)))
        return math.exp(-Gz / kT) * math.erf(math.sqrt(max(E - Gz, 0.0) / kT))

    pts = [-L] + roots + [L]
    return math.sqrt(2 * math.pi * kT) * sum(
        quad(f, a, b, limit=400, epsabs=0, epsrel=1e-12)[0] for a, b in zip(pts[:-1], pts[1:]))


def _check(model, params, kT):
    mu = float(params["mu"])
    env = energy_envelope(model, params, kT * mu)
    split = env.split
    G = split.numpy_functions()[2]
    ref_x2 = boltzmann_moment(split, kT)
    assert env.stationary_moment_x2() == pytest.approx(ref_x2, rel=1e-8, abs=1e-12)
    assert env.stationary_moment_v2() == pytest.approx(kT, rel=1e-8)   # equipartition
    L = 1.0
    while float(G(np.array(L))) / kT < 60 or float(G(np.array(-L))) / kT < 60:
        L *= 1.5
    top = min(p.lo for p in env.pieces) + 12 * kT
    seps = [p.hi for p in env.pieces if p.annulus.bounded]
    edges = np.unique(np.concatenate([np.linspace(0, top, 13), seps]))
    edges = edges[edges <= top]
    Z = _mass_below(G, 60 * kT + max(seps, default=0.0), kT, L)
    M = np.array([_mass_below(G, e, kT, L) for e in edges]) / Z
    ref = np.diff(M) / np.diff(edges)
    got = env.energy_bins(edges)
    assert np.max(np.abs(got - ref)) <= 1e-8 * np.max(ref)


def test_issue_case_cdc_at_rest():
    """The case of issue 36: CDC at rest, mu = 0.15, Delta = 2, lam = 1.3, Omega = 1,
    D = 0.09 (kT = 0.6); <x^2> = 0.5950454 (was 0.592332, -0.46 %), and the energy bins
    on both sides of the separatrix (the near-inflection at x ~ 2.25 included)."""
    _check("cdc", {"mu": 0.15, "Delta": 2, "lam": 1.3, "Omega": 1}, 0.6)


_c = sp.Symbol("c")
_k = sp.Symbol("k")
_b = sp.Symbol("b")
QUARTIC = Oscillator("quartic_cosine", -xdot - _c * x**3 - _b * sp.sin(_k * x),
                     description="x'' + mu x' + x + mu c x^3 + mu b sin(k x) = 0 (a test "
                                 "potential with several wells and near-inflections)")


@pytest.mark.slow
@settings(max_examples=8, deadline=None,
          suppress_health_check=[HealthCheck.too_slow])
@given(Delta=st.floats(0.2, 4.0), lam=st.floats(0.7, 2.5), Omega=st.floats(0.6, 1.5),
       kT=st.floats(0.08, 2.0))
def test_cdc_envelope_is_boltzmann(Delta, lam, Omega, kT):
    """CDC (paper eq. 12) at rest: any Delta, lam, Omega, temperature."""
    _check("cdc", {"mu": 0.1, "Delta": Delta, "lam": lam, "Omega": Omega}, kT)


@pytest.mark.slow
@settings(max_examples=6, deadline=None,
          suppress_health_check=[HealthCheck.too_slow])
@given(c=st.floats(0.05, 5.0), b=st.floats(0.0, 15.0), k=st.floats(0.5, 4.0),
       kT=st.floats(0.1, 2.0))
def test_quartic_envelope_is_boltzmann(c, b, k, kT):
    """``G = x^2/2 + mu c x^4/4 + mu b (1 - cos k x)/k``: single and multiple wells."""
    _check(QUARTIC, {"mu": 0.2, "c": c, "b": b, "k": k}, kT)


def test_noise_that_dwarfs_the_barriers_is_refused_with_the_numbers():
    """CDC, mu = 0.1, Delta = 3, lam = 1.3, D = 100 (D/mu = 1000, 234 barrier heights):
    the top orbit of the outer annulus (E = 40 D/mu) crosses 2 (x+ - x-)/lam inflections of
    G = x^2/2 - (Delta/k) cos(k x) (the zeros of G'' = 1 + Delta k cos(k x), counted in
    closed form); that is above the limit, so the envelope is refused in seconds with the
    numbers instead of minutes of orbit quadratures."""
    import re
    import time

    from kbm.errors import ModelError
    from numerics.escape.envelope import MAX_INFLECTIONS

    Delta, lam, mu, D = 3.0, 1.3, 0.1, 100.0
    k = 2 * math.pi / lam
    t0 = time.perf_counter()
    with pytest.raises(ModelError, match=r"D/mu = 1000 .* inflections of G") as err:
        energy_envelope("cdc", {"mu": mu, "Delta": Delta, "lam": lam, "Omega": 1}, D)
    assert time.perf_counter() - t0 < 30
    got = int(re.search(r"across (\d+) inflections", str(err.value)).group(1))
    E = float(re.search(r"at E = ([0-9.e+]+)", str(err.value)).group(1))
    xp = brentq(lambda z: z * z / 2 - Delta / k * math.cos(k * z) - E, 1.0, 1e4)
    phi = math.acos(-1 / (Delta * k))  # zeros at k x = +-phi + 2 pi j
    zeros = sum(1 for s in (phi, -phi) for j in range(-2000, 2001)
                if abs((s + 2 * math.pi * j) / k) < xp)
    assert abs(got - zeros) <= 2 and got > MAX_INFLECTIONS
