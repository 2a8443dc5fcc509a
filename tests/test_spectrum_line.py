"""The linewidth of a noisy self-excited oscillator: averaged theory against simulation.

References checked: Lax's linewidth D_eff = D_phi + g^2 D_a/lambda^2 (Phys. Rev. 160, 290
(1967)) with D_phi = D/(2 omega0^2 a*^2) for x'' + x = mu F + sqrt(2 D) xi (van der Pol:
D/8 at a* = 2, Stratonovich, Topics vol. 2, ch. 9); the long-time phase diffusion of the
averaged equations (a quadrature over the stationary amplitude density) reduces to it as
D -> 0; the simulated phase-variance growth and mean frequency agree with it within a few
standard errors (fixed seeds); the same bytes on any worker count and after --resume.
"""

from __future__ import annotations

import dataclasses
import json
import math

import numpy as np
import pytest
from kbm.model.builtins import custom_model
from numerics.cli import main
from numerics.errors import NoCycleError
from numerics.spectrum.phase_diffusion import line_theory
from numerics.spectrum.psd import ResolutionError
from numerics.spectrum.simulate import simulate_line

CUBIC = "(1 - x**2)*xdot - alpha*x**3"


def test_vdp_linearised_linewidth_is_D_over_8():
    """Van der Pol: a* = 2, lambda = mu, no shear, D_eff = D/(2 a*^2) = D/8."""
    th = line_theory("vdp", {"mu": 0.1}, 0.004)
    assert th.amplitude == pytest.approx(2.0, abs=1e-12)
    assert th.relaxation == pytest.approx(0.1, rel=1e-12)
    assert th.shear == 0.0
    assert th.linewidth_linear == pytest.approx(0.004 / 8, rel=1e-12)
    assert th.frequency == pytest.approx(1.0, abs=1e-12)  # F odd in x': no shift at order 1


def test_cubic_stiffness_shear_widens_the_line_ten_times():
    """F = (1 - x^2) x' - alpha x^3: Duffing's backbone omega = 1 + 3 alpha mu a^2/8 gives g =
    3 alpha mu a/4 = 1.5 mu at a* = 2, lambda = mu: 1 + (g a*/lambda)^2 = 10."""
    th = line_theory(custom_model(CUBIC), {"mu": 0.05, "alpha": 1}, 0.001)
    assert th.shear == pytest.approx(0.075, rel=1e-12)
    assert th.enhancement == pytest.approx(10.0, rel=1e-12)
    assert th.linewidth_linear == pytest.approx(10 * 0.001 / 8, rel=1e-12)
    assert th.frequency_cycle == pytest.approx(1 + 3 * 0.05 * 4 / 8, rel=1e-12)


@pytest.mark.parametrize("mu, alpha", [(0.05, 0.0), (0.2, 1.0)])
def test_quadrature_reduces_to_lax_as_noise_falls(mu, alpha):
    """The exact long-time phase diffusion of the averaged equations tends to Lax's
    linearised D_eff as D -> 0 at fixed mu, the difference growing with D/mu."""
    model = custom_model(CUBIC)
    errs = [line_theory(model, {"mu": mu, "alpha": alpha}, kappa * mu).linewidth
            / line_theory(model, {"mu": mu, "alpha": alpha}, kappa * mu).linewidth_linear - 1
            for kappa in (1e-3, 1e-2, 1e-1)]
    assert abs(errs[0]) < 3e-3
    assert abs(errs[0]) < abs(errs[1]) < abs(errs[2]) < 0.2



