"""The compiled DOP853 flow (numerics.flow.jit) against independent references.

References: the exact solution of the damped linear oscillator and its fundamental
matrix; scipy's own DOP853 (same tableau, independent code) on the same extended
system; the LSODA (ODEPACK) shooting path of :func:`numerics.limit_cycle`.
"""

from __future__ import annotations

import math
import os
import subprocess
import sys

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings, strategies as st
from scipy.integrate import solve_ivp

from kbm.model.builtins import custom_model
from numerics import IntegrationError, limit_cycle
from numerics.flow import (JIT_METHOD, Method, compile_model, flow, model_template,
                           template_flow)
from kbm.symbols import t as TIME
from numerics.flow.jit import jit_flow, rhs_source

pytest.importorskip("numba")

E0 = [1.0, 0.0, 0.0, 1.0]  # Phi(0) = identity, stored (Phi11, Phi21, Phi12, Phi22)


def _linear_exact(mu: float, x0: float, t: np.ndarray) -> np.ndarray:
    """x'' + mu x' + x = 0: exact x, x' from (x0, 0) and the fundamental matrix, underdamped."""
    w = math.sqrt(1 - mu**2 / 4)
    e = np.exp(-mu * t / 2)
    c, s = np.cos(w * t), np.sin(w * t)
    # columns: solutions from (1, 0) and from (0, 1)
    x_a = e * (c + mu / (2 * w) * s)
    v_a = -e * s / w
    x_b = e * s / w
    v_b = e * (c - mu / (2 * w) * s)
    return np.array([x0 * x_a, x0 * v_a, x_a, v_a, x_b, v_b])


@settings(max_examples=15, deadline=None)
@given(mu=st.floats(0.01, 1.5), x0=st.floats(0.1, 5.0), t_end=st.floats(0.5, 30.0))
def test_linear_damping_exact_solution_and_fundamental_matrix(mu, x0, t_end):
    """Damped linear oscillator x'' + mu x' + x = 0 (F = -x'): state, fundamental matrix,
    int div f = -mu t and the dissipation Gamma = Gamma_+ = mu int x'^2 dt (all loss, no
    gain) against closed forms, at 11 equally spaced output times (hit exactly, no
    interpolation)."""
    m = custom_model("-xdot", name="linear-damping")
    cm = compile_model(m, {"mu": mu})
    ys = flow(cm, [x0, 0.0, *E0, 0.0, 0.0, 0.0], t_end, 10, Method.COMPILED, 1e-12, 1e-12)
    t = np.linspace(0.0, t_end, 11)
    ref = _linear_exact(mu, x0, t)
    assert np.max(np.abs(ys[:, :6] - ref.T)) < 1e-9 * max(1.0, x0)
    assert np.max(np.abs(ys[:, 6] + mu * t)) < 1e-9 * max(1.0, t_end)
    # energy balance of the linear oscillator: E(0) - E(t) = mu int x'^2 dt, with E from
    # the exact solution
    energy = 0.5 * (ref[1] ** 2 + ref[0] ** 2)
    assert np.max(np.abs(ys[:, 7] - (energy[0] - energy))) < 1e-9 * max(1.0, x0**2)
    assert np.all(ys[:, 8] == 0.0)


@settings(max_examples=20, deadline=None)
@given(mu=st.floats(0.05, 2.0), beta=st.floats(0.5, 2.0), Delta=st.floats(0.0, 1.5),
       x0=st.floats(0.3, 3.0), t_end=st.floats(1.0, 12.0))
def test_compiled_flow_equals_scipy_dop853(mu, beta, Delta, x0, t_end):
    """SEDF (paper eq. 3): the compiled flow of the nine extended states equals scipy's
    solve_ivp(DOP853) at rtol = atol = 1e-13 on the same right-hand side."""
    p = {"mu": mu, "beta": beta, "Delta": Delta, "lam": 1.0}
    cm = compile_model("sedf", p)
    y0 = [x0, 0.0, *E0, 0.0, 0.0, 0.0]
    ours = flow(cm, y0, t_end, 1, Method.COMPILED, 1e-12, 1e-12)[-1]
    ref = solve_ivp(cm.rhs_ext, (0.0, t_end), y0, method="DOP853", rtol=1e-13,
                    atol=1e-13).y[:, -1]
    assert np.max(np.abs(ours - ref) / (1.0 + np.abs(ref))) < 1e-9


