"""The cost bound of the driven slider's explicit integration (numerics.sliding.stiffness).

The reference is the linear stability of explicit Runge-Kutta methods (Hairer & Wanner,
*Solving ODEs II*, sec. IV.2): a step ``h`` is stable only for ``h |lambda| <= c`` with ``c``
the real stability interval (about 6 for DOP853), so a run through a damping with
``|dD/dx'| = lambda(t)`` takes at least ``int lambda dt / c`` steps.
"""

import time

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from kbm.errors import ParameterError
from numerics.errors import IntegrationError
from numerics.sliding.reference import MAX_STIFF_STEPS, slide
from numerics.sliding.stiffness import STABILITY_INTERVAL, StepGuard, stiff_steps, stiff_t_end


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