@pytest.mark.parametrize("kappa", [1e-4, 1e-6, 1e-8])
@pytest.mark.parametrize("alpha, lax", [(1.0, 10 / 8), (0.0, 1 / 8)])
def test_quadrature_at_tiny_noise_is_the_small_noise_line(kappa, alpha, lax):
    """At D/mu = kappa -> 0 the quadrature's D_eff/D tends to Lax's closed form (1/a*^2 +
    g^2/lambda^2)/2 at a* = 2: 10/8 for the cubic stiffness alpha = 1 (g = 3/2, lambda = 1/2
    in units of mu), 1/8 for van der Pol (alpha = 0), with the first finite-noise correction
    of relative size kappa/2 (measured 5.00e-5, 5.0e-7, 4e-9 of the cubic's).  The density
    is (D/mu)^(1/2) wide: on the grid from 0 to a* it got a handful of points, and the
    integral F of (B - <B>) P, summed from a = 0, lost all its digits where P is exp(-60)
    of its peak (D_eff/D = 1.29 at 1e-4, 3.16 at 1e-6, 4.7 at 1e-8)."""
    mu = 0.1
    th = line_theory(custom_model(CUBIC), {"mu": mu, "alpha": alpha}, kappa * mu)
    assert th.linewidth / (kappa * mu) == pytest.approx(lax, rel=max(kappa, 1e-6))

def test_no_cycle_is_refused():
    """Linear damping has no limit cycle: no line to speak of."""
    with pytest.raises(NoCycleError, match="no limit cycle"):
        line_theory("linear_damping", {"mu": 0.1, "zeta": 1}, 0.01)


def _small_run(workers, store=None, trajectories=8):
    th = line_theory("vdp", {"mu": 0.2}, 0.02)
    return simulate_line("vdp", {"mu": 0.2}, 0.02, trajectories=trajectories, duration=800.0,
                         burn_in=20.0, window=(0.9, 1.1), resolution=0.01, tau_min=25.0,
                         amplitude=th.amplitude, dt=2 * math.pi / 200, seed=3,
                         workers=workers, store=store)


def test_same_bytes_on_any_worker_count_and_after_resume(tmp_path):
    """One seed per trajectory, combined in trajectory order: workers=1 and 2, and a stored
    run resumed, give the same numbers to the bit."""
    from numerics.store import PointStore

    a = _small_run(1)
    b = _small_run(2)
    with PointStore(tmp_path / "s.sqlite") as s:
        _small_run(1, s)
    with PointStore(tmp_path / "s.sqlite", resume=True) as s:
        c = _small_run(2, s)
    for other in (b, c):
        assert other.frequency == a.frequency and other.linewidth == a.linewidth
        assert np.array_equal(other.psd.mean, a.psd.mean)
        assert np.array_equal(other.m2, a.m2)


def test_vdp_short_ensemble_matches_the_averaged_line():
    """vdp mu = 0.2, D = 0.02: the simulated HWHM (phase-variance growth) within four standard
    errors of the averaged quadrature, and the frequency within four of the second-order
    averaged frequency (1 - mu^2/16 at zero noise; Bogoliubov-Mitropolsky) plus the scheme's
    bias."""
    th1 = line_theory("vdp", {"mu": 0.2}, 0.02)
    th2 = line_theory("vdp", {"mu": 0.2}, 0.02, order=2)
    # lags from 5/lambda = 25 to duration/8 = 750: many relaxation times
    sim = simulate_line("vdp", {"mu": 0.2}, 0.02, trajectories=32, duration=6000.0,
                        burn_in=50.0, window=(0.95, 1.05), resolution=0.005, tau_min=25.0,
                        amplitude=2.0, seed=1, workers=1)
    lw, fr = sim.linewidth, sim.frequency
    assert abs(lw.value - th1.linewidth) < 4 * lw.stderr, (lw, th1.linewidth)
    assert abs(fr.value - sim.step_bias - th2.frequency) < 4 * fr.stderr, (fr, th2.frequency)
    # the first-order frequency 1 is off by mu^2/16 = 2.5e-3, many standard errors
    assert abs(fr.value - 1.0) > 5 * fr.stderr