@pytest.mark.parametrize("model, params", [
    ("vdp", {"mu": 1}),
    ("sedf", {"mu": 0.1, "Delta": 1.5, "lam": 1, "beta": 1}),
    ("rayleigh", {"mu": 0.5}),
])
def test_compiled_shooting_equals_lsoda_shooting(model, params):
    """The limit cycle through the compiled DOP853 and through LSODA (ODEPACK Adams/BDF):
    period, amplitudes, multipliers and dissipation agree."""
    a = limit_cycle(model, params)
    b = limit_cycle(model, params, method="LSODA")
    assert a.method == JIT_METHOD and b.method == "LSODA"
    assert abs(a.period - b.period) < 1e-9 * a.period
    assert abs(a.amplitude_max - b.amplitude_max) < 1e-9 * a.amplitude_max
    assert abs(a.amplitude_first_harmonic - b.amplitude_first_harmonic) < 1e-9
    assert abs(a.floquet_multipliers[1] - b.floquet_multipliers[1]) < 1e-7
    assert abs(a.dissipation.gamma_minus - b.dissipation.gamma_minus) < 1e-8


def test_step_limit_and_blow_up_are_reported():
    """The integrator's bounds: a step limit returns status 1; x'' = -x + x^3 from x = 3
    escapes to infinity in finite time (energy v^2/2 + x^2/2 - x^4/4 > 1/4), which the
    shooting reports as an IntegrationError naming the time, not as a number."""
    cm = compile_model("vdp", {"mu": 1})
    fl = template_flow(cm.template)
    res = fl([2.0, 0.0, *E0, 0.0, 0.0, 0.0], 100.0, cm.pvec, 1e-12, 1e-12, 1, 5)
    assert res.status == 1 and res.steps == 5
    m = custom_model("x**3", name="escape")
    cm = compile_model(m, {"mu": 1})
    with pytest.raises(IntegrationError, match="before t = 20"):
        flow(cm, [3.0, 0.0, *E0, 0.0, 0.0, 0.0], 20.0, 1, Method.COMPILED, 1e-12, 1e-12)


def test_models_without_math_equivalent_fall_back_to_lsoda():
    """A Bessel function has no numba/math form: no compiled flow, and the cycle is found by
    LSODA (van der Pol with a J0 stiffness perturbation)."""
    x = sp.Symbol("x")
    assert jit_flow([sp.besselj(0, x)], TIME, [x], []) is None
    m = custom_model("(1 - x**2)*xdot - besselj(0, x)/10", name="vdp-bessel")
    c = limit_cycle(m, {"mu": 0.5})
    assert c.method == "LSODA" and c.success
    # its potential holds a hypergeometric function (int J0): the energy balance still closes
    assert abs(c.energy_residual) < 1e-8 * c.dissipation.gamma_minus


def test_no_jit_environment_variable(monkeypatch):
    """KBM_NO_JIT=1 switches the compiled integrator off: the same cycle through LSODA."""
    monkeypatch.setenv("KBM_NO_JIT", "1")
    m = custom_model("(1 - x**2)*xdot + x**3/7", name="vdp-nojit")
    c = limit_cycle(m, {"mu": 0.3})
    assert c.method == "LSODA" and c.success


def test_generated_source_is_independent_of_hash_seed():
    """The printed right-hand side (and so its cache file name) is the same bytes whatever
    PYTHONHASHSEED is."""
    code = ("import sympy as sp; from numerics.flow.compiled import model_template; "
            "from numerics.flow.jit import rhs_source; from kbm.symbols import t; "
            "tp = model_template('sedf'); "
            "print(rhs_source(tp.ext_exprs, t, tp.ext_symbols, "
            "[sp.Symbol(n) for n in tp.names]))")
    outs = {subprocess.run([sys.executable, "-c", code], check=True, capture_output=True,
                           text=True, env={**os.environ, "PYTHONHASHSEED": seed}).stdout
            for seed in ("0", "1", "12345")}
    assert len(outs) == 1
    tp = model_template("sedf")
    assert rhs_source(tp.ext_exprs, TIME, tp.ext_symbols,
                      [sp.Symbol(n) for n in tp.names]) + "\n" == outs.pop()


