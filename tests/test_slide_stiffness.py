"""The cost bound of the driven slider's explicit integration (numerics.sliding.stiffness).

The reference is the linear stability of explicit Runge-Kutta methods (Hairer & Wanner,
*Solving ODEs II*, sec. IV.2): a step ``h`` is stable only for ``h |lambda| <= c`` with ``c``
the real stability interval (about 6 for DOP853), so a run through a damping with
``|dD/dx'| = lambda(t)`` takes at least ``int lambda dt / c`` steps.
"""

import math
import time

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, strategies as st
from scipy.integrate import solve_ivp

from kbm.errors import ParameterError
from kbm.model.builtins import Oscillator
from kbm.symbols import mu as MU, x as X, xdot as XDOT
from numerics.errors import IntegrationError
from numerics.sliding.driven import driven_system
from numerics.sliding.reference import MAX_STIFF_STEPS, slide
from numerics.sliding.stiffness import (STABILITY_INTERVAL, StepGuard, damping_envelope,
                                        stiff_steps, stiff_t_end)
from numerics.sliding.damping import damping_rate, damping_text


def test_steps_follow_the_stability_law_and_the_bound_covers_them():
    """SEDF at mu = 1e3 (paper eq. 3): steps >= int mu |beta x^2 - 1| dt / c along the path
    actually integrated, and the module's bound (|x| <= v t + Delta/Omega^2) is above it."""
    p = {"Delta": 3.0, "beta": 1.0, "mu": 1e3, "v": 0.1}
    r = slide("sedf", p, t_end=15.0)
    t, x = r.sol.t, r.sol.y[0]
    lam = p["mu"] * np.abs(p["beta"] * x[:-1] ** 2 - 1)
    needed = float(np.sum(lam * np.diff(t))) / STABILITY_INTERVAL["DOP853"]
    steps = len(t) - 1
    assert steps >= 0.9 * needed  # stability: h |lambda| <= c (up to the 6.4 measured)
    full = dict(p, Omega=1.0)
    assert stiff_steps("sedf", full, 15.0, "DOP853") >= needed


def test_stiff_sedf_is_refused_at_once_with_the_numbers():
    """`kbm slide sedf -p Delta=3 -p beta=1 -p mu=1e6 -p v=0.1 --t-end 15` ran > 60 s."""
    t0 = time.process_time()
    with pytest.raises(ParameterError, match=r"needs about .* steps.*lower mu or t_end"):
        slide("sedf", {"Delta": 3.0, "beta": 1.0, "mu": 1e6, "v": 0.1}, t_end=15.0)
    assert time.process_time() - t0 < 5.0


def test_long_sedf_run_is_refused_and_the_suggested_t_end_fits():
    """t_end = 31000 at v = 0.01 (under MAX_PERIODS) ran > 10 min: the lab-frame damping
    mu (beta x^2 - 1) grows like (v t)^2, so the cost grows like t_end^3."""
    p = {"Delta": 3.0, "beta": 1.0, "v": 0.01}
    with pytest.raises(ParameterError, match=r"t_end <= ([0-9.e+]+)\)") as e:
        slide("sedf", p, t_end=31000.0)
    suggested = float(str(e.value).rsplit("t_end <= ", 1)[1].split(")")[0])
    full = {"mu": 0.1, "Omega": 1.0, "lam": 1.0, **p}
    assert stiff_steps("sedf", full, suggested, "DOP853") <= 1.001 * MAX_STIFF_STEPS  # 4 digits
    assert stiff_steps("sedf", full, 1.01 * suggested, "DOP853") > MAX_STIFF_STEPS
    assert stiff_t_end("sedf", full, "DOP853", MAX_STIFF_STEPS, 31000.0) == pytest.approx(
        suggested, rel=1e-3)


def test_the_step_guard_stops_a_stiff_integration_with_the_numbers():
    """y' = -lambda y with lambda = 1e5 to t = 1 needs ~ lambda/c = 1.7e4 DOP853 steps; a
    budget of 100 steps stops it near t = 100 c/lambda, with an IntegrationError."""
    lam = 1e5
    guard = StepGuard(lambda t, y: -lam * y, 100, "DOP853")
    with pytest.raises(IntegrationError, match=r"stopped at t = ([0-9.e-]+) of t_end = 1") as e:
        guard.run(lambda f: solve_ivp(f, (0.0, 1.0), [1.0], method="DOP853"), 1.0,
                  lambda t, x: lam)
    t_stop = float(str(e.value).split("stopped at t = ")[1].split(" ")[0])
    assert 0 < t_stop <= 1.5 * 100 * STABILITY_INTERVAL["DOP853"] / lam


