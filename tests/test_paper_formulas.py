"""The paper's eqs. (6)-(9) as printed (kbm.paper), their errata, and the numerical evidence."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from kbm import paper
from kbm.evaluate import numpy_function

SYMS = [paper.mu, paper.beta, paper.Delta, paper.k]


def test_errata_rows():
    """ERRATA has one frozen row per printed formula, eqs. (6)-(9), with the printed
    expression of kbm.paper."""
    assert [e.equation for e in paper.ERRATA] == ["6", "7", "8", "9"]
    assert paper.ERRATA[0].printed == paper.phase_rate()
    with pytest.raises(Exception):
        paper.ERRATA[0].equation = "5"


def test_eq6_vdp_frequency_on_the_cycle():
    """Eq. (6) at Delta = 0 on the cycle beta a^2 = 4: the printed mu^2 term vanishes, the
    corrected one gives the van der Pol frequency 1 - mu^2/16 (Bogoliubov & Mitropolsky)."""
    on_cycle = {paper.Delta: 0, paper.a: 2 / sp.sqrt(paper.beta)}
    assert sp.simplify(paper.phase_rate().subs(on_cycle)) == 1
    assert sp.simplify(paper.ERRATA[0].corrected.subs(on_cycle) - (1 - paper.mu**2 / 16)) == 0


def test_eq6_corrected_has_first_order_potential_shift():
    """The corrected eq. (6) holds mu B_1 = Delta J_1(k a)/a (conservative force
    -Delta sin(k x): frequency shift -(1/(pi a)) int sin(k a cos s) cos s ds ... = Delta J_1/a)."""
    c = sp.expand(paper.corrected("6"))
    first = c.coeff(paper.Delta, 1).subs(paper.mu, 0)
    assert sp.simplify(first - sp.besselj(1, paper.k * paper.a) / paper.a) == 0


def test_eq7_no_potential_term_at_first_order():
    """Eq. (7): the corrected amplitude rate at mu -> 0 (Delta/mu fixed) is the van der Pol
    a/2 (1 - beta a^2/4) only; the printed one adds Delta J_1(k a)."""
    d = sp.Symbol("d")
    corr = sp.expand(paper.corrected("7").subs(paper.Delta, d * paper.mu))
    lead = sp.limit(corr / paper.mu, paper.mu, 0)
    assert sp.simplify(lead - paper.a / 2 * (1 - paper.beta * paper.a**2 / 4)) == 0
    printed = sp.expand(paper.amplitude_rate().subs(paper.Delta, d * paper.mu))
    plead = sp.limit(printed / paper.mu, paper.mu, 0)
    assert sp.simplify(plead - lead - d * sp.besselj(1, paper.k * paper.a)) == 0


def test_eq8_corrected_against_fft():
    """Corrected eq. (8): u_1 of F = -delta sin(k x) is, harmonic by harmonic m >= 3, the
    m-th Fourier coefficient of -delta sin(k a cos psi) divided by 1 - m^2 (independent FFT);
    the printed f misses the factor and the third harmonic."""
    a0, k0, D, m0 = 0.8, 2 * np.pi, 0.3, 0.1   # Delta/mu = 3
    psi = np.linspace(0, 2 * np.pi, 256, endpoint=False)
    forcing = -(D / m0) * np.sin(k0 * a0 * np.cos(psi))
    c = np.fft.rfft(forcing) / psi.size
    mm = np.arange(c.size)
    c_u = np.where(mm >= 2, c / (1 - mm.astype(float)**2 + (mm < 2)), 0)
    expected = np.fft.irfft(c_u * psi.size, psi.size)
    beta0 = 0.0   # isolate the potential part
    corr = numpy_function(paper.corrected("8"), [paper.a, paper.psi, *SYMS])
    got = corr(a0, psi, m0, beta0, D, k0)
    assert np.max(np.abs(got - expected)) < 1e-12 * np.max(np.abs(expected)) + 1e-14
    printed = numpy_function(paper.f(), [paper.a, paper.psi, *SYMS])(a0, psi, m0, beta0, D, k0)
    assert np.max(np.abs(printed - expected)) > 0.1 * np.max(np.abs(expected))


def test_eq9_printed_mean_and_corrected_harmonics():
    """Eq. (9) as printed has the constant -(k Delta^2/mu) J_0 J_1; the corrected u_2 has no
    constant (F is odd in x) and no first harmonic (convention)."""
    psi = np.linspace(0, 2 * np.pi, 256, endpoint=False)
    args = (1.7, psi, 0.1, 1.0, 0.2, 2 * np.pi)
    corr = numpy_function(paper.corrected("9"), [paper.a, paper.psi, *SYMS])(*args)
    c = np.fft.rfft(corr) / psi.size
    assert abs(c[0]) < 1e-14 and abs(c[1]) < 1e-14 and abs(c[3]) > 1e-4
    printed = numpy_function(paper.g(), [paper.a, paper.psi, *SYMS])(*args)
    ka = 2 * np.pi * 1.7
    from scipy.special import jv
    assert np.mean(printed) == pytest.approx(-(2 * np.pi) * 0.04 / 0.1 * jv(0, ka) * jv(1, ka),
                                             rel=1e-12)


def test_errata_evidence_small_delta():
    """At mu = 0.05, Delta = 0.1 (KBM valid) the corrected formulas are closer to the true
    cycle than the printed ones for every erratum (eqs. 6-10), and the printed eq. (7)
    calls the stable cycle unstable."""
    from numerics.paper.errata import CASES, errata_evidence

    rows = errata_evidence(CASES[:1])
    assert {r.equation for r in rows} == {"6", "7", "8", "9", "10"}
    for r in rows:
        assert r.success
        if r.quantity.startswith("stable"):
            assert (r.printed, r.corrected, r.numeric) == (0.0, 1.0, 1.0)
        else:
            assert r.corrected_error < r.printed_error / 5, (r.equation, r.quantity)
