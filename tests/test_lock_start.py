"""``kbm lock`` follows the locked state from inside the asked interval
(numerics.locking.start), against independent references.

Before, the state was followed from 0 whatever the interval: ``kbm lock sedf-dimer -p
mu=0.1 -p Delta=0.5 --vary kappa=0.1:1 --vary beta=0.5:1.5`` exited 2 with "no locked
state ... at beta = 0", outside the interval asked for.  The references:

- ``coupled-vdp`` at first order: the phase equation ``gamma' = mu (sigma - c sin gamma)``
  (equal amplitudes) locks for ``|sigma| <= c`` exactly, the closed-form tongue;
- its true upper edge at ``mu = 0.08``, ``c = 0.2``: the extremum of ``sigma(x2(0))`` along
  the locked branch shot with scipy's DOP853 (``tests/test_shooting_acceptance.py``, a
  saddle-node of cycles, Kuznetsov sec. 5.3), 0.20160636567730025;
- ``sedf-dimer`` in ``beta``: its in-phase cycle ``x1 = x2 = x(t)`` is the single slider's
  (paper eq. 3 at ``v = 0``), and the locked state is lost where the difference mode
  ``u = x1 - x2``, ``u'' + u = mu (-(beta x^2 - 1) u' - 2 beta x x' u - delta k cos(k x) u
  - 2 kappa u)``, gets a multiplier through +1: shot here with scipy.
"""

from __future__ import annotations

import contextlib
import functools
import io
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from _references import section_cycle
from numerics.cli import main
from kbm.model.coupled_builtins import get_coupled_model
from kbm.errors import ParameterError
from kbm.parameters.names import PhysicalAxis
from numerics.locking.start import followed_axis, side_limits, start_values
from numerics.locking.mutual import locking_region

#: the true upper edge of coupled-vdp at mu = 0.08, c = 0.2 by scipy (the reference of
#: tests/test_shooting_acceptance.py, which recomputes it)
FOLD = 0.20160636567730025


@settings(max_examples=200, deadline=None)
@given(lo=st.floats(-50, 50), width=st.floats(1e-6, 100))
def test_start_values_lie_in_the_interval(lo, width):
    """Every value tried lies in [lo, hi], none twice; 0 first when the interval holds it
    (the symmetric point of a 1:1 tongue), else the middle; the ends are tried; the side
    limits reach the interval's ends from the start."""
    hi = lo + width
    vals = start_values(lo, hi)
    assert all(lo <= v <= hi for v in vals) and len(set(vals)) == len(vals)
    assert vals[0] == (0.0 if lo <= 0 <= hi else pytest.approx(0.5 * (lo + hi)))
    assert lo in vals and hi in vals
    for at in vals:
        lim = side_limits(at, lo, hi)
        assert at - lim[-1] == pytest.approx(lo, abs=1e-12 * (1 + abs(lo)))
        assert at + lim[1] == pytest.approx(hi, abs=1e-12 * (1 + abs(hi)))


def test_vdp_edge_from_an_interval_without_zero():
    """``sigma`` in [0.1, 0.5]: the start lies inside it (0.15: the middle 0.3 is past the
    edge, and 0.2 = c sits on the order-1 fold, no start), the order-1 edge is c (closed
    form), the true edge the scipy fold to 1e-10, and the lower edges (outside) are not
    reported."""
    r = locking_region("coupled-vdp", {"mu": 0.08, "c": 0.2}, ("sigma", 0.1, 0.5), None,
                       (1,), 1e-9)
    assert len(r.starts) == 1 and 0.1 <= r.starts[0] <= 0.5
    assert [s for _, s in r.averaged[1]] == [pytest.approx(0.2, abs=1e-12)]
    assert len(r.true) == 1
    # measured: 0.20160636567732 (2e-14 from scipy), stated error 3.2e-11
    assert abs(r.true[0][1] - FOLD) < 1e-10
    assert abs(r.true[0][1] - FOLD) <= 10 * r.errors[0] + 1e-11