def test_slide_stops_with_the_numbers_when_its_step_budget_is_spent(monkeypatch):
    """slide's own integration is bounded: SEDF at mu = 1e3, T = 15 takes ~4900 DOP853 steps;
    with the budget lowered to 1000 it stops early with the damping mu |beta x^2 - 1| there."""
    import numerics.sliding.reference as reference

    monkeypatch.setattr(reference, "GUARD_STEPS", 1000)
    with pytest.raises(IntegrationError, match=r"stopped at t = ([0-9.e-]+) of t_end = 15 "
                                              r"after about 1e\+03 steps.*\|dD/dx'\| = ") as e:
        slide("sedf", {"Delta": 3.0, "beta": 1.0, "mu": 1e3, "v": 0.1}, t_end=15.0)
    assert float(str(e.value).split("stopped at t = ")[1].split(" ")[0]) < 15.0


def test_the_cdc_refusal_names_its_own_damping():
    """The CDC's damping mu x' (paper eq. 12) has the constant |dD/dx'| = mu: a run refused
    for its stiffness (mu t_end/6 = 2.5e6 steps of DOP853) says so, not the SEDF's
    mu |beta x^2 - 1|."""
    with pytest.raises(ParameterError) as err:
        slide("cdc", {"mu": 1e3, "Delta": 3, "v": 0.1}, t_end=15000.0)
    msg = str(err.value)
    assert "|dD/dx'| = mu (mu = 1000)" in msg and "beta" not in msg


_pos = st.floats(0.01, 100.0)
_num = st.floats(-50.0, 50.0)


@given(mu=_pos, beta=_pos, v=st.floats(0.0, 10.0), t=st.floats(0.0, 100.0), x=_num, xd=_num)
def test_the_derived_damping_rate_is_the_closed_form(mu, beta, v, t, x, xd):
    """|dD/dx'| derived by sympy from each slider's F equals the closed forms of the paper's
    damping forces at random states: the SEDF's D = mu (beta x^2 - 1) x' (eq. 3) has
    mu |beta x^2 - 1|, the CDC's D = mu x' (eq. 12) mu, sedf_comoving's
    mu |beta (x - v t)^2 - 1|."""
    p = {"mu": mu, "beta": beta, "Delta": 3.0, "Omega": 1.0, "lam": 1.0, "v": v}
    y = (x, xd, t)
    closed = {"sedf": mu * abs(beta * x * x - 1), "cdc": mu,
              "sedf_comoving": mu * abs(beta * (x - v * t) ** 2 - 1)}
    for model, want in closed.items():
        q = {k: w for k, w in p.items() if not (model == "cdc" and k == "beta")}
        assert damping_rate(model, q)(t, y) == pytest.approx(want, rel=1e-12, abs=1e-12 * mu)


def test_the_driven_systems_damping_is_the_signed_closed_form():
    """The friction map's runaway rate (DrivenSystem.damping, from the same derivative with
    the stage-attached part at x - v tau) is the signed -d x''/d x' of eqs. 3 and 12:
    mu (beta x^2 - 1), mu and mu (beta (x - v tau)^2 - 1), on rows (x, x', tau, ...)."""
    mu, beta, v = 0.7, 1.3, 0.3
    y = np.random.default_rng(5).normal(scale=4.0, size=(40, 7))
    y[:, 2] = np.abs(y[:, 2]) * 50
    x, z = y[:, 0], y[:, 0] - v * y[:, 2]
    closed = {"sedf": mu * (beta * x * x - 1), "cdc": mu + 0 * x,
              "sedf_comoving": mu * (beta * z * z - 1)}
    for model, want in closed.items():
        p = {"mu": mu, "Delta": 3.0, "lam": 1.0, "v": v} | ({} if model == "cdc" else
                                                           {"beta": beta})
        got = driven_system(model, p, engine="scipy").damping(y)
        np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-12 * mu)


def test_the_damping_texts_are_printed_from_the_derivative():
    """The messages' |dD/dx'| of eqs. 3 and 12, and of the stage-attached SEDF."""
    assert damping_text("cdc") == "|dD/dx'| = mu"
    assert damping_text("sedf") == "|dD/dx'| = mu |beta x^2 - 1| (growing with |x| ~ v t)"
    assert damping_text("sedf_comoving") == "|dD/dx'| = mu |beta (x - v t)^2 - 1|"


