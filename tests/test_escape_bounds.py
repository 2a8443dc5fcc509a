"""``kbm escape`` far below ``E_b/kT = 1`` refuses at once instead of running for minutes.

At ``kT = D/mu = 1000`` against the CDC's barrier ``E_b = 1.087`` (mu = 0.1, Delta = 3) no
escape rate is defined (the barrier does not hold the slider; Hanggi, Talkner and
Borkovec, Rev. Mod. Phys. 62 (1990) 251: rate theory needs ``E_b >> kT``), and the averaged
envelope, cut ``40 kT`` above the well, spanned hundreds of the potential's ripples: the
review's run was still in ``adaptive_panels`` of the outer annulus after 120 s.  The barrier
in the message is checked against ``G(x_s) - G(0)`` at the saddle ``g(x_s) = 0`` found by
root bracketing (an independent route to the phase portrait's).
"""

from __future__ import annotations

import time

import numpy as np
import pytest
from scipy.optimize import brentq

from kbm.model.conservative import split_conservative
from kbm.errors import ParameterError
from numerics.escape.report import NO_RATE_BARRIER_OVER_KT, escape_report


def _barrier() -> float:
    split = split_conservative("cdc", {"mu": "0.1", "Delta": "3", "Omega": "1", "lam": "1"})
    g, _, G, _ = split.numpy_functions()
    xs = brentq(lambda x: float(g(np.array(x))), 0.5, 0.7, xtol=1e-14)
    return float(G(np.array(xs)) - G(np.array(0.0)))


def test_escape_far_below_the_thermal_energy_is_refused_at_once(capsys):
    from numerics.cli import main

    t0 = time.monotonic()
    status = main(["escape", "cdc", "-p", "mu=0.1", "-p", "Delta=3", "-p", "D=100",
                   "--no-simulation"])
    took = time.monotonic() - t0
    out = capsys.readouterr()
    assert status == 2 and out.out == "" and took < 30
    lines = out.err.strip().splitlines()
    assert len(lines) == 1
    Eb = _barrier()
    assert f"E_b/kT = {Eb * 0.1 / 100:.3g} < {NO_RATE_BARRIER_OVER_KT:g}" in lines[0]
    assert f"barrier E_b - E_0 = {Eb:.4g}" in lines[0] and "kT = D/mu = 1000" in lines[0]
    assert f"lower D to {Eb * 0.1 / 2:.3g}" in lines[0]


def test_the_library_refuses_before_the_envelope():
    with pytest.raises(ParameterError, match="no escape rate"):
        escape_report("cdc", {"mu": "0.1", "Delta": "3", "D": "30"}, simulate=False)
