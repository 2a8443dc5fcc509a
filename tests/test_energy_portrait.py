"""Conservative phase portrait of the energy averaging: periods, Gamma, equilibria, annuli.

Every reference is independent of the code under test: closed forms (elliptic
integrals, the harmonic oscillator, the van der Pol energy balance) and a
brute-force sign scan of g on a fine grid.
"""

import numpy as np
import pytest
import sympy as sp
from scipy.special import ellipk

from kbm.model.conservative import ConservativeSplit, NotConfiningError, split_conservative
from kbm.errors import ModelError, NonAutonomousError, ParameterError
from kbm.model.builtins import get_model
from kbm.symbols import x, xdot
from numerics.energy import Annulus, phase_portrait, sample_orbits
from numerics.energy.balance import harmonics

SEDF = {"mu": 0.1, "beta": 1, "lam": 1}


def test_linear_period_is_2pi_over_omega0():
    """T(E) = 2 pi/omega0 for every energy of g = omega0^2 x (harmonic oscillator)."""
    s = split_conservative("sedf", {**SEDF, "Delta": 0, "Omega": 2})
    p = phase_portrait(s)
    (a,) = p.annuli
    E = np.geomspace(1e-6, 1e6, 25)
    assert np.allclose(a.period(E), np.pi, rtol=1e-13, atol=0)


def test_pendulum_period_is_4K():
    """Pendulum g = sin x: T(E) = 4 K(m), m = E/2, on the libration annulus 0 < E < 2."""
    sp_split = ConservativeSplit(get_model("vdp"), sp.sin(x), sp.Integer(0), 1 - sp.cos(x), 0.1)
    fun = sp_split.numpy_functions()
    a = Annulus("pendulum well", 0.0, 2.0, (0.0,), (-np.pi, 0.0, 0.0, np.pi), fun)
    E = np.array([1e-4, 0.1, 0.5, 1.0, 1.5, 1.9, 1.99])
    q = a.quadrature(E)
    # G = 1 - cos x loses digits for small x (cancellation in the user's expression)
    assert np.allclose(q.period[1:], 4 * ellipk(E[1:] / 2), rtol=1e-12, atol=0)
    assert q.period[0] == pytest.approx(4 * ellipk(E[0] / 2), rel=1e-9)
    xm, xp = a.turning_points(E)
    assert np.allclose(xp, np.arccos(1 - E), rtol=1e-12)
    assert np.allclose(xm, -xp, rtol=1e-13)


def test_duffing_period_elliptic():
    """Duffing g = x + x^3 (model duffing, mu = 1): T = 4 K(m)/sqrt(1 + A^2), m = A^2/(2(1 + A^2))."""
    s = split_conservative("duffing", {"mu": 1})
    (a,) = phase_portrait(s).annuli
    A = np.array([0.01, 0.3, 1.0, 2.5, 10.0])
    E = A**2 / 2 + A**4 / 4
    m = A**2 / (2 * (1 + A**2))
    assert np.allclose(a.period(E), 4 * ellipk(m) / np.sqrt(1 + A**2), rtol=1e-12, atol=0)
    assert np.allclose(a.turning_points(E)[1], A, rtol=1e-13)


def test_gamma_van_der_pol_closed_form():
    """g = x, h = (1 - x^2) v: Gamma(E) = pi omega A^2 (1 - A^2/4), A = sqrt(2E)/omega."""
    s = split_conservative("vdp", {"mu": 0.3})
    (a,) = phase_portrait(s).annuli
    E = np.geomspace(1e-3, 1e3, 13)
    A = np.sqrt(2 * E)
    q = a.quadrature(E, gamma=True)
    assert np.allclose(q.gamma, np.pi * A**2 * (1 - A**2 / 4), rtol=1e-12, atol=1e-12)


def test_sampled_orbit_and_harmonics_of_linear_oscillator():
    """g = omega0^2 x: X(E, theta) = A cos theta, V = -omega0 A sin theta; harmonics c_1 = A/2."""
    s = split_conservative("sedf", {**SEDF, "Delta": 0, "Omega": 1.5})
    (a,) = phase_portrait(s).annuli
    E = np.array([0.5, 2.0])
    A = np.sqrt(2 * E) / 1.5
    o = sample_orbits(a, E, 64)
    assert np.allclose(o.X, A[:, None] * np.cos(o.theta), atol=1e-11)
    assert np.allclose(o.V, -1.5 * A[:, None] * np.sin(o.theta), atol=1e-11)
    c = harmonics(a, E, 4)
    assert np.allclose(c[:, 1], A / 2, rtol=1e-12)
    assert np.allclose(c[:, [0, 2, 3]], 0, atol=1e-12)


