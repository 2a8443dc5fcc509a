"""Tongues that open beyond first order: the Mathieu tongues at delta = 1 and 9/4.

x'' + (delta + eps cos s) x = 0 near delta = n^2/4 is the forced model
x'' + omega0^2 x = -mu x cos(nu t), nu = 2 omega0/n + mu sigma (built-ins ``mathieu-2``:
omega0 = 1, resonance 1/1; ``mathieu-3``: omega0 = 3/2, resonance 2/3), with
delta = omega0^2/nu^2 and eps = mu/nu^2.  The tongue n opens at order n of the KBM
expansion (its width is O(eps^n)).

Independent references:

- Abramowitz & Stegun 20.2.25, the characteristic values a_2, b_2, a_3, b_3 for small q
  (A&S: y'' + (a - 2 q cos 2z) y = 0, so a = 4 delta and q = -2 eps; a_n(-q) = a_n(q)
  for even n and a_n(-q) = b_n(q) for odd n, so the pair {a_n/4, b_n/4} at q = 2 eps is
  the pair of edges).  The typed coefficients are checked here against an independent
  exact computation: the Rayleigh-Schroedinger perturbation series, in exact rationals,
  of the eigenvalue of the Hill (Fourier) matrix of the Mathieu operator near n^2/4, in
  the even and odd subspaces (non-degenerate there);
- Floquet numerics: the monodromy matrix over 2 pi (scipy DOP853, rtol 1e-12) has trace
  +2 on the edges of an even tongue and -2 on those of an odd one.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from kbm.errors import ModelError
from kbm.model.forced import ForcedOscillator
from kbm.expansion.forced import derive_forced
from kbm.slowflow.tongues import epsilon, mathieu_transition, transition_curves
from kbm.symbols import mu
from numerics.comparison.response_convergence import slope

q = sp.Symbol("q")
R = sp.Rational
#: A&S 20.2.25: a_2, b_2 through q^8
AS_A2 = 4 + R(5, 12) * q**2 - R(763, 13824) * q**4 + R(1002401, 79626240) * q**6 \
    - R(1669068401, 458647142400) * q**8
AS_B2 = 4 - R(1, 12) * q**2 + R(5, 13824) * q**4 - R(289, 79626240) * q**6 \
    + R(21391, 458647142400) * q**8
#: A&S 20.2.25: a_3, b_3 through q^8
AS_A3 = 9 + R(1, 16) * q**2 + R(1, 64) * q**3 + R(13, 20480) * q**4 - R(5, 16384) * q**5 \
    - R(1961, 23592960) * q**6 - R(609, 104857600) * q**7 + R(4957199, 2113929216000) * q**8
AS_B3 = 9 + R(1, 16) * q**2 - R(1, 64) * q**3 + R(13, 20480) * q**4 + R(5, 16384) * q**5 \
    - R(1961, 23592960) * q**6 + R(609, 104857600) * q**7 + R(4957199, 2113929216000) * q**8
AS = {2: (AS_A2, AS_B2), 3: (AS_A3, AS_B3)}
MODEL = {2: "mathieu-2", 3: "mathieu-3"}


def _truncate(expr: sp.Expr, n: int) -> sp.Expr:
    """``expr`` (a polynomial in ``epsilon``) through ``epsilon**n``."""
    p = sp.Poly(sp.expand(expr), epsilon)
    return sp.Add(*[c * epsilon**k for (k,), c in p.terms() if k <= n])


def _as_edges(n: int, order: int) -> set:
    """{a_n/4, b_n/4} at q = 2 eps through eps^order (A&S 20.2.25)."""
    return {_truncate(f.subs(q, 2 * epsilon) / 4, order) for f in AS[n]}


def _hill_series(n: int, parity: int, order: int) -> list[Fraction]:
    """The eigenvalue ``delta(eps) = sum d_r eps^r`` near ``n^2/4`` of the Hill matrix of
    ``x'' + (delta + eps cos s) x = 0`` (``x = sum c_k exp(i k s)``, ``k`` integer for even
    ``n``, half-integer for odd ``n``: ``delta c_k = k^2 c_k - (eps/2)(c_{k-1} + c_{k+1})``)
    in the subspace ``c_{-k} = parity c_k``, by Rayleigh-Schroedinger perturbation theory
    in exact rationals (the diagonal is non-degenerate there)."""
    half = n % 2 == 1
    size = n // 2 + order + 2  # c_r has support within r of the unperturbed state
    ks = [Fraction(2 * j + 1, 2) if half else Fraction(j) for j in range(size)]
    m1 = [[Fraction(0)] * size for _ in range(size)]
    for i in range(size):
        for j in (i - 1, i + 1):
            if 0 <= j < size:
                m1[i][j] -= Fraction(1, 2)
    if half:  # the neighbour of k = 1/2 below is c_{-1/2} = parity c_{1/2}
        m1[0][0] -= Fraction(parity, 2)
    else:  # k = 0: the neighbour c_{-1} = parity c_1
        m1[0][1] -= Fraction(parity, 2)
    diag = [k * k for k in ks]
    J = n // 2
    if not half and parity == -1:  # c_0 = 0
        diag, m1, J = diag[1:], [row[1:] for row in m1[1:]], J - 1
    size = len(diag)
    vecs = [[Fraction(int(i == J)) for i in range(size)]]
    lam = [diag[J]]
    for r in range(1, order + 1):
        mv = [sum(m1[i][j] * vecs[r - 1][j] for j in range(size)) for i in range(size)]
        lam.append(mv[J])
        vecs.append([Fraction(0) if i == J else
                     (-mv[i] + sum(lam[s] * vecs[r - s][i] for s in range(1, r + 1)))
                     / (diag[i] - diag[J]) for i in range(size)])
    return lam


@pytest.mark.parametrize("n", [2, 3])
def test_as_20_2_25_transcription_against_hill_matrix_series(n):
    """The typed A&S 20.2.25 coefficients of a_n, b_n (n = 2, 3) through q^8 equal the
    exact perturbation series of the Hill matrix's eigenvalues (a = 4 delta, q = 2 eps)."""
    hill = {sp.Add(*[sp.Rational(c.numerator, c.denominator) * epsilon**r
                     for r, c in enumerate(_hill_series(n, parity, 8))]) for parity in (1, -1)}
    assert hill == _as_edges(n, 8)


