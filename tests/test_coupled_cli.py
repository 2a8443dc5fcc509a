"""The command-line contracts of issue 23: ``kbm derive`` with one ``--rhs`` per degree of
freedom, ``--omega0`` lists and ``--internal``; ``kbm cycle`` of a coupled system (all 2N
Floquet multipliers); ``kbm lock`` (``boundary_averaged``, ``boundary_true``, ``--out``).

References: Nayfeh & Mook (1979) sec. 6.6's first-order equations of the 1:3 resonance,
worked out by hand for ``duffing-1-3`` (potential coupling ``k x1^3 x2``); Liouville's
formula for the multipliers; the true locking edge of ``tests/test_coupled_cycle.py``.
"""

from __future__ import annotations

import contextlib
import io
import json
from types import SimpleNamespace

import pytest
import sympy as sp

from kbm.symbols import parse
from numerics.cli import main


def kbm(*args: str, code: int = 0) -> SimpleNamespace:
    """The command line in this process (``numerics.cli.main``, as the console script runs
    it): its exit status, standard output and standard error."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = main(list(args))
    assert status == code, err.getvalue()
    return SimpleNamespace(returncode=status, stdout=out.getvalue(), stderr=err.getvalue())


def test_derive_rhs_list_json_contract():
    """The 1:3 resonance of two cubic oscillators with the potential coupling V = k x1^3 x2:
    by hand, a1' = -(3k/8) a1^2 a2 sin(gamma), a2' = (k/24) a1^3 sin(gamma),
    gamma = psi2 - 3 psi1 (the averaged k x1^2 x2 and x1^3 terms, omega = 1, 3)."""
    out = kbm("derive", "--rhs", "-x1**3 - 3*k*x1**2*x2", "--rhs", "-x2**3 - k*x1**3",
              "--omega0", "1,3", "--internal", "1:3", "-n", "2", "--json").stdout
    d = json.loads(out)
    assert d["dof"] == 2 and d["omega0"] == ["1", "3"] and d["internal"] == ["1:3"]
    assert len(d["A"]) == 2 and len(d["A"][0]) == 3 and d["A"][0][0] is None
    assert parse(d["gammas"]["gamma1"]) == parse("psi2 - 3*psi1")
    a1, a2, k, g = sp.symbols("a1 a2 k gamma1")
    assert sp.expand(parse(d["A"][0][1]) + 3 * k / 8 * a1**2 * a2 * sp.sin(g)) == 0
    assert sp.expand(parse(d["A"][1][1]) - k / 24 * a1**3 * sp.sin(g)) == 0
    # the rates of gamma are psi2' - 3 psi1'
    rate = parse(d["gamma_rates"]["gamma1"][1])
    assert sp.expand(rate - parse(d["B"][1][1]) + 3 * parse(d["B"][0][1])) == 0


def test_derive_builtin_latex_and_one_dof_unchanged():
    tex = kbm("derive", "coupled-vdp", "-n", "1", "--latex").stdout
    assert tex.startswith("\\begin{align*}") and "\\gamma_{1}" in tex
    one = json.loads(kbm("derive", "--rhs", "(1 - x**2)*xdot", "-n", "1", "--json").stdout)
    assert one["A"] == [None, "-a*(a**2 - 4)/8"]  # the one-degree-of-freedom JSON, as before


def test_derive_text_says_what_theta_and_the_rates_are():
    """Issue 40 item 9: the text of ``kbm derive duffing-1-3`` defines the forcing angle,
    ``theta = nu t`` with ``nu = 3 + mu sigma`` (Nayfeh & Mook 1979 sec. 6.6.2), consistently
    with its own slow flow: ``gamma2 = theta - psi2`` has the first-order rate
    ``d nu/d mu - B_2,1``; it says what ``A_i,n`` is, and writes ``x1'' + x1`` (not
    ``1*x1``), each linear term ``omega_i^2 x_i`` with the frequencies of the JSON."""
    text = kbm("derive", "duffing-1-3", "-n", "2").stdout
    d = json.loads(kbm("derive", "duffing-1-3", "-n", "2", "--json").stdout)
    lines = {ln.split(" = ")[0].strip(): ln.split(" = ", 1)[1] for ln in text.splitlines()
             if " = " in ln}
    theta_line = next(ln for ln in text.splitlines() if "theta = nu*t" in ln)
    nu = parse(theta_line.split("nu = ")[1])
    mu, sigma = sp.symbols("mu sigma")
    assert nu.subs(mu, 0) == 3 and parse(d["omega0"][1]) == 3  # omega2 : nu = 1 : 1
    rate = parse(lines["dgamma2/dt [mu^1]"])
    assert sp.expand(rate - (sp.diff(nu, mu) - parse(d["B"][1][1]))) == 0
    assert sp.diff(nu, mu) == sigma
    assert "da_i/dt = mu*A_i,1 + mu^2*A_i,2" in text
    assert "A_i,n, B_i,n: mode i, the coefficient of mu^n" in text
    assert "+ 1*x" not in text
    for i, w in enumerate(d["omega0"], 1):
        left = next(k for k in lines if k.startswith(f"x{i}''"))
        assert parse(left.split("+", 1)[1]) == parse(w) ** 2 * sp.Symbol(f"x{i}")
    assert kbm("derive", "vdp", "-n", "1").stdout.startswith(
        "KBM expansion of vdp: x'' + x = mu*(")


@pytest.mark.parametrize("args, message", [
    (["--rhs", "-x1**3", "--rhs", "-x2**3", "--omega0", "1,2,3"],
     "2 right-hand sides (--rhs) but 3 frequencies"),
    (["--rhs", "-x1**2*x2", "--rhs", "-x1**3", "--omega0", "1,3"], "--internal 1:3"),
    ([*[a for i in range(1, 8) for a in ("--rhs", f"-x{i}**3")],
      "--omega0", "1,2,3,4,5,6,7"], "above the limit 6"),
    (["--rhs", "-x1**3", "--rhs", "-x2**3", "--omega0", "1,3", "--internal", "1:2"],
     "not in the declared ratio 1:2"),
    (["--rhs", "-x1**3", "--rhs", "-x3**3"], "not a state variable"),
])
def test_derive_bad_input_one_line(args, message):
    err = kbm("derive", *args, "-n", "1", code=2).stderr
    assert message in err and err.count("\n") == 1


def test_cycle_of_a_coupled_builtin_has_all_multipliers():
    d = json.loads(kbm("cycle", "coupled-vdp", "-p", "mu=0.05", "-p", "sigma=0.1",
                       "--json").stdout)
    assert len(d["floquet_multipliers"]) == 4
    assert d["floquet_multipliers"][0] == pytest.approx(1, abs=1e-9)
    li = d["liouville"]
    assert li["det_monodromy"] == pytest.approx(li["exp_divergence_integral"], rel=1e-8)
    assert d["stable"] and len(d["amplitudes"]) == 2
    err = kbm("cycle", "coupled-vdp", "-p", "mu=0.05", "--start", "1,2,3", code=2).stderr
    assert "needs 4 numbers" in err


def test_lock_json_contract_and_figure(tmp_path):
    d = json.loads(kbm("lock", "coupled-vdp", "-p", "mu=0.05", "-p", "c=0.3", "--vary",
                       "sigma=-1:1", "--order", "2", "--tol", "1e-8", "--json", "--out",
                       str(tmp_path)).stdout)
    assert set(d["boundary_averaged"]) == {"1", "2"}
    assert [p[0] for p in d["boundary_true"]] == [0.3, 0.3]
    lo, hi = sorted(p[1] for p in d["boundary_true"])
    # the true edges of test_coupled_cycle at mu = 0.05 (bisection to 1e-9 there)
    assert lo == pytest.approx(-0.2977584409, abs=2e-7)
    assert hi == pytest.approx(0.3022584333, abs=2e-7)
    o2 = sorted(p[1] for p in d["boundary_averaged"]["2"])
    assert abs(o2[1] - hi) < 5e-5 < abs(0.3 - hi)  # order 2 is closer than order 1
    assert (tmp_path / "lock.png").stat().st_size > 10_000
    assert json.loads((tmp_path / "lock.json").read_text())["boundary_true"] == d["boundary_true"]
    err = kbm("lock", "coupled-vdp", "-p", "mu=0.05", "--vary", "sigma=1:-1", code=2).stderr
    assert "FROM < TO" in err
    err = kbm("lock", "duffing-1-3", "-p", "mu=0.05", "--vary", "k=0:1", code=2).stderr
    assert "error" in err


def test_cycle_of_a_forced_coupled_system():
    """quadratic-1-2 forced near the higher mode: a response of period 2 x 2 pi/nu with its
    four multipliers; the saturated a2 is near 2 sqrt 2 (tests/test_coupled_forced.py)."""
    d = json.loads(kbm("cycle", "quadratic-1-2", "-p", "mu=0.01", "-p", "zeta1=0.5", "-p",
                       "zeta2=0.5", "-p", "sigma1=0", "-p", "sigma2=1", "-p", "h=30",
                       "--json").stdout)
    assert d["multiple"] == 2 and len(d["floquet_multipliers"]) == 4
    assert abs(d["amplitudes"][1] - 2 * 2**0.5) < 0.2 < d["amplitudes"][0]
