"""The O(mu) and O(mu^2) corrections of the linewidth (``kbm spectrum --order 2``) against the
true cycle.

References checked: the small-noise linewidth of a stable cycle is ``D <Z_v^2>`` with ``Z``
the phase response (Kuramoto, *Chemical Oscillations* (1984), sec. 3.2; Demir, Mehrotra and
Roychowdhury, IEEE Trans. Circuits Syst. I 47, 655 (2000)), computed independently of the
averaging by the adjoint Floquet problem of the true cycle
(:mod:`numerics.spectrum.floquet`).  At order 1 the averaged phase response gives Lax's
``D/(2 omega0^2) (1/a^2 + g^2/lambda^2)`` exactly (Phys. Rev. 160, 290 (1967)); at order 2
(the phase response through the third-order transform, right through ``mu^2``) its error
against the true cycle falls like ``mu^3`` (``mu^4`` for ``F`` odd in ``x'``) where order
1's falls like ``mu``.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
import sympy as sp
from kbm.expansion.one_dof import derive
from kbm.model.builtins import custom_model
from kbm.noise.phase_diffusion import linewidth_series, phase_response
from kbm.symbols import a, psi
from numerics.cli import main
from numerics.spectrum.phase_diffusion import line_theory

CUBIC = "(1 - x**2)*xdot - alpha*x**3"


def test_order_1_phase_response_is_lax():
    """<Z_v^2> at order 1 is Lax's (1/a^2 + g^2/lambda^2)/2 for any alpha and a (the cubic
    stiffness' g_1 = 3 alpha a/4, lambda_1 = (3 a^2 - 4)/8), checked at points of (a, alpha)
    by the mean over psi (exact for a trigonometric polynomial on 64 points)."""
    al = sp.Symbol("alpha")
    z = sp.lambdify((a, psi, al), phase_response(derive(custom_model(CUBIC), 1), 1))
    ps = 2 * np.pi * np.arange(64) / 64
    for av, alv in ((2.0, 1.0), (1.5, 0.3), (3.0, -2.0), (0.7, 5.0)):
        g, lam = 3 * alv * av / 4, (3 * av**2 - 4) / 8
        lax = (1 / av**2 + g**2 / lam**2) / 2
        assert np.mean(z(av, ps, alv) ** 2) == pytest.approx(lax, rel=1e-12)


def test_closed_forms_of_the_correction():
    """D_eff = D (c0 + mu c1): van der Pol (F odd in x') has no O(mu) term, c0 = 1/8 (Lax at
    a* = 2); the cubic stiffness at alpha = 1 has c0 = 10/8 (Lax, 1 + (g a*/lambda)^2 = 10)
    and c1 = -67/8."""
    assert linewidth_series("vdp") == (2, sp.Rational(1, 8), 0)
    a0, c0, c1 = linewidth_series(custom_model(CUBIC), {"alpha": 1})
    assert (a0, c0, c1) == (2, sp.Rational(5, 4), sp.Rational(-67, 8))


def test_order_2_phase_response_order_and_its_fall_back():
    """``--order 2`` takes the phase response through the third-order transform where the
    symbolic expansion reaches order 3 (polynomial F within the cost budget of
    :mod:`kbm.expansion.cost`: ``(x + 1)^40 x'`` is estimated at 1.8e6 terms at order 3,
    ``(x + 1)^45 x'`` at 2.6e6, over the 2e6), else through the first-order one (the SEDF's
    sin(k x): Bessel sums symbolic to order 2 only, kbm.expansion.one_dof.MAX_ORDER_TRIG).
    Order 1 is Lax's."""
    from kbm.expansion.cost import COST_BUDGET, expansion_cost
    from kbm.model.builtins import get_model
    from kbm.noise.phase_response import response_order

    assert [response_order(get_model("vdp"), o) for o in (1, 2)] == [1, 3]
    assert [response_order(get_model("sedf"), o) for o in (1, 2)] == [1, 2]
    for power, want in ((40, 3), (45, 2)):
        m = custom_model(f"(x + 1)**{power}*xdot")
        assert (expansion_cost(m.F, 3)[0] <= COST_BUDGET) == (want == 3)
        assert response_order(m, 2) == want