def _difference_mode_multiplier(beta: float, mu: float, delta: float, k: float,
                                kappa: float) -> float:
    """The multiplier of the difference mode nearest +1 on the dimer's in-phase cycle,
    shot with scipy's DOP853 (Newton on (x(0), T) on the section x' = 0)."""
    from scipy.integrate import solve_ivp

    def one(t, w):
        x, v = w
        return [v, -x + mu * (-(beta * x * x - 1) * v - delta * math.sin(k * x))]

    x0, T = section_cycle(one, 2 / math.sqrt(beta), 2 * math.pi)

    def ext(t, w):
        x, v, P = w[0], w[1], w[2:].reshape(2, 2)
        A = np.array([[0.0, 1.0],
                      [-1 - mu * (2 * beta * x * v + delta * k * math.cos(k * x) + 2 * kappa),
                       -mu * (beta * x * x - 1)]])
        return np.concatenate([one(t, w[:2]), (A @ P).ravel()])

    s = solve_ivp(ext, (0, T), [x0, 0.0, 1, 0, 0, 1], method="DOP853", rtol=1e-11,
                  atol=1e-12)
    m = np.linalg.eigvals(s.y[2:, -1].reshape(2, 2))
    return float(m[np.argmin(np.abs(m - 1))].real)


@pytest.mark.slow  # 4-7 s; the default run keeps its siblings (five-minute rule)
def test_sedf_dimer_edge_in_beta_against_the_difference_mode():
    """The reported case (``--vary beta`` on an interval without 0) at kappa = 0.1, on
    [0.65, 0.75]: the middle 0.7 and the grid's 0.6875, 0.7125, 0.675 are past the order-1
    edge 0.7198, so the state is followed from 0.725; the true lower edge is where the
    difference mode's multiplier crosses +1 (scipy, the root interpolated from beta = edge
    -+ 1e-4) to 1e-6; the upper edge (1.23) lies outside."""
    mu, delta, k, kappa = 0.1, 0.5 / 0.1, 2 * math.pi, 0.1
    r = locking_region("sedf-dimer", {"mu": mu, "Delta": 0.5, "kappa": kappa},
                       ("beta", 0.65, 0.75), None, (1,), 1e-7)
    assert r.coupling == "kappa" and r.starts == (pytest.approx(0.725),)
    assert len(r.true) == 1 and len(r.averaged[1]) == 1
    edge = r.true[0][1]
    h = 1e-4
    m_in, m_out = (_difference_mode_multiplier(b, mu, delta, k, kappa)
                   for b in (edge + h, edge - h))
    assert m_in < 1 < m_out  # stable inside the locked interval, unstable past its edge
    root = edge + h - 2 * h * (m_in - 1) / (m_in - m_out)
    # measured: edge 0.70261654, root 0.70261653 (1.4e-8 apart; bisection bracket 1e-7)
    assert abs(root - edge) < 1e-6, (edge, root)
    # the averaged order-1 edge (0.71983) is within O(mu) of it
    assert abs(r.averaged[1][0][1] - edge) < 0.05


@functools.lru_cache(maxsize=None)
def _dimer_axis(user: str, lo: float, hi: float) -> PhysicalAxis:
    return followed_axis(get_coupled_model("sedf-dimer"), {"mu": "0.1"}, user, lo, hi)


def test_physical_axis_is_the_scaled_one_over_the_mapped_interval():
    """``--vary Delta`` and ``--vary lam`` of the sliders are followed as ``delta = Delta/mu``
    and ``k = 2 pi/lam`` (the model's physical map) over the mapped interval; a model's own
    name is followed as it is; a map with a pole in the interval, or without mu, is
    refused in command-line terms."""
    dimer = get_coupled_model("sedf-dimer")
    ax = _dimer_axis("Delta", -0.1, 0.5)
    assert ax.name == "delta" and ax.span == pytest.approx((-1.0, 5.0), abs=1e-15)
    ax = _dimer_axis("lam", 0.2, 5.0)
    assert ax.name == "k" and ax.span == pytest.approx((2 * math.pi / 5, 2 * math.pi / 0.2))
    assert followed_axis(dimer, {}, "beta", 0.5, 1.5).to_user(0.75) == 0.75
    with pytest.raises(ParameterError, match=r"--vary lam=-1:1"):
        followed_axis(dimer, {"mu": "0.1"}, "lam", -1, 1)
    with pytest.raises(ParameterError, match=r"-p mu=VALUE"):
        followed_axis(dimer, {}, "Delta", 0.1, 1)


