"""Following the SEDF cycle in its period beyond the branch's end (multiple shooting with
Poincare sections, the parameter free; numerics.cycles.long_period, issue 25).

Independent references: the saddle connection computed by shooting the saddles'
manifolds (numerics.cycles.manifolds), which the parameter must converge to, and the
period law T = -k ln|Delta_h - Delta| + c with k = 2/lambda_u computed at the saddles
(Shil'nikov), whose slope the points must follow while |Delta_h - Delta| is resolved.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from numerics import limit_cycle
from numerics.cycles.long_period import follow_period
from numerics.cycles.manifolds import saddle_connection

P = {"mu": 0.1, "beta": 1, "lam": 1}


def test_follow_the_period_to_the_heteroclinic_loop():
    start = limit_cycle("sedf", {**P, "Delta": 3.2})  # period 8.99
    pts = follow_period("sedf", P, "Delta", start.amplitude_max, start.period, 3.2, 22.0)
    T = np.array([q.period for q in pts])
    p = np.array([q.parameter for q in pts])
    assert T[-1] >= 22.0 and T[-1] > 2.4 * start.period
    assert np.all(np.diff(p) > -1e-12)  # Delta rises to its limit
    conn = saddle_connection("sedf", P, "Delta", (3.2, 3.3), 1.58, -1.58, -1, -1)
    assert abs(p[-1] - conn.parameter) < 1e-10
    # the unstable eigenvalue at the saddles x_s = +-1.5809 of x'' = -x - mu (x^2 - 1) x'
    # - Delta sin(2 pi x), by hand; the loop passes both
    xs, D, mu = conn.saddles[0], conn.parameter, P["mu"]
    a = -1 - 2 * math.pi * D * math.cos(2 * math.pi * xs)
    b = -mu * (xs**2 - 1)
    lam_u = (b + math.sqrt(b * b + 4 * a)) / 2
    k = 2 / lam_u
    sel = (conn.parameter - p) > 1e-9
    slope = np.polyfit(-np.log(conn.parameter - p[sel]), T[sel], 1)[0]
    assert abs(slope - k) < 0.05 * k, (slope, k)


@pytest.mark.slow
def test_twenty_times_the_start_period():
    """Issue 25: the branch followed until the period is 20 times its start (6.287 at
    Delta = 0), 130, with the continuity residual at most 1e-8 (about a minute).  From
    T ~ 22 on, |Delta_h - Delta| < exp(-T/k) is below double precision: Delta stays at
    the connection and the longer orbits wait at the saddles within the residual."""
    start = limit_cycle("sedf", {**P, "Delta": 3.2})
    pts = follow_period("sedf", P, "Delta", start.amplitude_max, start.period, 3.2, 130.0,
                        tol=1e-8)
    conn = saddle_connection("sedf", P, "Delta", (3.2, 3.3), 1.58, -1.58, -1, -1)
    assert pts[-1].period >= 20 * 2 * math.pi * 1.0006  # 20 x the van der Pol period 6.287
    assert max(q.residual for q in pts) <= 1e-8
    assert abs(pts[-1].parameter - conn.parameter) < 1e-10


def test_branch_continues_in_its_period():
    """continue_cycles(follow_period=F): past the homoclinic end the branch goes on in the
    period to F times the start's; the parameter converges to the saddle connection of the
    manifolds' shooting (independent), and the non-trivial multiplier (Liouville, summed
    over the segments) falls like exp(-|div| T) near the saddles."""
    from numerics.cycles.continuation import continue_cycles

    br = continue_cycles("sedf", {**P, "Delta": 3.2}, "Delta", (3.2, 4.0), directions=(1,),
                         follow_period=2.5)
    T0 = br.points[0].period
    assert br.points[-1].period >= 2.5 * T0 - 1e-9
    conn = saddle_connection("sedf", P, "Delta", (3.2, 3.3), 1.58, -1.58, -1, -1)
    assert abs(br.points[-1].parameter - conn.parameter) < 1e-9
    end = [s for s in br.special if s.kind == "homoclinic"][0]
    assert "followed in its period" in end.message
    long = [q for q in br.points if q.period > 12.0]
    mults = [abs(q.multipliers[1]) for q in long]
    assert all(b < a for a, b in zip(mults, mults[1:]))  # stable, ever more strongly
    assert all(q.stable for q in long)


@pytest.mark.slow
def test_branch_from_delta_zero_to_twenty_times_its_period():
    """Issue 25, the command's path (``kbm branch ... --follow-period 20``): from the van der
    Pol cycle at Delta = 0 the branch and its continuation in the period reach 20 times the
    start's period (125.7), the periods rising, the parameter at the manifolds' connection.
    The multiple shooting can stall from one start (a mesh waiting at the saddles); the
    branch then restarts it from an earlier point (about 30 s)."""
    from numerics.cycles.continuation import continue_cycles

    br = continue_cycles("sedf", {**P, "Delta": 0.0}, "Delta", (0.0, 4.0), follow_period=20)
    T = np.array([q.period for q in br.points])
    assert T[-1] >= 20 * T[0] - 1e-9 and np.all(np.diff(T) > 0)
    conn = saddle_connection("sedf", P, "Delta", (3.2, 3.3), 1.58, -1.58, -1, -1)
    assert abs(br.points[-1].parameter - conn.parameter) < 1e-10
    assert max(q.residual for q in br.points) < 1e-8