def test_order_2_phase_response_cycle_and_its_refusal():
    """The cycle of the phase response's rate ``mu A_1 + mu^2 A_2 + mu^3 A_3``: van der Pol's
    ``a* = 2 + mu^2/64 + O(mu^4)`` (Bogoliubov-Mitropolsky's third approximation; A_2 = 0,
    A_3(2) = 1/64 mu^3 against A_1'(2) = -mu) from the second-order cycle a* = 2; a rate
    without a stable root near a* is refused in one sentence that says what to do."""
    from types import SimpleNamespace

    from kbm.noise.phase_diffusion import phase_diffusion
    from kbm.symbols import mu
    from numerics.errors import NoCycleError
    from numerics.spectrum.density import response_cycle

    pd = phase_diffusion("vdp", 2)
    for m in (0.1, 0.2):
        r = response_cycle(pd, {mu: m}, 2.0, 2)
        assert abs(r - (2 + m**2 / 64)) < m**4 / 10, (m, r)
    assert response_cycle(phase_diffusion("vdp", 1), {mu: 0.1}, 2.0, 1) == 2.0
    flat = SimpleNamespace(response_order=3, response_rate=mu * (1 + a**2))
    with pytest.raises(NoCycleError, match="no stable cycle near a\\* = 2.*--order 1"):
        response_cycle(flat, {mu: 0.1}, 2.0, 2)


def test_vdp_order_2_moves_the_line_by_mu_squared_only():
    """Van der Pol: order 2 changes the small-noise linewidth by O(mu^2) (no O(mu) term),
    by the true cycle's 7 mu^2/256 (<Z_v^2> = 1/8 + 7 mu^2/256 + O(mu^4):
    tests/test_spectrum_order2_vdp.py) within 2 % (measured 0.49 %, 0.12 % at mu = 0.1,
    0.05; before, order 2 moved it by -69 mu^2/512, the wrong sign)."""
    for m in (0.1, 0.05):
        D = 0.1 * m
        s1 = line_theory("vdp", {"mu": m}, D).small_noise / D
        s2 = line_theory("vdp", {"mu": m}, D, order=2).small_noise / D
        assert s1 == pytest.approx(0.125, rel=1e-12)
        assert (s2 - s1) / m**2 == pytest.approx(7 / 256, rel=0.02)


def test_order_2_error_against_the_true_cycle_falls_like_mu_cubed():
    """Cubic stiffness alpha = 1 at mu = 0.1, 0.05: the error of D<Z_v^2> against the adjoint
    Floquet value of the true cycle halves with mu at order 1 (+72 %, +35 %) and falls more
    than five times at order 2 (+0.84 %, +0.13 %: like mu^3, the phase response right
    through mu^2; before, -4.6 %, -1.4 %: like mu^2)."""
    from numerics.spectrum.floquet import phase_response as floquet

    model = custom_model(CUBIC)
    e1, e2 = [], []
    for m in (0.1, 0.05):
        ref = floquet(model, {"mu": m, "alpha": 1}).zv2
        D = 0.1 * m
        for order, e in ((1, e1), (2, e2)):
            th = line_theory(model, {"mu": m, "alpha": 1}, D, order=order)
            e.append(th.small_noise / D / ref - 1)
    assert 1.8 < e1[0] / e1[1] < 2.3
    assert abs(e2[0]) < 0.012 and abs(e2[0] / e2[1]) > 5.0
    assert abs(e2[1]) < abs(e1[1]) / 100


def _first_order_transform(model, params: dict, m: float) -> float:
    """``<Z_v^2>`` through the first-order transform (``u_1``; rates to ``A_2``, ``B_2``) at
    the cycle of ``A_1 + mu A_2``: what ``--order 2`` used before."""
    from scipy.optimize import brentq

    from kbm.symbols import mu

    res = derive(model, 2, params or None)
    z = sp.lambdify((a, psi), phase_response(res, 2).subs(mu, m))
    rate = sp.lambdify(a, res.A[1] + m * res.A[2])
    a_star = brentq(rate, 1.5, 2.5, xtol=1e-15)
    return float(np.mean(z(a_star, 2 * np.pi * np.arange(512) / 512) ** 2))