@settings(max_examples=100, deadline=None)
@given(x=st.floats(0.2, 5.0))
def test_physical_axis_maps_back(x):
    """A value found in the scaled parameter maps back to the physical one: Delta = mu
    delta, lam = 2 pi/k, the error by the derivative (|d lam/dk| = lam^2/(2 pi))."""
    assert _dimer_axis("Delta", -0.1, 0.5).to_user(x) == pytest.approx(0.1 * x, rel=1e-13)
    lam = _dimer_axis("lam", 0.2, 5.0)
    assert lam.to_user(2 * math.pi / x) == pytest.approx(x, rel=1e-13)
    assert lam.error(2 * math.pi / x, 1e-8) == pytest.approx(x * x / (2 * math.pi) * 1e-8,
                                                             rel=1e-4)


def test_sedf_dimer_edge_in_physical_delta_against_the_difference_mode():
    """``--vary Delta`` (physical) was followed as a name the slow flow does not hold: no
    edge was ever found.  On [-0.1, -0.03] at kappa = 0.5 the in-phase state is lost where
    the difference mode's multiplier crosses +1 (scipy at delta = Delta/mu), to 1e-6 in
    Delta."""
    mu, kappa = 0.1, 0.5
    r = locking_region("sedf-dimer", {"mu": mu, "kappa": kappa}, ("Delta", -0.1, -0.03),
                       None, (1,), 1e-7)
    assert r.detuning == "Delta" and -0.1 <= r.starts[0] <= -0.03
    assert len(r.true) == 1 and len(r.averaged[1]) == 1
    edge = r.true[0][1]  # measured: -0.04273894119, scipy root -0.04273894129
    h = 1e-5
    m_in, m_out = (_difference_mode_multiplier(1.0, mu, D / mu, 2 * math.pi, kappa)
                   for D in (edge + h, edge - h))
    assert m_in < 1 < m_out
    root = edge + h - 2 * h * (m_in - 1) / (m_in - m_out)
    assert abs(root - edge) < 1e-6, (edge, root)


def _kbm(*args: str) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = main(list(args))
    return status, out.getvalue(), err.getvalue()


def test_no_locked_state_in_the_interval_is_said_in_command_line_terms():
    """Beyond the tongue (|sigma| > c = 0.3 at first order) nothing locks: exit 2 with one
    line that names the interval as it was given and the values tried."""
    status, out, err = _kbm("lock", "coupled-vdp", "-p", "mu=0.1", "-p", "c=0.3",
                            "--vary", "sigma=0.5:1")
    assert status == 2 and out == ""
    line = err.strip()
    assert "\n" not in line and "no locked state" in line
    assert "--vary sigma=0.5:1" in line and "sigma in [0.5, 1]" in line
    assert "np.float64" not in line


@pytest.mark.slow
def test_cli_sedf_dimer_beta_interval_with_a_coupling_axis():
    """The command of the report (two kappa values instead of seven, ~12 s; the cheaper
    sibling is test_sedf_dimer_edge_in_beta_against_the_difference_mode): exit 0, both edges
    inside [0.5, 1.5] at each kappa, the start inside it, the death line at the start."""
    status, out, err = _kbm("lock", "sedf-dimer", "-p", "mu=0.1", "-p", "Delta=0.5",
                            "--vary", "kappa=0.1,1", "--vary", "beta=0.5:1.5")
    assert status == 0, err
    rows = [ln for ln in out.splitlines() if "true" in ln]
    assert len(rows) == 2
    for row in rows:
        true = [float(s) for s in row.split("true")[1].split(",")]
        assert len(true) == 2 and all(0.5 < s < 1.5 for s in true)
    assert "beta = 0:" not in out and "beta = 1:" in out
