"""Energy-envelope stochastic averaging and the averaged escape rate (numerics.escape).

References: the Boltzmann distribution exp(-H/kT), kT = D/mu, is the exact stationary
density of x'' + mu x' + g(x) = sqrt(2 D) xi (Risken, The Fokker-Planck Equation, 10.1);
Kramers' low-friction rate (Hanggi, Talkner, Borkovec, RMP 62 (1990) 251, eq. 4.8);
the Mel'nikov-Meshkov depopulation factor (ibid. eq. 4.49).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.integrate import quad

from kbm.errors import KBMError, ModelError, ParameterError
from numerics.escape import (averaged_escape, boltzmann_moment, central_well, energy_envelope,
                             melnikov_meshkov_factor)
from numerics.escape.envelope import origin_well_envelope
from numerics.escape.noise_params import NoStationaryState

CDC = {"mu": 0.05, "Delta": 3, "lam": 1, "Omega": 1}


@pytest.fixture(scope="module")
def cdc_env():
    return energy_envelope("cdc", CDC, 0.05)   # kT = 1, about the barrier height 1.09


def test_cdc_log_density_is_boltzmann_on_every_annulus(cdc_env):
    """Linear damping: f(E) = exp(-E/kT) on every annulus, glued across the separatrices."""
    kT = 0.05 / 0.05
    c = None
    for p in cdc_env.pieces:
        E = np.linspace(p.lo, p.hi, 7)[1:-1]
        c = float(p.log_f(E[0]) + E[0] / kT) if c is None else c
        assert np.allclose(p.log_f(E) + E / kT, c, atol=2e-6), p.annulus.label


def test_cdc_averaged_x2_matches_boltzmann_quadrature(cdc_env):
    """<x^2> of the averaged density on the graph of annuli against the Boltzmann
    quadrature int x^2 exp(-G/kT) dx / int exp(-G/kT) dx (owes nothing to averaging),
    at kT about the barrier, several wells visited."""
    ref = boltzmann_moment(cdc_env.split, 1.0)
    assert ref > 0.5   # the side wells at |x| = 0.95, 1.89 are populated
    assert cdc_env.stationary_moment_x2() == pytest.approx(ref, rel=1e-3)


def test_cdc_energy_density_is_density_of_states(cdc_env):
    """The averaged density of E on the central well is T(E) exp(-E/kT)/Z: its drift and
    diffusion satisfy the zero-flux condition b p = (sigma^2 p)'/2 with p = T exp(-E/kT)."""
    p = central_well(cdc_env)
    E = np.linspace(p.lo, p.hi, 9)[2:-2]
    h = 1e-3   # central difference: O(h^2); the Chebyshev I(E) is good to ~1e-5
    b = cdc_env.drift(E)

    def s2p(e):
        return cdc_env.diffusion(e) * p.annulus.period(e) * np.exp(-e)

    flux = b * p.annulus.period(E) * np.exp(-E) - (s2p(E + h) - s2p(E - h)) / (4 * h)
    assert np.max(np.abs(flux)) < 1e-4 * np.max(b * p.annulus.period(E) * np.exp(-E))


def _mfpt_direct(env):
    """Gardiner's double integral with T(E) itself (a second route to tau)."""
    p = central_well(env)
    E0, Eb, D, kT = p.lo, p.hi, env.D, env.D / env.mu
    T = lambda z: float(p.annulus.period(np.array([z]))[0])  # noqa: E731
    I = lambda z: float(p.action(z))  # noqa: E731
    inner = lambda y: quad(lambda z: T(z) * math.exp(-(z - y) / kT), E0, y, limit=200)[0]  # noqa: E731
    return quad(lambda y: inner(y) / (D * I(y)), E0, Eb, limit=200, epsrel=1e-8)[0]


@pytest.mark.slow
@pytest.mark.parametrize("build", [energy_envelope, origin_well_envelope])
def test_mfpt_two_routes(build):
    """tau from the integrated-by-parts form equals the textbook double integral
    int dy/(sigma^2 p) 2 int p dz (Gardiner, Handbook, 5.2.158) with p = T exp(-E/kT)
    (on the whole graph of annuli and on the well at the origin alone)."""
    env = build("cdc", CDC, 0.05 * 1.087 / 4)
    tau = averaged_escape(env).mfpt
    assert tau == pytest.approx(_mfpt_direct(env), rel=1e-5)


def test_averaged_rate_tends_to_kramers():
    """As E_b/kT -> inf the averaged rate tends to Kramers' low-friction rate (HTB eq. 4.8),
    with a relative difference shrinking like kT/E_b."""
    gaps = []
    for r in (10, 20, 40):
        D = 0.05 * 1.0873 / r
        e = averaged_escape(energy_envelope("cdc", CDC, D))
        gaps.append(abs(e.rate_averaged / e.rate_kramers - 1) * r)
    assert gaps[2] < 0.06 * 40   # within 6 % at E_b/kT = 40
    assert gaps[0] < 10 and gaps[1] < 10 and gaps[2] < 10   # O(kT/E_b), bounded coefficient