@pytest.mark.slow
@pytest.mark.parametrize("name, mus", [("cubic", (0.1, 0.05, 0.025)),
                                       ("rayleigh", (0.2, 0.1, 0.05))])
def test_order_2_error_falls_one_power_faster_than_before(name, mus):
    """Against the true cycle (adjoint Floquet), the order-2 small-noise <Z_v^2> now and
    through the first-order transform (before), relative errors (measured):

    ========  =====  =========  =========
    model     mu     before     now
    ========  =====  =========  =========
    cubic     0.1    -4.6e-2    +8.4e-3
    cubic     0.05   -1.4e-2    +1.3e-3
    cubic     0.025  -3.8e-3    +1.8e-4
    rayleigh  0.2    +2.4e-2    -4.2e-4
    rayleigh  0.1    +5.9e-3    -2.6e-5
    rayleigh  0.05   +1.5e-3    -1.6e-6
    ========  =====  =========  =========

    The cubic's (an O(mu) term, c_1 = -67/8) falls like mu^3 (local slopes 2.7, 2.8) where
    it fell like mu^2 (1.7, 1.9); Rayleigh's (F odd in x', no O(mu) term) like mu^4
    (slopes 4.0, 4.0) where it fell like mu^2."""
    from numerics.spectrum.floquet import phase_response as floquet

    model, params = ((custom_model(CUBIC), {"alpha": 1}) if name == "cubic"
                     else ("rayleigh", {}))
    old, new = [], []
    for m in mus:
        ref = floquet(model, {"mu": m, **params}).zv2
        D = 1e-4 * m
        new.append(line_theory(model, {"mu": m, **params}, D, order=2).small_noise / D / ref
                   - 1)
        old.append(_first_order_transform(model, params, m) / ref - 1)
    slope_old = [np.log2(old[i] / old[i + 1]) for i in range(2)]
    slope_new = [np.log2(new[i] / new[i + 1]) for i in range(2)]
    for so, sn in zip(slope_old, slope_new):
        assert 1.6 < so < 2.2 and sn > so + 0.7, (old, new)
    assert all(abs(n) < abs(o) / 4 for o, n in zip(old, new)), (old, new)


@pytest.mark.slow
def test_floquet_slope_is_the_closed_form():
    """The true cycle's (<Z_v^2> - 10/8)/mu at mu = 0.025, 0.0125, Richardson-extrapolated to
    mu = 0, is the closed form c1 = -67/8 (within 1.5 %: the O(mu^2) remainder), and its
    (<Z_v^2> - 10/8 + 67 mu/8)/mu^2 is c2 = 3117/64 (48.32 against 48.70)."""
    from numerics.spectrum.floquet import phase_response as floquet

    model = custom_model(CUBIC)
    zv2 = {m: floquet(model, {"mu": m, "alpha": 1}).zv2 for m in (0.025, 0.0125)}
    s = [(zv2[m] - 1.25) / m for m in (0.025, 0.0125)]
    assert 2 * s[1] - s[0] == pytest.approx(-67 / 8, rel=0.015)
    # and the mu^2 term of --order 2's phase response (the third-order transform):
    # c2 = 3117/64 = 48.70, the true cycle's Richardson-extrapolated 48.32
    _, c0, c1, c2 = linewidth_series(model, {"alpha": 1}, terms=3)
    assert (c0, c1, c2) == (sp.Rational(5, 4), sp.Rational(-67, 8), sp.Rational(3117, 64))
    s2 = [(zv2[m] - 1.25 + 67 * m / 8) / m**2 for m in (0.025, 0.0125)]
    assert 2 * s2[1] - s2[0] == pytest.approx(3117 / 64, rel=0.015)


