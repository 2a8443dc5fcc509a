"""``kbm response --convergence``: the order-N error against mu through the command line.

Independent references: a hand-written scipy shooting (``solve_ivp`` and ``fsolve``) for the
true response's first harmonic, and Nayfeh & Mook's first-order Duffing frequency response
``[zeta^2 + (sigma - 3 alpha a^2/8)^2] a^2 = h^2/4`` (sec. 4.1.1), which does not depend on
``mu``, for the order-1 amplitude and the order-1 lower jump point.  The slopes come out
near the order only if the prediction really converges to the true response.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq, fsolve

from numerics.cli import main

ZETA, ALPHA, H = 0.1, 1.0, 0.5
DUFF = ["-p", f"zeta={ZETA}", "-p", f"alpha={ALPHA:g}", "-p", f"h={H}"]
MUS = "0.01,0.02,0.04"


def _run(capsys, argv) -> str:
    assert main(argv) == 0
    return capsys.readouterr().out


def _first_order_amplitude(sigma: float) -> float:
    """The single positive root in ``a**2`` of N&M's first-order frequency response."""
    k = 3 * ALPHA / 8
    # k^2 A^3 - 2 k sigma A^2 + (zeta^2 + sigma^2) A - h^2/4 = 0 in A = a^2
    roots = np.roots([k * k, -2 * k * sigma, ZETA**2 + sigma**2, -H * H / 4])
    pos = [r.real for r in roots if abs(r.imag) < 1e-12 and r.real > 0]
    assert len(pos) == 1, roots
    return math.sqrt(pos[0])


def _first_order_lower_jump() -> float:
    """The lower jump of N&M's first-order curve: the local minimum of
    ``sigma_+(a) = 3 alpha a^2/8 + sqrt(h^2/(4 a^2) - zeta^2)`` (``d sigma_+/da = 0``)."""
    def dsig(a):
        r = H * H / (4 * a * a) - ZETA**2
        return 3 * ALPHA * a / 4 - H * H / (4 * a**3) / math.sqrt(r)

    a = brentq(dsig, 0.3, 1.5, xtol=1e-14)
    return 3 * ALPHA * a * a / 8 + math.sqrt(H * H / (4 * a * a) - ZETA**2)


def _scipy_first_harmonic(mu: float, sigma: float) -> float:
    """The response of period ``2 pi/nu`` by a scipy shooting from rest, and the amplitude
    of its component at ``nu``."""
    nu = 1 + mu * sigma
    T = 2 * math.pi / nu

    def f(t, y):
        x, v = y
        return [v, -x + mu * (-2 * ZETA * v - ALPHA * x**3 + H * math.cos(nu * t))]

    def miss(y0):
        return solve_ivp(f, (0, T), y0, method="DOP853", rtol=1e-12, atol=1e-13).y[:, -1] - y0

    y0 = fsolve(miss, [0.0, 0.0], xtol=1e-13)
    assert np.max(np.abs(miss(y0))) < 1e-10
    t = np.linspace(0, T, 257)[:-1]
    x = solve_ivp(f, (0, T), y0, method="DOP853", rtol=1e-12, atol=1e-13, t_eval=t).y[0]
    return 2 * abs(np.mean(x * np.exp(-1j * nu * t)))