def _slider(name: str, F: sp.Expr) -> Oscillator:
    """A slider of the paper's form with the damping of ``F`` (not a built-in)."""
    beta, delta, k, Omega, Delta, lam = sp.symbols("beta delta k Omega Delta lam")
    return Oscillator(name, F - delta * sp.sin(k * X), omega0=Omega,
                      physical={"delta": Delta / MU, "k": 2 * sp.pi / lam},
                      defaults={"Omega": 1})


def test_a_model_without_a_branch_gets_its_estimate():
    """Two sliders no code names: (a) a positive damping growing with the position, D = mu
    (1 + beta x^2) x': no cycle (A = 0), x^2 <= (v t)^2, so N = mu (beta v^2 T^3/3 + T)/c;
    (b) a Rayleigh slider, D = -mu (1 - x'^2/3) x', whose cycle has the velocity amplitude
    A omega0 = 2 (Rayleigh's, the van der Pol amplitude of x'): |dD/dx'| = mu |x'^2 - 1| is
    largest at x'^2 = v^2 + 4, so N = mu (v^2 + 3) T/c."""
    beta = sp.Symbol("beta")
    grow = _slider("grow", -(1 + beta * X**2) * XDOT)
    rayleigh = _slider("rayleigh_slider", (1 - XDOT**2 / 3) * XDOT)
    c = STABILITY_INTERVAL["DOP853"]
    for mu, b, v, T, Om in [(1e3, 1.0, 0.1, 15.0, 1.0), (0.1, 2.5, 0.01, 3000.0, 2.0)]:
        p = {"mu": mu, "beta": b, "Delta": 3.0, "Omega": Om, "lam": 1.0, "v": v}
        assert stiff_steps(grow, p, T, "DOP853") == pytest.approx(
            mu * (b * v * v * T**3 / 3 + T) / c, rel=1e-12)
        q = {k: w for k, w in p.items() if k != "beta"}
        assert stiff_steps(rayleigh, q, T, "DOP853") == pytest.approx(
            mu * (v * v + 3) * T / c, rel=1e-12)
    assert damping_text(grow) == "|dD/dx'| = mu |beta x^2 + 1| (growing with |x| ~ v t)"
    assert damping_text(rayleigh) == "|dD/dx'| = mu |xdot^2 - 1|"


def test_a_damping_that_is_not_a_polynomial_is_bounded_on_a_grid():
    """D = mu (2 + sin x) x' (not a polynomial: the largest |dD/dx'| on a grid of the envelope
    |x| <= v t, which holds x = v t): for v T <= pi/2 the bound is mu (2 + sin(v t)), so N =
    mu (2 T + (1 - cos(v T))/v)/c; without damping N = 0."""
    wavy = _slider("wavy", -(2 + sp.sin(X)) * XDOT)
    mu, v, T = 1e3, 0.1, 15.0
    p = {"mu": mu, "Delta": 3.0, "Omega": 1.0, "lam": 1.0, "v": v}
    assert stiff_steps(wavy, p, T, "DOP853") == pytest.approx(
        mu * (2 * T + (1 - math.cos(v * T)) / v) / STABILITY_INTERVAL["DOP853"], rel=1e-6)
    assert damping_text(wavy) == "|dD/dx'| = mu |sin(x) + 2| (growing with |x| ~ v t)"
    assert stiff_steps(_slider("free", sp.Integer(0)), p, T, "DOP853") == 0.0


def test_a_model_without_a_branch_is_bounded_along_its_run():
    """The estimate for D = mu (1 + beta x^2) x' (no hand branch) covers the stability law
    along the run itself: x'' + mu (1 + beta x^2) x' + Delta sin(2 pi x) + (x - v t) = 0
    integrated here with DOP853 takes at least 0.9 int mu (1 + beta x^2) dt / c steps (Hairer &
    Wanner IV.2), and the estimate is above that integral; at every step the envelope's
    bound mu (1 + beta (v t)^2) is above the damping there (the slider stays behind the
    stage, |x| <= v t)."""
    beta = sp.Symbol("beta")
    grow = _slider("grow", -(1 + beta * X**2) * XDOT)
    mu, b, Delta, v, T = 1e3, 1.0, 3.0, 0.1, 15.0

    def rhs(t, y):
        x, xd = y
        return [xd, -mu * (1 + b * x * x) * xd - Delta * math.sin(2 * math.pi * x) - (x - v * t)]
    sol = solve_ivp(rhs, (0.0, T), [0.0, 0.0], method="DOP853", rtol=1e-10, atol=1e-12)
    lam = mu * (1 + b * sol.y[0][:-1] ** 2)
    needed = float(np.sum(lam * np.diff(sol.t))) / STABILITY_INTERVAL["DOP853"]
    assert len(sol.t) - 1 >= 0.9 * needed
    p = {"mu": mu, "beta": b, "Delta": Delta, "Omega": 1.0, "lam": 1.0, "v": v}
    assert stiff_steps(grow, p, T, "DOP853") >= needed
    assert np.all(damping_envelope(grow, p)(sol.t[:-1]) >= lam)