def test_too_short_run_names_the_resolution():
    with pytest.raises(ResolutionError, match=r"it gives 0\.0"):
        simulate_line("vdp", {"mu": 0.2}, 0.02, trajectories=8, duration=100.0, burn_in=0.0,
                      window=(0.9, 1.1), resolution=0.001, tau_min=5.0, amplitude=2.0)


@pytest.mark.parametrize("argv, message", [
    (["vdp", "-p", "mu=0.1", "-p", "D=0"], "D > 0 and finite (a linewidth needs noise"),
    (["vdp", "-p", "mu=0.1", "-p", "D=-0.5"], "D = -0.5"),
    (["linear_damping", "-p", "mu=0.1", "-p", "zeta=1", "-p", "D=0.01"], "no limit cycle"),
    (["vdp", "-p", "mu=0.1", "-p", "D=0.01", "--duration", "100"],
     "too short for the resolution"),
    (["vdp", "-p", "mu=0.1", "-p", "D=0.01", "-p", "zeta=1"], "unknown parameter 'zeta'"),
    (["vdp", "-p", "mu=0.1", "-p", "D=0.01", "--vary", "mu=0.1:0.2"], "varies the noise only"),
])
def test_cli_bad_input_one_line_exit_2(argv, message, capsys):
    assert main(["spectrum", *argv]) == 2
    err = capsys.readouterr().err.strip()
    assert message in err and "\n" not in err


def test_cli_json_contract_and_temperature(capsys):
    """The JSON keys scripts depend on; -p T=0.1 is D = mu T = 0.01."""
    assert main(["spectrum", "vdp", "-p", "mu=0.1", "-p", "T=0.1", "--no-simulation",
                 "--json"]) == 0
    rep = json.loads(capsys.readouterr().out)
    assert rep["D"] == pytest.approx(0.01)
    for key in ("linewidth", "frequency"):
        assert {"averaged", "simulated", "stderr"} <= set(rep[key])
    assert {"omega", "averaged", "simulated", "lower", "upper"} <= set(rep["psd"])
    assert rep["linewidth"]["averaged"] == pytest.approx(line_theory(
        "vdp", {"mu": 0.1}, 0.01).linewidth, rel=1e-12)
    # the averaged PSD integrates to the fundamental's variance <r_1>^2/2 + pedestal
    w, s = np.array(rep["psd"]["omega"]), np.array(rep["psd"]["averaged"])
    assert np.all(s > 0) and np.argmax(s) == len(w) // 2


def test_cli_simulated_json_and_figures(tmp_path, capsys):
    """A small run: simulated entries filled, band around the mean, figures written."""
    assert main(["spectrum", "vdp", "-p", "mu=0.2", "-p", "D=0.02", "--trajectories", "8",
                 "--duration", "1200", "--resolution", "0.006", "--workers", "1", "--json",
                 "--out", str(tmp_path)]) == 0
    rep = json.loads(capsys.readouterr().out)
    assert rep["linewidth"]["simulated"] > 0 and rep["linewidth"]["stderr"] > 0
    assert rep["frequency"]["stderr"] > 0
    p = {k: np.array(v) for k, v in rep["psd"].items() if isinstance(v, list)}
    assert p["omega"].shape == p["simulated"].shape == p["lower"].shape
    assert np.all(p["lower"] <= p["simulated"]) and np.all(p["simulated"] <= p["upper"])
    assert (tmp_path / "spectrum-vdp-psd.png").stat().st_size > 0
    assert (tmp_path / "spectrum-vdp-linewidth.png").stat().st_size > 0
    assert (tmp_path / "spectrum-vdp.json").exists()


@pytest.mark.slow
def test_vdp_mu_01_D_001_linewidth_and_frequency():
    """The issue's case: vdp mu = 0.1, D = 0.01, default run (64 trajectories): the HWHM
    within three standard errors of the averaged one, the frequency within three of the
    second-order averaged one (plus the scheme's bias)."""
    from numerics.spectrum.result import line_report

    r1 = line_report("vdp", {"mu": 0.1}, 0.01, workers=2)
    r2 = line_report("vdp", {"mu": 0.1}, 0.01, order=2, simulate=False)
    lw, fr = r1["linewidth"], r1["frequency"]
    assert abs(lw["averaged"] - lw["simulated"]) < 3 * lw["stderr"]
    f_sim = fr["simulated"] - fr["step_bias"]
    assert abs(r2["frequency"]["averaged"] - f_sim) < 3 * fr["stderr"]