@settings(max_examples=15, deadline=None)
@given(st.floats(1e-4, 1e-2))
def test_melnikov_meshkov_small_delta(delta):
    """A(delta) -> delta as delta -> 0, with A(delta)/delta < 1 (HTB eq. 4.49, 4.50)."""
    a = melnikov_meshkov_factor(delta)
    assert a < delta
    assert a / delta > 1 - 2 * math.sqrt(delta)


def test_melnikov_meshkov_large_delta():
    """A(delta) -> 1 as delta -> inf (the transition-state limit)."""
    assert melnikov_meshkov_factor(40.0) == pytest.approx(1.0, abs=1e-3)


@pytest.mark.parametrize("D", [-0.1, float("nan"), float("inf"), "x", 0])
def test_bad_noise(D):
    with pytest.raises(ParameterError):
        energy_envelope("cdc", CDC, D)


def test_no_well_refused():
    """A single-well potential has no barrier: refused with the reason."""
    env = energy_envelope("cdc", {**CDC, "Delta": 0.1}, 0.01)
    with pytest.raises(ModelError, match="no barrier"):
        averaged_escape(env)


def test_driven_refused():
    with pytest.raises(KBMError):
        energy_envelope("cdc", {**CDC, "v": 0.1}, 0.01)


@pytest.mark.parametrize("model, params, D", [
    pytest.param("cdc", {"mu": 0.02, "Delta": 3, "lam": 1, "Omega": 1}, 0.007,
                 marks=pytest.mark.slow),
    ("cdc", {"mu": 0.02, "Delta": 2, "lam": 1.3, "Omega": 1}, 0.003),
    ("sedf", {"mu": 0.1, "Delta": 3, "beta": 1, "lam": 1, "Omega": 1}, 0.05)])
def test_origin_well_envelope_gives_the_same_mfpt(model, params, D):
    """The MFPT (Gardiner 5.2.158) uses ln f inside the well only, so the well at the origin
    alone gives the rate of the whole glued envelope (to rounding), and the same Kramers
    and Mel'nikov-Meshkov rates; its stationary density refuses (one annulus only)."""
    whole = averaged_escape(energy_envelope(model, params, D))
    env = origin_well_envelope(model, params, D)
    alone = averaged_escape(env)
    assert len(env.pieces) == 1 and not env.complete
    assert alone.rate_averaged == pytest.approx(whole.rate_averaged, rel=1e-13)
    assert (alone.barrier, alone.saddles, alone.action) == (whole.barrier, whole.saddles,
                                                            whole.action)
    assert alone.rate_melnikov == whole.rate_melnikov
    with pytest.raises(ModelError, match="well at the origin only"):
        env.stationary_moment_x2()


def test_no_well_at_the_origin_is_refused_before_any_annulus_is_fitted(monkeypatch):
    """``kbm escape cdc -p Delta=-3`` (g'(0) = 1 - 2 pi Delta/lam < 0: the origin a saddle,
    paper eq. 12's potential) and ``-p Delta=0.1`` (a single well, no barrier): the reason
    comes from the phase portrait, before the envelope's annuli are fitted (on e8c4642 the
    whole envelope was built first, 6-7 s, to say it)."""
    import numerics.escape.envelope as envelope

    def fail(*args, **kwargs):
        raise AssertionError("an annulus was fitted")

    monkeypatch.setattr(envelope, "fitted", fail)
    with pytest.raises(ModelError, match="not the bottom of a well"):
        envelope.origin_well_envelope("cdc", {**CDC, "Delta": -3}, 0.01)
    with pytest.raises(ModelError, match="no barrier"):
        envelope.origin_well_envelope("cdc", {**CDC, "Delta": 0.1}, 0.01)


def test_origin_well_envelope_refuses_as_the_whole_one():
    """No well at the origin: the same reason; growing energy: no stationary state (the
    outer annulus' drift at its top, from one orbit quadrature)."""
    with pytest.raises(ModelError, match="no barrier"):
        averaged_escape(origin_well_envelope("cdc", {**CDC, "Delta": 0.1}, 0.01))
    bad = {"mu": 0.1, "Delta": 2, "beta": -1, "lam": 1, "Omega": 1}
    with pytest.raises(NoStationaryState) as whole:
        energy_envelope("sedf", bad, 0.01)
    with pytest.raises(NoStationaryState) as alone:
        origin_well_envelope("sedf", bad, 0.01)
    assert str(alone.value).split("=")[0] == str(whole.value).split("=")[0]