def test_cli_method_option(capsys):
    """`kbm cycle --method compiled` and `--method LSODA` give the same van der Pol cycle
    (mu = 0.5) to 1e-9."""
    import json

    from numerics.cli import main

    out = {}
    for meth in ("compiled", "LSODA"):
        assert main(["cycle", "vdp", "--param", "mu=0.5", "--method", meth, "--json"]) == 0
        out[meth] = json.loads(capsys.readouterr().out)
    assert out["compiled"]["method"] == JIT_METHOD and out["LSODA"]["method"] == "LSODA"
    assert abs(out["compiled"]["period"] - out["LSODA"]["period"]) < 1e-9
    assert abs(out["compiled"]["amplitude_max"] - out["LSODA"]["amplitude_max"]) < 1e-9


def test_compiled_method_unavailable_is_a_clear_error(monkeypatch, capsys):
    """Asking for the compiled integrator where there is none: an IntegrationError naming
    the way out, and on the command line one line and exit status 2."""
    from numerics.cli import main

    monkeypatch.setenv("KBM_NO_JIT", "1")
    m = custom_model("(1 - x**2)*xdot - x**3/5", name="vdp-nojit-2")
    with pytest.raises(IntegrationError, match="method='auto' or 'LSODA'"):
        limit_cycle(m, {"mu": 0.3}, method=JIT_METHOD)
    code = main(["cycle", "--rhs", "(1 - x**2)*xdot - x**3/5", "--param", "mu=0.3",
                 "--method", "compiled"])
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1 and "LSODA" in err


@pytest.mark.parametrize("model, params", [
    ("vdp", {"mu": 0.5}), ("vdp", {"mu": 5}), ("vdp", {"mu": 100}), ("rayleigh", {"mu": 2}),
    ("sedf", {"mu": 0.3, "Delta": 0.5, "lam": 1, "beta": 1}),
])
def test_compiled_transient_settles_on_the_shooting_cycle(model, params):
    """The compiled transient from x = 0.5 (maxima bracketed by samples, refined by Newton on
    x' = 0 with the flow) lands on the maximum and period that shooting converges to."""
    from numerics.cycles import transient

    c = limit_cycle(model, params)
    cm = compile_model(model, params)
    x_max, period, maxima = transient(cm, 0.5, Method.COMPILED, 1e-10, 2e3, 1e3)
    assert abs(x_max - c.amplitude_max) < 1e-8 * c.amplitude_max
    assert abs(period - c.period) < 1e-7 * c.period


@pytest.mark.parametrize("mu", [50.0, 100.0])
def test_relaxation_oscillation_dorodnitsyn(mu):
    """van der Pol at large mu through the compiled integrator: Dorodnitsyn's asymptotic
    period T = (3 - 2 ln 2) mu + 3 alpha mu^(-1/3) - (2/3) ln(mu)/mu + O(1/mu), alpha =
    2.338107 (first zero of Ai(-z)) (A. A. Dorodnitsyn 1947; J. Grasman, Asymptotic Methods
    for Relaxation Oscillations, 1987, ch. 1), and the trivial multiplier is 1 to 1e-8."""
    c = limit_cycle("vdp", {"mu": mu})
    assert c.method == JIT_METHOD and c.success
    alpha = 2.338107410459767
    T = (3 - 2 * math.log(2)) * mu + 3 * alpha * mu ** (-1 / 3) - 2 / 3 * math.log(mu) / mu
    assert abs(c.period - T) < 2.0 / mu
    assert abs(c.floquet_multipliers[0] - 1) < 1e-8
    det, liouville = c.liouville
    assert abs(det - liouville) < 1e-8 * max(1.0, abs(liouville))


@pytest.mark.slow
def test_relaxation_oscillation_compiled_equals_lsoda():
    """van der Pol mu = 50: the compiled DOP853 and LSODA (BDF) shootings agree on the period
    to 1e-9 relative."""
    a = limit_cycle("vdp", {"mu": 50})
    b = limit_cycle("vdp", {"mu": 50}, method="LSODA")
    assert abs(a.period - b.period) < 1e-9 * a.period