def _brute_force_zeros(D):
    """Sign changes of g = x + Delta sin(2 pi x) on a 2e6-point grid (independent scan)."""
    xs = -10 + (np.arange(2_000_001) + 1 / np.pi) * 1e-5  # no grid point on a zero
    g = xs + D * np.sin(2 * np.pi * xs)
    i = np.nonzero(np.sign(g[:-1]) != np.sign(g[1:]))[0]
    zeros = 0.5 * (xs[i] + xs[i + 1])
    kinds = np.where(g[i + 1] > g[i], "center", "saddle")
    return zeros, kinds


@pytest.mark.parametrize("D", [1.5, 3.0])
def test_sedf_equilibria_and_annuli(D):
    """Equilibria of sedf (Delta = 1.5, 3) equal a brute-force sign scan of g; the annuli form
    the merge tree: one per center, one band per distinct saddle level, one outer."""
    p = phase_portrait(split_conservative("sedf", {**SEDF, "Delta": D}))
    zeros, kinds = _brute_force_zeros(D)
    xs = np.array([e.x for e in p.equilibria])
    assert len(xs) == len(zeros)
    assert np.allclose(xs, zeros, atol=2e-5)
    assert [e.kind for e in p.equilibria] == list(kinds)
    for e in p.equilibria:
        assert abs(e.x + D * np.sin(2 * np.pi * e.x)) < 1e-13
        G = e.x**2 / 2 + D * (1 - np.cos(2 * np.pi * e.x)) / (2 * np.pi)
        assert e.energy == pytest.approx(G, abs=1e-13)
    n_centers = int(np.sum(kinds == "center"))
    saddle_levels = {round(e.energy, 9) for e in p.equilibria if e.kind == "saddle"}
    assert len(p.separatrix_energies) == len(saddle_levels)
    labels = [a.label for a in p.annuli]
    assert labels.count("outer") == 1
    wells = [a for a in p.annuli if len(a.wells) == 1]
    assert len(wells) == n_centers
    bands = [a for a in p.annuli if len(a.wells) > 1 and a.bounded]
    # symmetric potential: every saddle level below the top one closes one band
    assert len(bands) == len(saddle_levels) - 1
    for a in p.annuli:
        assert a.energy_min < a.energy_max
        E = a.energy_min + (0.5 * (a.energy_max - a.energy_min) if a.bounded else 1.0)
        xm, xp = a.turning_points(E)
        assert xm < min(a.wells) <= max(a.wells) < xp
        # the orbit encircles exactly the wells of the annulus
        inside = zeros[(zeros > xm) & (zeros < xp) & (kinds == "center")]
        assert np.allclose(np.sort(inside), np.sort(a.wells), atol=2e-5)
    if D == 1.5:
        assert "side well at x=+0.898" in labels and "central well" in labels


def test_non_confining_potential():
    """Omega = 0: G = Delta (1 - cos kx)/k is bounded: a NotConfiningError (a ModelError)."""
    with pytest.raises(NotConfiningError, match="does not confine"):
        split_conservative("sedf", {**SEDF, "Delta": 1.5, "Omega": 0})
    assert issubclass(NotConfiningError, ModelError)


def test_bad_inputs():
    """Non-autonomous model, mu missing or 0, a parameter without value, a wrong potential."""
    with pytest.raises(NonAutonomousError):
        split_conservative(get_model("sedf", {"v": 0.1}), {**SEDF, "Delta": 1.5})
    with pytest.raises(ParameterError, match="mu"):
        split_conservative("vdp", {})
    with pytest.raises(ParameterError, match="mu = 0"):
        split_conservative("vdp", {"mu": 0})
    with pytest.raises(ParameterError, match="beta"):
        split_conservative("sedf", {"mu": 0.1, "Delta": 1.5, "lam": 1})
    with pytest.raises(ModelError, match="potential"):
        split_conservative("vdp", {"mu": 0.1}, potential="x**4")
    s = split_conservative("vdp", {"mu": 0.1}, potential="x**2/2 + 7")
    assert s.user_potential and sp.simplify(s.G - x**2 / 2) == 0
    assert sp.expand(s.h - (1 - x**2) * xdot) == 0