def test_cli_order_2_json_keeps_every_key(capsys, monkeypatch):
    """--order 2: linewidth.averaged holds the corrected line, averaged_order says 2, and
    every key of order 1 is there; at mu = 0.1, D = 0.01 the small-noise part is within 1.2 %
    of the true cycle's D<Z_v^2> (--floquet) where order 1 is 72 % off, and the finite-D/mu
    widening of the stationary density (6 % at D/mu = 0.1) is the same factor at both
    orders.  The true cycle's phase response (``--floquet``) depends on the model and its
    parameters, not on the averaging order: both runs ask for it, and the second gets the
    first's (:func:`numerics.spectrum.result.true_cycle` keeps it; computing it twice took
    two thirds of the test's time)."""
    import numerics.spectrum.floquet as floquet
    import numerics.spectrum.result as result

    real, calls = floquet.phase_response, []

    def counted(model, params, **kw):
        calls.append(1)
        return real(model, params, **kw)

    monkeypatch.setattr(floquet, "phase_response", counted)
    result._true_cycle.cache_clear()
    argv = ["spectrum", "--rhs", CUBIC, "-p", "alpha=1", "-p", "mu=0.1", "-p", "D=0.01",
            "--no-simulation", "--json", "--floquet"]
    assert main(argv) == 0
    r1 = json.loads(capsys.readouterr().out)
    assert main(argv + ["--order", "2"]) == 0
    r2 = json.loads(capsys.readouterr().out)
    assert len(calls) == 1  # both runs asked, with the same model and parameters
    assert set(r1) == set(r2) and set(r1["linewidth"]) == set(r2["linewidth"])
    l1, l2 = r1["linewidth"], r2["linewidth"]
    assert (l1["averaged_order"], l2["averaged_order"]) == (1, 2)
    assert l1["small_noise"] == pytest.approx(l1["linearised"], rel=1e-12)
    assert l1["small_noise"] / l1["floquet"] - 1 > 0.6
    assert abs(l2["small_noise"] / l2["floquet"] - 1) < 0.012  # 0.84 % (before: 4.6 %)
    w1 = l1["averaged"] / l1["small_noise"]
    w2 = l2["averaged"] / l2["small_noise"]
    assert 1.0 < w1 < 1.1 and w2 == pytest.approx(w1, abs=0.01)


@pytest.mark.slow
def test_cubic_order_2_matches_the_simulated_line():
    """mu = 0.05, D = 0.005 (D/mu = 0.1), 64 trajectories (seed 3: 0.00511, 6.9 % standard
    error): the simulated HWHM (phase-variance growth) is within 8 % plus three standard
    errors of the order-2 averaged line (-3.6 %; -5.0 % with the first-order transform),
    where the order-1 line is more than three standard errors too wide (+30 %;
    docs/spectra.rst, 256 trajectories: 0.00473 +- 0.00016 against 0.0066272 at order 1
    and 0.0049270 at order 2)."""
    from numerics.spectrum.result import line_report

    r = line_report(custom_model(CUBIC), {"mu": 0.05, "alpha": 1}, 0.005, order=2, seed=3,
                    workers=2)
    lw = r["linewidth"]
    rel_se = lw["stderr"] / lw["simulated"]
    e2 = lw["averaged"] / lw["simulated"] - 1
    assert abs(e2) < 0.08 + 3 * rel_se
    th1 = line_theory(custom_model(CUBIC), {"mu": 0.05, "alpha": 1}, 0.005)
    e1 = th1.linewidth / lw["simulated"] - 1
    assert e1 > 3 * rel_se and abs(e2) < e1 / 3


@pytest.mark.parametrize("power, a_u", [(5, "2.57"), (7, "2.264")])
def test_order_2_refused_where_the_noise_escapes_its_spurious_cycle(power, a_u, capsys):
    """F = (1 - x^2) x' - x^5 (or x^7), mu = 0.1, D = 0.01: mu^2 A_2 holds a^7 (a^9) with a
    positive sign, so the second-order amplitude rate turns positive again at a_u (an
    unstable cycle of the truncated series, the root of a^6 - 5.33 a^4 - 21.3 a^2 + 85.3
    for x^5) and the stationary density ``P = a exp((2/D) int A)`` grows without bound
    beyond it (the density grid came out empty: IndexError).  Here ln P falls by less than
    the quadrature's cut of 60 between a* and a_u: refused with the numbers, one line, no
    traceback; the stated D bound gives a line."""
    from numerics.errors import NoCycleError

    rhs = f"(1-x**2)*xdot - x**{power}"
    with pytest.raises(NoCycleError, match=f"unstable cycle at a = {a_u}") as exc:
        line_theory(custom_model(rhs, omega0=1), {"mu": 0.1}, 0.01, order=2)
    assert "--order 1" in str(exc.value)
    bound = float(str(exc.value).split("give D below about ")[1].split(",")[0])
    assert line_theory(custom_model(rhs, omega0=1), {"mu": 0.1}, bound / 2,
                       order=2).linewidth > 0
    argv = ["spectrum", "--rhs", rhs, "-p", "mu=0.1", "-p", "D=0.01", "--order", "2",
            "--no-simulation"]
    assert main(argv) != 0
    err = capsys.readouterr().err
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1