def test_amplitude_convergence_json(capsys, tmp_path):
    """Below the lower jump (sigma = -0.5, one response): slopes ~1 and ~2; the true
    amplitudes match a scipy shooting, and the order-1 errors the closed form."""
    assert main(["response", "duffing-forced", *DUFF, "--detuning", "-0.5", "--convergence",
                 MUS, "--order", "2", "--json", "--out", str(tmp_path)]) == 0
    out, err = capsys.readouterr()
    d = json.loads(out)  # the JSON alone on standard output, the figure's path on stderr
    assert err == f"figure: {tmp_path / 'convergence.png'}\n"
    assert set(d) >= {"model", "resonance", "parameters", "quantity", "mu", "true", "errors",
                      "slopes", "orders", "sigma"}
    assert d["model"] == "duffing-forced" and d["resonance"] == "1/1"
    assert d["parameters"] == {"zeta": ZETA, "alpha": ALPHA, "h": H}
    assert d["mu"] == [0.01, 0.02, 0.04] and d["orders"] == [1, 2] and d["sigma"] == -0.5
    assert set(d["errors"]) == set(d["slopes"]) == {"1", "2"}
    s1, s2 = d["slopes"]["1"], d["slopes"]["2"]
    assert 0.9 < s1 < 1.1 and 1.85 < s2 < 2.15, d["slopes"]
    assert all(e2 < e1 / 50 for e1, e2 in zip(d["errors"]["1"], d["errors"]["2"]))
    assert abs(_scipy_first_harmonic(0.04, -0.5) - d["true"][-1]) < 1e-8
    a1 = _first_order_amplitude(-0.5)
    for true, e1 in zip(d["true"], d["errors"]["1"]):
        assert abs(abs(a1 - true) - e1) < 1e-9
    assert (tmp_path / "convergence.png").stat().st_size > 10_000


@pytest.mark.slow  # 4-8 s; kept out of the default run (five-minute rule)
def test_fold_convergence_text(capsys):
    """The lower jump point's detuning (fold 0 in sigma 0..1.2): slopes ~1 and ~2 printed,
    the order-1 errors against the closed-form first-order jump."""
    out = _run(capsys, ["response", "duffing-forced", *DUFF, "--vary", "sigma=0:1.2",
                        "--convergence", MUS])
    lines = out.splitlines()
    assert "detuning of fold 0" in lines[1]
    rows = [[float(v) for v in ln.split()] for ln in lines[3:6]]
    assert [r[0] for r in rows] == [0.01, 0.02, 0.04]
    f1 = _first_order_lower_jump()
    for mu, true, e1, e2 in rows:
        # the table prints the errors to 5 significant digits
        assert abs(abs(f1 - true) - e1) < 1e-4 * e1, (f1, true, e1)
        assert e2 < e1 / 50
    slopes = {ln.split()[1].rstrip(":"): float(ln.split()[2]) for ln in lines
              if ln.startswith("  order ")}
    assert 0.9 < slopes["1"] < 1.1 and 1.85 < slopes["2"] < 2.15, out
    assert "(expected 2)" in out


@pytest.mark.parametrize("extra, words", [
    (["--detuning", "0", "--convergence", "0.01,0.02"], "at least 3 values of mu, got 2"),
    (["--detuning", "0", "--convergence", "0.01,0.02,-0.04"], "positive and finite, got -0.04"),
    (["--detuning", "0", "--convergence", "0.01,0.02,0.02"], "distinct, got 0.02"),
    (["--detuning", "0", "--convergence", "0.01,a,0.02"], "comma-separated numbers"),
    (["--detuning", "0", "--convergence", MUS, "--nu", "1"], "cannot go with --nu"),
    (["--detuning", "0", "--convergence", MUS, "--no-numeric"], "--no-numeric"),
    (["--convergence", MUS], "either --detuning SIGMA"),
    (["--detuning", "0", "--convergence", MUS, "--fold", "1"], "use it with --vary"),
    (["--vary", "sigma=0:1", "--fold", "1"], "--fold chooses the fold"),
    (["--detuning", "0", "--convergence", MUS, "-p", "mu=0.1"], "leave out --param mu=0.1"),
    (["--detuning", "0", "--convergence", MUS, "--order", "9"], "between 1 and 8, got 9"),
    (["--detuning", "0", "--convergence", MUS, "--amax", "0.1"],
     "no fixed point of the order-2 slow flow at sigma = 0 for mu = 0.01 with 0.0001 < a"),
])
def test_convergence_one_line_errors(capsys, extra, words):
    assert main(["response", "duffing-forced", *DUFF, *extra]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and words in err, err


def test_too_few_folds_names_the_numbers(capsys):
    """No fold in sigma 0..0.3 (the lower jump is at 0.52): the count, range and mu."""
    assert main(["response", "duffing-forced", *DUFF, "--vary", "sigma=0:0.3",
                 "--convergence", MUS]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1, err
    assert "0 fold(s) in sigma 0 to 0.3 at mu = 0.01, no fold 0" in err