def test_as_20_2_25_against_scipy():
    """The typed a_2, b_2, a_3, b_3 agree with scipy's characteristic values to O(q^9)."""
    from scipy.special import mathieu_a, mathieu_b

    for qq in (0.1, 0.2, 0.4):
        for n, (fa, fb) in AS.items():
            assert abs(float(fa.subs(q, qq)) - mathieu_a(n, qq)) < qq**9
            assert abs(float(fb.subs(q, qq)) - mathieu_b(n, qq)) < qq**9


@pytest.mark.parametrize("n, order", [(2, 2), (2, 3), (2, 4), (2, 6), (2, 8),
                                      (3, 3), (3, 4), (3, 5), (3, 6), (3, 8)])
def test_kbm_series_equals_abramowitz_stegun_20_2_25(n, order):
    """The order-N transition curves of the tongue n (opening at order n) give delta(eps)
    through eps^N, equal to a_n/4, b_n/4 of A&S 20.2.25 at q = 2 eps."""
    curves = transition_curves(derive_forced(MODEL[n], order))
    assert len(curves) == 2 and {c.opens_at for c in curves} == {n}
    got = {sp.expand(mathieu_transition(c)) for c in curves}
    assert got == _as_edges(n, order)


@pytest.mark.parametrize("n", [2, 3])
def test_edges_share_the_centre_and_split_at_mu_to_the_n_minus_1(n):
    """sigma(mu) of order N has degree N - 1; the two edges agree below mu^(n-1) (the
    centre of the tongue, from the phi-free rates) and differ at mu^(n-1)."""
    N = n + 2
    s1, s2 = (sp.Poly(c.sigma, mu) for c in transition_curves(derive_forced(MODEL[n], N)))
    assert s1.degree() == s2.degree() == N - 1
    d = sp.Poly(s1.as_expr() - s2.as_expr(), mu)
    assert min(k for (k,), _ in d.terms()) == n - 1