def test_order_2_density_below_the_spurious_cycle_has_the_small_noise_limit():
    """Where the barrier holds (D << 0.01), the density confined below a_u gives the order-2
    line, which tends to its small-noise form D <Z_v^2> (the phase response through the
    near-identity transform, a second computation) as D -> 0: within 1e-3 at D = 1e-5."""
    th = line_theory(custom_model("(1-x**2)*xdot - x**5", omega0=1), {"mu": 0.1}, 1e-5,
                     order=2)
    assert th.linewidth == pytest.approx(th.small_noise, rel=1e-3)


def test_bessel_series_at_a_point_is_summed_in_numpy():
    """The SEDF's rates hold Jacobi-Anger Bessel series, which sympy's evalf summed for
    minutes (kbm spectrum sedf --order 2 ran 310 s); they are cut after 80 terms and summed
    in numpy: Neumann's J_0(z) + 2 sum_{n>=1} J_2n(z) = 1 (Abramowitz & Stegun 9.1.46)."""
    from kbm.symbols import a
    from numerics.spectrum._evaluate import at as _at

    n = sp.Symbol("n", integer=True, positive=True)
    series = sp.besselj(0, a) + 2 * sp.Sum(sp.besselj(2 * n, a), (n, 1, sp.oo))
    for z in (0.3, 3.7, 11.0):
        assert _at(series, {}, z) == pytest.approx(1.0, abs=1e-13)


@pytest.mark.slow
def test_sedf_order_2_refused_in_seconds_with_the_reason(capsys):
    """``kbm spectrum sedf -p mu=0.1 -p Delta=3 -p beta=1 -p lam=1 -p D=0.05 --order 2``
    ran about 5 minutes in sympy's evalf of the Bessel series and ended in a ValueError
    traceback; now (8 s of CPU) one line: the second-order cycle a* = 0.88 has an unstable
    one at a = 1.31 only 0.52 below it in ln P."""
    argv = ["spectrum", "sedf", "-p", "mu=0.1", "-p", "Delta=3", "-p", "beta=1", "-p",
            "lam=1", "-p", "D=0.05", "--order", "2", "--no-simulation"]
    assert main(argv) != 0
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "unstable cycle at a = 1.308" in err
    assert "--order 1" in err


@pytest.mark.slow
def test_sedf_order_2_against_the_true_cycle():
    """The SEDF (F = (1 - beta x^2) x' - delta sin(k x), a Bessel series at order 2) at mu =
    0.02, Delta = 0.06, D = 1e-5: the order-2 small-noise linewidth D <Z_v^2> is nearer the
    true cycle's (adjoint Floquet, exact in mu) than order 1's (measured relative errors
    0.0009 against 0.0032); at mu = 0.1, Delta = 3 (not small) the second order's line
    centre comes out negative and is refused."""
    from numerics.errors import NoCycleError
    from numerics.spectrum.floquet import phase_response

    p = {"mu": 0.02, "Delta": 0.06, "beta": 1, "lam": 1}
    true = phase_response("sedf", p).linewidth(1e-5)
    e1, e2 = (abs(line_theory("sedf", p, 1e-5, order=o).small_noise / true - 1)
              for o in (1, 2))
    assert e2 < 0.5 * e1 and e2 < 2e-3
    with pytest.raises(NoCycleError, match="Omega = -1.658 at order 2 is not positive"):
        line_theory("sedf", {"mu": 0.1, "Delta": 3, "beta": 1, "lam": 1}, 1e-4, order=2)