@pytest.mark.slow
def test_cubic_stiffness_line_is_several_times_wider():
    """F = (1 - x^2) x' - alpha x^3, alpha = 1, mu = 0.025, D/mu = 0.1: the simulated HWHM is
    several times the isochronous D/(2 a*^2) (Kuramoto's shear), and the averaged
    (first-order) one is within 15 % (plus three standard errors) of it: its error is of
    order mu (+50 % at mu = 0.1, +120 % at mu = 0.2)."""
    from numerics.spectrum.result import line_report

    r = line_report(custom_model(CUBIC), {"mu": 0.025, "alpha": 1}, 0.0025, workers=2)
    lw = r["linewidth"]
    assert lw["simulated"] > 4 * r["theory"]["phase_diffusion"]
    rel_se = lw["stderr"] / lw["simulated"]
    assert abs(lw["averaged"] / lw["simulated"] - 1) < 0.15 + 3 * rel_se


def test_cli_vary_temperature_sweep(tmp_path, capsys):
    """--vary T=A:B:3 runs D = mu T at three values; the averaged HWHM grows with D (at small
    D/mu linearly: Lax's D_eff is proportional to D) and the linewidth figure is written."""
    assert main(["spectrum", "vdp", "-p", "mu=0.1", "--vary", "T=0.01:0.04:3",
                 "--no-simulation", "--json", "--out", str(tmp_path)]) == 0
    rep = json.loads(capsys.readouterr().out)
    Ds = [s["D"] for s in rep["sweep"]]
    assert Ds == pytest.approx([0.001, 0.0025, 0.004])
    lws = [s["linewidth"]["averaged"] for s in rep["sweep"]]
    assert lws[0] < lws[1] < lws[2]
    assert lws[2] / lws[0] == pytest.approx(4.0, rel=0.05)
    assert (tmp_path / "spectrum-vdp-linewidth.png").exists()


def test_floquet_phase_response_refuses_a_driven_model():
    """The phase response is that of an autonomous cycle: the model's one acceleration
    (drive included) of a slider pulled at ``v != 0`` has no limit cycle, refused with the
    package's error before any integration."""
    from kbm.errors import NonAutonomousError
    from numerics.spectrum.floquet import phase_response

    with pytest.raises(NonAutonomousError, match="stage velocity"):
        phase_response("sedf", {"mu": 0.1, "Delta": 1.5, "beta": 1.3, "lam": 1, "v": 0.1})


@pytest.mark.slow
def test_floquet_phase_response_limits():
    """The adjoint Floquet route (exact in mu, first order in D): van der Pol's <Z_v^2>
    tends to Lax's 1/(2 a*^2) = 1/8 as mu -> 0 (error O(mu^2)), and the cubic stiffness'
    tends to the averaged 10/8 from below, with an error falling like mu."""
    from numerics.spectrum.floquet import phase_response

    v = phase_response("vdp", {"mu": 0.05})
    assert v.normalisation_spread < 1e-8
    assert abs(v.zv2 - 0.125) < 0.1 * 0.05**2
    model = custom_model(CUBIC)
    e = [1.25 - phase_response(model, {"mu": m, "alpha": 1}).zv2 for m in (0.05, 0.025)]
    assert 0 < e[1] < e[0]
    assert 1.5 < e[0] / e[1] < 2.7  # first order in mu


