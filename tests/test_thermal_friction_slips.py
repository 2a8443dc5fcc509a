"""The slips and backward jumps of ``numerics.thermal.friction`` (the compiled
``slip_stats``) against an independent count on the same trajectories.

The trajectory is drawn again by the kernels' ``sample_path`` (the same one-step map and
generator, every step kept) and counted by the well index ``n = floor(x/lam + 1/2)`` with a
hysteresis: a well counts as *settled* once the slider has stayed in it for a natural
period ``2 pi/Omega``; a slip is a change of the settled well forwards (however many
wells at once), a backward jump a change backwards, and a return to the settled well (an
oscillation in the well, a barrier top crossed and recrossed) is neither.  The slip force
is the largest spring force ``Omega^2 (v t - x)`` during the stay the slip leaves (its first
step out included), ``L_slip = v t - n lam`` at that first step out.  Paper eq. (12) (the CDC) and the SEDF with its
self-excitation attached to the stage (``sedf_comoving``), whose swings over several wells
often end in the well they left (counted as slips and backward jumps before).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from numerics.noise.langevin import langevin_system
from numerics.noise.seeds import trajectory_states
from numerics.thermal.friction import _times  # the run's burn-in, length and step


def _settled_count(t, x, v, lam, Omega, gap):
    """Slips, slip-force sum, backward jumps and ``L_slip`` sum of one sampled trajectory
    (``t, x`` at every step of the run) by the settled-well rule of the module docstring;
    the stay at the end closes the window (settled or not)."""
    well = np.floor(x / lam + 0.5)
    force = Omega**2 * (v * t - x)
    starts = np.concatenate(([0], np.nonzero(np.diff(well))[0] + 1))
    ends = np.concatenate((starts[1:], [len(x)]))
    # a stay is settled when the next crossing comes more than `gap` after its first one
    # (the first stay of the window and the last stay: settled by the window's edges)
    stay = np.append(t[starts[1:]] - t[starts[:-1]], math.inf)
    settled = stay > gap
    settled[0] = True
    slips = back = 0
    fsum = lsum = 0.0
    current, peak, leave = well[0], force[0], 0.0
    for s, e, ok in zip(starts, ends, settled):
        if not ok:
            continue
        n = well[s]
        if n > current:
            slips, fsum, lsum = slips + 1, fsum + peak, lsum + leave
        elif n < current:
            back += 1
        current, peak = n, force[s:e + 1].max()
        leave = v * t[e] - n * lam if e < len(x) else math.nan
    return slips, fsum, back, lsum


@pytest.mark.parametrize("model, params, D", [
    ("sedf_comoving", {"mu": 0.1, "Delta": 3.0, "beta": 1.0, "v": 1e-2}, 0.001),
    ("sedf_comoving", {"mu": 0.1, "Delta": 3.0, "beta": 1.0, "v": 1e-2}, 0.004),
    ("cdc", {"mu": 1.0, "Delta": 3.0, "v": 1e-2}, 0.04),
    ("cdc", {"mu": 0.1, "Delta": 3.0, "v": 1e-2}, 0.004),
])
def test_slips_equal_the_settled_well_count(model, params, D):
    """Per trajectory (4, ``wells = 5``, about the run's step): slips, backward jumps, the
    slip-force and ``L_slip`` sums of ``slip_stats`` equal the settled-well count of the
    same trajectory; the comoving SEDF has slips and backward jumps (its swings recross
    barrier tops), and the CDC's slips cross the wells of a slip together."""
    params = {**params, "lam": 1.0, "Omega": 1.0}
    s = langevin_system(model, params, D)
    v, gap = params["v"], 2 * math.pi
    run, burn, h_run = _times(s, v, 1.0, 5.0)
    # a power of two below the run's step: every time k h exact, so that sample_path's
    # t0 + k h and slip_stats' (t0 + n_burn h) + k h are the same numbers (else the swings
    # of the comoving SEDF part the two trajectories after a rounding of the stage position)
    h = 2.0 ** math.floor(math.log2(h_run))
    n_burn, n_run = round(burn / h), round(run / h)
    states = trajectory_states(3, 0, 4)
    y0 = np.zeros((4, 2))
    rows = s.kernels.slip_stats(s._p(), s.sigma, y0, 0.0, h, n_burn, n_run, states, 1.0, gap,
                                v)
    totals = np.zeros(3)
    for i in range(4):
        path = s.kernels.sample_path(s._p(), s.sigma, y0[i], 0.0, h, n_burn + n_run, 1,
                                     states[i])[n_burn + 1:]
        t = (n_burn + 1 + np.arange(n_run)) * h
        spring = params["Omega"]**2 * (v * t - path[:, 0])
        assert rows[i, 0] == pytest.approx(spring.mean(), rel=1e-9)  # the same trajectory
        slips, fsum, back, lsum = _settled_count(t, path[:, 0], v, 1.0, 1.0, gap)
        assert (rows[i, 1], rows[i, 4]) == (slips, back)
        assert rows[i, 2] == pytest.approx(fsum, rel=1e-9, abs=1e-9)
        assert rows[i, 5] == pytest.approx(lsum, rel=1e-9, abs=1e-9)
        totals += (slips, back, np.floor(path[-1, 0] + 0.5) - np.floor(path[0, 0] + 0.5))
    assert totals[0] > 0
    if model == "sedf_comoving":
        assert totals[1] > 0
