"""``numerics.sliding.potential.slip_energy``: the one-well quasi-static slip energy of the
Prandtl-Tomlinson slider (D'Acunto, eq. 4 and Section 2), against scipy applied to eq. (4)
written here by hand.

``U(x, L) = Omega^2 (x - L)^2/2 - (Delta lam/2 pi) cos(2 pi x/lam)``.  The stick state is lost
where ``dU/dx = d^2U/dx^2 = 0`` (found here by ``brentq`` on the typed ``d^2U/dx^2`` and the
linear ``dU/dx = 0`` for ``L``); the slider lands in the next minimum ``x1`` of ``U(., L0)``
(the first upward zero of the typed ``dU/dx`` beyond ``x0``); ``Delta W = U(x0, L0) - U(x1,
L0)``.  Stick-slip exists only for ``eta = Delta k/Omega^2 > 1`` (Tomlinson's criterion).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from kbm.errors import ParameterError
from numerics.sliding.potential import slip_energy


def _by_hand(Delta: float, lam: float, Omega: float) -> float:
    k = 2 * math.pi / lam

    def U(x, L):
        return Omega**2 * (x - L)**2 / 2 - Delta / k * math.cos(k * x)

    # d^2U/dx^2 = Omega^2 + Delta k cos(k x): its root on the rising flank (0, lam/2)
    x0 = brentq(lambda x: Omega**2 + Delta * k * math.cos(k * x), 0.0, lam / 2, xtol=1e-15)
    L0 = x0 + Delta * math.sin(k * x0) / Omega**2      # dU/dx = 0 solved for L
    # dU/dx(., L0) has a double root at x0 (a maximum of dU/dx: d^2U/dx^2 changes sign
    # there), so U falls past x0 and x1 is the first upward zero of dU/dx after it (a grid
    # of lam/4096 finds the bracket, brentq the root)
    dU = lambda x: Omega**2 * (x - L0) + Delta * math.sin(k * x)  # noqa: E731
    xs = x0 + lam * np.arange(1, 2 * 4096) / 4096
    g = np.array([dU(x) for x in xs])
    up = np.flatnonzero((g[:-1] < 0) & (g[1:] >= 0))[0]
    x1 = brentq(dU, xs[up], xs[up + 1], xtol=1e-15)
    return U(x0, L0) - U(x1, L0)


@pytest.mark.parametrize("Delta, lam, Omega", [
    (3.0, 1.0, 1.0),     # the paper's (Fig. 5)
    (3.0, 1.0, 2.0),     # strong spring: one-well slips (tests/test_paper_sliding.py)
    (0.5, 2.0, 0.7),     # eta = 3.2
    (0.2, 1.0, 1.0),     # eta = 1.26, close to Tomlinson's threshold
])
def test_slip_energy_is_the_drop_from_the_saddle_node_to_the_next_minimum(Delta, lam, Omega):
    """``Delta W = U(x0, L0) - U(x1, L0)`` (paper Section 2) from scipy on eq. (4) typed."""
    assert slip_energy(Delta, lam, Omega) == pytest.approx(_by_hand(Delta, lam, Omega),
                                                           rel=1e-9, abs=1e-12)


@pytest.mark.parametrize("Delta, lam, Omega", [(0.0, 1.0, 1.0), (0.15, 1.0, 1.0),
                                               (0.3, 1.0, 1.5)])
def test_no_stick_slip_below_tomlinson_threshold(Delta, lam, Omega):
    """``Delta k <= Omega^2``: ``U(., L)`` has one minimum for every ``L``, no slip."""
    assert Delta * 2 * math.pi / lam <= Omega**2
    assert slip_energy(Delta, lam, Omega) is None


@pytest.mark.parametrize("kw, words", [
    ({"Delta": -1.0}, "Delta must be >= 0"),
    ({"Delta": math.nan}, "Delta must be finite"),
    ({"Delta": 3.0, "lam": 0.0}, "lam must be > 0"),
    ({"Delta": 3.0, "Omega": -1.0}, "Omega must be > 0"),
])
def test_bad_parameters_are_refused_with_what_to_change(kw, words):
    with pytest.raises(ParameterError, match=words):
        slip_energy(**kw)