def test_lorentzian_fit_stderr_is_the_scatter_of_independent_ensembles():
    """A phase-diffusion signal ``x = cos(t + sqrt(2 D_eff) W(t))`` has a Lorentzian line of
    half width ``D_eff`` at 1 (Stratonovich, *Topics in the Theory of Random Noise* I,
    ch. 3; the line of the spectra docs with no amplitude noise).  Over 48 independent
    ensembles of 16 trajectories the fitted half widths scatter about ``D_eff`` by their
    stated standard error: the least-squares covariance, which takes the correlated Welch
    bins as independent, stated 1/1.5 of the scatter (at D_eff = 0.01, 0.000188 against
    0.000285);
    the jackknife over trajectories states it."""
    from numerics.spectrum.linewidth import fit_lorentzian
    from numerics.spectrum.psd import ensemble_psd

    D_eff, h, N, K = 0.02, 1.0, 16, 48
    res = D_eff / 4
    n = 8 * math.ceil(2 * math.pi / (res * h))
    rng = np.random.default_rng(1)
    fits = []
    for _ in range(K):
        phase = np.cumsum(rng.standard_normal((N, n)) * math.sqrt(2 * D_eff * h), axis=1)
        x = np.cos(h * np.arange(n) + phase + rng.uniform(0, 2 * math.pi, (N, 1)))
        fit = fit_lorentzian(ensemble_psd(x, h, resolution=res), 1.0, D_eff)
        assert fit.success
        fits.append((fit.hwhm, fit.hwhm_stderr))
    width, stated = np.array(fits).T
    scatter = width.std(ddof=1)
    assert abs(width.mean() - D_eff) < 3 * scatter / math.sqrt(K)  # unbiased at res = D_eff/4
    assert 0.75 < scatter / stated.mean() < 1.3  # the sd of the scatter is 10 % at K = 48


def test_lorentzian_fit_states_where_its_stderr_is_the_least_squares_one(monkeypatch):
    """The fit's standard error says how it was found: the jackknife over trajectories, or
    the least-squares covariance (fewer than 8 trajectories, or a jackknife refit that fails),
    which the test above measured 1.5 times below the scatter of independent ensembles of the
    phase-diffusion line (Stratonovich, *Topics in the Theory of Random Noise* I, ch. 3)."""
    import scipy.optimize

    from numerics.spectrum.linewidth import fit_lorentzian
    from numerics.spectrum.psd import ensemble_psd

    D_eff, h = 0.02, 1.0
    res = D_eff / 4
    n = 8 * math.ceil(2 * math.pi / (res * h))
    rng = np.random.default_rng(2)

    def line(trajectories):
        phase = np.cumsum(rng.standard_normal((trajectories, n)) * math.sqrt(2 * D_eff * h),
                          axis=1)
        x = np.cos(h * np.arange(n) + phase + rng.uniform(0, 2 * math.pi, (trajectories, 1)))
        return ensemble_psd(x, h, resolution=res)

    assert fit_lorentzian(line(8), 1.0, D_eff).stderr_source == "jackknife over trajectories"
    few = fit_lorentzian(line(4), 1.0, D_eff)
    assert few.success and few.stderr_source.startswith("least squares")
    assert "4 trajectories" in few.stderr_source
    psd, calls, fit = line(8), [], scipy.optimize.curve_fit

    def failing_refit(*args, **kwargs):  # the whole fit succeeds, the third refit fails
        calls.append(1)
        if len(calls) == 4:
            raise RuntimeError("Optimal parameters not found")
        return fit(*args, **kwargs)

    monkeypatch.setattr(scipy.optimize, "curve_fit", failing_refit)
    failed = fit_lorentzian(psd, 1.0, D_eff)
    monkeypatch.undo()
    assert failed.success and failed.stderr_source.startswith("least squares")
    assert "without trajectory 2 failed" in failed.stderr_source
    least = fit_lorentzian(dataclasses.replace(psd, rows=None), 1.0, D_eff)
    assert failed.hwhm == least.hwhm and failed.hwhm_stderr == least.hwhm_stderr