def _trace(delta: float, eps: float) -> float:
    """Trace of the monodromy matrix of x'' + (delta + eps cos s) x = 0 over 2 pi."""
    def f(t, y):
        k = delta + eps * np.cos(t)
        return [y[1], -k * y[0], y[3], -k * y[2]]

    s = solve_ivp(f, (0, 2 * np.pi), [1, 0, 0, 1], rtol=1e-12, atol=1e-13, method="DOP853")
    return s.y[0, -1] + s.y[3, -1]


def _floquet_errors(n: int, order: int, eps) -> list[float]:
    """max over the two edges of |delta_KBM - delta_Floquet| at each eps."""
    fs = [sp.lambdify(epsilon, mathieu_transition(c))
          for c in transition_curves(derive_forced(MODEL[n], order))]
    target = 2.0 if n % 2 == 0 else -2.0
    errs = []
    for e in eps:
        pred = sorted(float(f(e)) for f in fs)
        w = pred[1] - pred[0]
        true = [brentq(lambda d: _trace(d, e) - target, p - w / 3, p + w / 3, xtol=1e-15)
                for p in pred]
        errs.append(max(abs(p - t) for p, t in zip(pred, true)))
    return errs


@pytest.mark.parametrize("n, order, rate", [(2, 2, 4), (2, 4, 6), (3, 3, 4), (3, 4, 5),
                                            (3, 5, 6)])
def test_kbm_tongue_error_against_floquet_scales(n, order, rate):
    """Against the Floquet edges (trace of the monodromy = +2 for n = 2, -2 for n = 3) the
    order-N curves' error falls as eps^rate: N + 1, or N + 2 when the eps^(N+1) term of
    a_n, b_n vanishes (n = 2, N even: A&S 20.2.25 has even powers only)."""
    eps = np.array([0.1, 0.2, 0.4])
    errs = _floquet_errors(n, order, eps)
    assert slope(eps, errs) > rate - 0.4, (errs, slope(eps, errs))
    assert slope(eps, errs) < rate + 0.4, (errs, slope(eps, errs))


def test_floquet_reference_agrees_with_scipy():
    """The Floquet root finder (the reference above) reproduces scipy's a_2/4 and b_2/4."""
    from scipy.special import mathieu_a, mathieu_b

    e = 0.3
    for ref in (mathieu_a(2, 2 * e) / 4, mathieu_b(2, 2 * e) / 4):
        d = brentq(lambda d: _trace(d, e) - 2, ref - 1e-3, ref + 1e-3, xtol=1e-15)
        assert abs(d - ref) < 1e-10


def test_order_below_the_opening_order_is_refused_with_the_order():
    """mathieu-3 at order 2: the message names order 3 and what to do."""
    with pytest.raises(ModelError, match=r"opens at order 3 \(A_3 depends on phi\); "
                                         r"derive at order N >= 3"):
        transition_curves(derive_forced("mathieu-3", 2))


@pytest.mark.parametrize("F, res, match", [
    ("-2*zeta*xdot", "1/1", "no parametric .*term"),
    ("-x*cos(theta)", "3/1", "no tongue opens at any order"),
    ("-2*zeta*xdot - x*cos(theta)", "1/1", "phi-free part A_1 .* before the tongue opens "
                                           "at order 2"),
])
def test_no_tongue_refusals_say_why(F, res, match):
    """No parametric term; a resonance p > 2 (a linear F never resonates there); a damping
    of order mu before a tongue of order mu^2."""
    with pytest.raises(ModelError, match=match):
        transition_curves(derive_forced(ForcedOscillator("m", F, resonance=res), 3))


def test_mathieu_transition_refuses_a_non_mathieu_model():
    curves = transition_curves(derive_forced("parametric", 1, {"alpha": 0}))
    with pytest.raises(ModelError, match="F = -x\\*cos\\(theta\\)"):
        mathieu_transition(curves[0])