@given(mu=st.floats(0.01, 1e4), beta=st.floats(0.1, 10.0), v=st.floats(0.0, 1.0),
       T=st.floats(0.1, 3000.0), Omega=st.floats(0.5, 2.0))
def test_the_sedf_estimate_is_its_closed_form(mu, beta, v, T, Omega):
    """SEDF (eq. 3): |dD/dx'| = mu |beta x^2 - 1| is largest at x^2 = (v t)^2 + A^2 with the
    van der Pol amplitude A = 2/sqrt(beta), so N = mu (beta v^2 T^3/3 + 3 T)/c."""
    p = {"mu": mu, "beta": beta, "Delta": 3.0, "Omega": Omega, "lam": 1.0, "v": v}
    assert stiff_steps("sedf", p, T, "DOP853") == pytest.approx(
        mu * (beta * v * v * T**3 / 3 + 3 * T) / STABILITY_INTERVAL["DOP853"], rel=1e-9)


@given(mu=st.floats(0.01, 1e4), beta=st.floats(0.1, 10.0), v=st.floats(1e-3, 1.0),
       Delta=st.floats(0.0, 10.0), Omega=st.floats(0.5, 2.0), T=st.floats(0.1, 3000.0))
def test_the_sedf_comoving_estimate_is_its_closed_form(mu, beta, v, Delta, Omega, T):
    """sedf_comoving: the spring pulls the slider through D = mu (beta z^2 - 1) x' at the
    stage velocity iff max over the lag z of Omega^2 |z| - mu v (beta z^2 - 1) =
    Omega^4/(4 mu beta v) + mu v reaches the pinning force Delta; then |z| <= max(Delta/Omega^2,
    A = 2/sqrt(beta)) and N = mu (beta max(d, A)^2 - 1) T/c, else the SEDF's closed form."""
    p = {"mu": mu, "beta": beta, "Delta": Delta, "Omega": Omega, "lam": 1.0, "v": v}
    pull = Omega**4 / (4 * mu * beta * v) + mu * v
    if abs(pull - Delta) < 1e-2 * Delta:  # the grid of lags resolves the maximum to 1e-2
        return
    c = STABILITY_INTERVAL["DOP853"]
    if pull >= Delta:
        z = max(Delta / Omega**2, 2 / math.sqrt(beta))
        want = mu * (beta * z * z - 1) * T / c
    else:
        want = mu * (beta * v * v * T**3 / 3 + 3 * T) / c
    assert stiff_steps("sedf_comoving", p, T, "DOP853") == pytest.approx(want, rel=1e-9)


@pytest.mark.slow
@pytest.mark.parametrize("mu, v, t_end, held", [(10.0, 0.1, 100.0, True),
                                                (3.0, 0.1, 100.0, True),
                                                (0.1, 0.1, 300.0, False)])
def test_sedf_comoving_estimate_covers_its_run(mu, v, t_end, held):
    """sedf_comoving at Delta = 3, beta = 1: a run takes at least int mu |beta (x - v t)^2 - 1|
    dt / c steps (Hairer & Wanner IV.2) and the estimate is above that integral.  At mu = 10
    and 3 (v = 0.1) the spring cannot pull the slider through its damping (max over the lag
    of Omega^2 |z| - mu v (beta z^2 - 1) = Omega^4/(4 mu beta v) + mu v < Delta), the lag grows
    with v t, and the stage-frame bound |x - v t| <= max(Delta/Omega^2, 2/sqrt(beta)) was
    2.7 and 1.2 times below the integral; at mu = 0.1 the slider follows the stage."""
    p = {"Delta": 3.0, "beta": 1.0, "mu": mu, "v": v}
    r = slide("sedf_comoving", p, t_end=t_end)
    t, x = r.sol.t, r.sol.y[0]
    lam = mu * np.abs((x[:-1] - v * t[:-1]) ** 2 - 1)
    needed = float(np.sum(lam * np.diff(t))) / STABILITY_INTERVAL["DOP853"]
    assert len(t) - 1 >= 0.9 * needed
    assert stiff_steps("sedf_comoving", r.params, t_end, "DOP853") >= needed
    frame = mu * (max(3.0, 2.0) ** 2 + 1) * t_end / STABILITY_INTERVAL["DOP853"]
    assert (frame < needed) == held
