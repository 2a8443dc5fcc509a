"""Phase diffusion of a noisy limit cycle
(numerics.spectrum.phase_diffusion.cycle_phase_diffusion) and ``kbm escape``.

References: Stratonovich, Topics in the Theory of Random Noise II, ch. 9; Lax, Phys. Rev.
160 (1967) 290 (amplitude-phase coupling); Kramers' low-friction rate (Hanggi, Talkner,
Borkovec, RMP 62 (1990) 251, eq. 4.8).
"""

from __future__ import annotations

import json
import math

import pytest
from hypothesis import given, settings, strategies as st

import kbm
from kbm.errors import ModelError
from numerics.cli import main
from numerics.spectrum.phase_diffusion import cycle_phase_diffusion as phase_diffusion


@settings(max_examples=10, deadline=None)
@given(st.floats(0.001, 0.3), st.floats(1e-4, 0.1))
def test_vdp_phase_diffusion_closed_form(mu, D):
    """van der Pol: a0 = 2, B_1 = 0, D_phi = D/(2 a0^2) = D/8 for any mu."""
    r = phase_diffusion("vdp", {"mu": mu}, D)
    assert r.amplitude == pytest.approx(2.0, rel=1e-12)
    assert r.D_phi == pytest.approx(D / 8, rel=1e-12)
    assert r.relaxation == pytest.approx(mu, rel=1e-12)   # -mu A_1'(2) = mu


def test_vdp_duffing_shear():
    """x'' - mu(1 - x^2)x' + x + mu alpha x^3: B_1 = 3 alpha a^2/8, A_1' (2) = -1, so the
    shear a0 B_1'/A_1' = -3 alpha and D_phi = (D/8)(1 + 9 alpha^2)."""
    for alpha in (0.5, 1.0, 2.0):
        m = kbm.custom_model(f"(1 - x**2)*xdot - {alpha}*x**3")
        r = phase_diffusion(m, {"mu": 0.05}, 0.01)
        assert r.shear == pytest.approx(-3 * alpha, rel=1e-12)
        assert r.D_phi == pytest.approx(0.01 / 8 * (1 + 9 * alpha**2), rel=1e-12)


def test_phase_diffusion_no_cycle():
    with pytest.raises(ModelError, match="no stable root"):
        phase_diffusion("linear_damping", {"mu": 0.05, "zeta": 1}, 0.01)


def test_escape_cli_averaged_json(capsys):
    """kbm escape --json: the keys scripts use; averaged rate within O(kT/E_b) of Kramers."""
    assert main(["escape", "cdc", "-p", "mu=0.02", "-p", "Delta=3", "-p", "D=0.0005",
                 "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    for key in ("rate_averaged", "rate_simulated", "stderr", "barrier"):
        assert key in out
    assert out["rate_simulated"] is None and "refused" in out["message"]   # E_b/kT = 43
    assert out["rate_averaged"] / out["rate_kramers"] == pytest.approx(1, abs=3 / 43.5)
    # the barrier of Omega^2 x^2/2 + (Delta/k)(1 - cos k x) at its saddle, independently
    xs = out["saddles"][1]
    k = 2 * math.pi
    assert out["barrier"] == pytest.approx(xs**2 / 2 + 3 / k * (1 - math.cos(k * xs)),
                                           rel=1e-12)
    assert abs(xs + 3 * math.sin(k * xs)) < 1e-9   # g(x_s) = x + Delta sin(k x) = 0
    # no simulation: the averaged rate states its order, no error and no gap
    v = out["validity"]
    assert (v["averaged_order"], v["z"], v["flagged"], v["expected_error"],
            v["expected_error_source"]) == (1, None, False, None, "none")


def test_escape_averaged_rate_beyond_low_friction_is_flagged(capsys):
    """Issue 36, validity in every output: the averaged (energy-diffusion) rate is the
    low-friction limit (Kramers 1940; Hanggi, Talkner, Borkovec 1990, sec. IV.A), valid for
    delta = mu I(E_b)/kT << 1.  At mu = 0.2 (CDC, Delta = 3, kT = 0.35: delta = 1.1) it is
    far above the simulated first passages to the saddles, the same quantity; the gap is
    flagged in the JSON and printed as a WARNING with what to do."""
    argv = ["escape", "cdc", "-p", "mu=0.2", "-p", "Delta=3", "-p", "D=0.07"]
    assert main(argv + ["--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    v = out["validity"]
    z = (out["rate_averaged"] - out["rate_simulated"]) / out["stderr"]
    assert v["z"] == pytest.approx(z, rel=1e-12) and z > 4 and v["flagged"]
    assert v["expected_error"] == pytest.approx(
        abs(out["rate_averaged"] - out["rate_simulated"]) + 2 * out["stderr"], rel=1e-12)
    delta = 0.2 * out["action_at_barrier"] / out["kT"]
    assert delta > 1 and f"{delta:.3g}" in v["advice"] and "--method fokker-planck" in v["advice"]
    assert v["advice"] in out["warnings"]
    assert main(argv) == 0
    assert f"WARNING: {v['advice']}" in capsys.readouterr().out


@pytest.mark.parametrize("extra, text", [
    (["-p", "D=-1"], "D = -1: give the noise intensity of sqrt(2 D) xi as -p D=VALUE with D > 0"),
    (["-p", "D=nan"], "D = nan: give the noise intensity"),
    (["-p", "D=0"], "D > 0"),
    (["-p", "D=0.01", "--trajectories", "5"], "at least 20"),
    ([], "-p D=VALUE"),
])
def test_escape_cli_bad_input(extra, text, capsys):
    assert main(["escape", "cdc", "-p", "mu=0.02", "-p", "Delta=3", *extra]) == 2
    err = capsys.readouterr().err
    assert text in err and err.count("\n") == 1


def test_escape_cli_no_well(capsys):
    assert main(["escape", "vdp", "-p", "mu=0.02", "-p", "D=0.01"]) == 2
    assert "no barrier" in capsys.readouterr().err


def test_censored_rate_estimator():
    """Exponential waiting times (rate 0.3) censored at t_end = 4: the estimate
    k / sum min(tau, t_end) is within 3 standard errors of the true rate (fixed seed)."""
    import numpy as np

    from numerics.escape.simulate import censored_rate

    rng = np.random.default_rng(12345)
    tau = rng.exponential(1 / 0.3, size=4000)
    t_end = 4.0
    r, se = censored_rate(np.minimum(tau, t_end), tau < t_end)
    assert abs(r - 0.3) < 3 * se
    assert se == pytest.approx(r / math.sqrt(np.count_nonzero(tau < t_end)))
