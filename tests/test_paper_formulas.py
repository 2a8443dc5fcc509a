"""The paper's eqs. (6)-(9) as printed (kbm.output.paper), their errata, and the numerical
evidence."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
import sympy as sp

from kbm.output import paper
from kbm.output.evaluate import numpy_function

SYMS = [paper.mu, paper.beta, paper.Delta, paper.k]


def _J(n, z):
    return sp.besselj(n, z)


def test_errata_rows():
    """ERRATA has one frozen row per printed formula, eqs. (6)-(9), in that order."""
    assert [e.equation for e in paper.ERRATA] == ["6", "7", "8", "9"]
    with pytest.raises(dataclasses.FrozenInstanceError):
        paper.ERRATA[0].equation = "5"


def test_printed_eq6_and_eq7_against_a_second_reading():
    """The printed eqs. (6) and (7) of kbm.output.paper equal the paper's formulas read again and
    typed here multiplied out: (1 - beta a^2/4)(1/3 - beta a^2/4) = 1/3 - beta a^2/3 +
    beta^2 a^4/16, and (7) term by term."""
    mu, beta, D, k, a = paper.mu, paper.beta, paper.Delta, paper.k, paper.a
    eq6 = 1 - mu**2 / 3 + mu**2 * beta * a**2 / 3 - mu**2 * beta**2 * a**4 / 16
    eq7 = (mu * a / 2 - mu * beta * a**3 / 8 + D * _J(1, k * a)
           + mu * k * D**2 / 2 * _J(0, k * a) * _J(1, k * a))
    rows = {e.equation: e.printed for e in paper.ERRATA}
    assert sp.expand(rows["6"] - eq6) == 0
    assert sp.expand(rows["7"] - eq7) == 0


def test_printed_eq8_and_eq9_against_a_second_reading():
    """The printed f and g of kbm.output.paper equal the paper's eqs. (8), (9) read again: the sum
    of (8) over all n >= 0 minus its n = 1 term (the printed "n != 1"), and (9) multiplied
    out; compared numerically (the sums are infinite)."""
    mu, beta, D, k, a, psi = paper.mu, paper.beta, paper.Delta, paper.k, paper.a, paper.psi
    n = sp.Symbol("n", integer=True, nonnegative=True)
    term = (-1)**n * _J(2 * n + 1, k * a) * sp.cos((2 * n + 1) * psi)
    eq8 = (-beta * a**3 / 32 * sp.sin(3 * psi)
           + D / mu * (sp.Sum(term, (n, 0, sp.oo)) + _J(3, k * a) * sp.cos(3 * psi)))
    eq9 = (-k * D**2 / mu * _J(0, k * a) * _J(1, k * a)
           - 2 * a * (sp.Rational(1, 3) - beta * a**2 / 3 + beta**2 * a**4 / 16) * sp.cos(psi))
    rows = {e.equation: e.printed for e in paper.ERRATA}
    psis = np.linspace(0, 2 * np.pi, 17)
    for hand, printed in ((eq8, rows["8"]), (eq9, rows["9"])):
        args = [paper.a, paper.psi, *SYMS]
        want = numpy_function(hand, args)(1.3, psis, 0.1, 0.7, 0.2, 2 * np.pi)
        got = numpy_function(printed, args)(1.3, psis, 0.1, 0.7, 0.2, 2 * np.pi)
        np.testing.assert_allclose(got, want, rtol=1e-13, atol=1e-15)


def test_corrected_eq6_is_the_textbook_van_der_pol_frequency_without_potential():
    """Without the potential (Delta = 0) the corrected eq. (6) is the van der Pol frequency
    1 + mu^2 B_2 with B_2 = -(1 - beta a^2 + 7 beta^2 a^4/32)/8 (Bogoliubov & Mitropolsky
    ch. 1, typed here; for beta = 1 the -1/8 + a^2/8 - 7 a^4/256 of the engine's tests), and
    it differs from the printed eq. (6)."""
    mu, beta, a = paper.mu, paper.beta, paper.a
    textbook = 1 - mu**2 * (1 - beta * a**2 + sp.Rational(7, 32) * beta**2 * a**4) / 8
    row = paper.ERRATA[0]
    assert sp.expand(row.corrected.subs(paper.Delta, 0).doit() - textbook) == 0
    assert sp.expand(row.printed.subs(paper.Delta, 0) - textbook) != 0


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
    from kbm.output.paper import ERRATA_CASES
    from numerics.paper.errata import errata_evidence

    rows = errata_evidence(ERRATA_CASES[:1])
    assert {r.equation for r in rows} == {"6", "7", "8", "9", "10"}
    for r in rows:
        assert r.success
        if r.quantity.startswith("stable"):
            assert (r.printed, r.corrected, r.numeric) == (0.0, 1.0, 1.0)
        else:
            assert r.corrected_error < r.printed_error / 5, (r.equation, r.quantity)
