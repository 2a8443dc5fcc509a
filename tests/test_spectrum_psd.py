"""The ensemble PSD (numerics.spectrum.psd) against exact closed forms.

The Ornstein-Uhlenbeck process ``dx = -gamma x dt + sqrt(2 D) dW`` sampled every ``dt`` is
exactly the AR(1) sequence ``x_{n+1} = phi x_n + e_n`` with ``phi = exp(-gamma dt)`` and
``var e = (D/gamma)(1 - phi^2)`` (Gillespie, Phys. Rev. E 54, 2084 (1996), eq. 1.9), whose
one-sided PSD in angular frequency is exactly ``(dt/pi) var e/|1 - phi exp(-i omega dt)|^2``
on ``[0, pi/dt]``: the Lorentzian ``2 D/(pi (gamma^2 + omega^2))`` with its aliasing
(Wiener-Khinchin).  The estimate must agree within a few standard errors.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from numerics.errors import NumericsError
from numerics.spectrum import PSD, ensemble_psd
from numerics.spectrum.psd import ResolutionError


def _ou(n_traj: int, n: int, dt: float, gamma: float, D: float, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    phi = math.exp(-gamma * dt)
    s = math.sqrt(D / gamma * (1 - phi * phi))
    from scipy.signal import lfilter

    x0 = rng.standard_normal(n_traj) * math.sqrt(D / gamma)  # stationary start
    e = rng.standard_normal((n_traj, n)) * s
    e[:, 0] = x0
    return lfilter([1.0], [1.0, -phi], e, axis=1)  # x_k = phi x_{k-1} + e_k


def _ou_psd(omega, dt, gamma, D):
    phi = math.exp(-gamma * dt)
    var_e = D / gamma * (1 - phi * phi)
    return dt / math.pi * var_e / np.abs(1 - phi * np.exp(-1j * omega * dt)) ** 2


def test_ou_psd_matches_the_aliased_lorentzian():
    """OU's exact sampled PSD (Wiener-Khinchin, AR(1) form) within a few standard errors,
    and the integral equals the stationary variance D/gamma."""
    dt, gamma, D = 0.05, 1.0, 0.3
    x = _ou(64, 8192, dt, gamma, D, seed=1)
    p = ensemble_psd(x, dt, nperseg=1024)
    exact = _ou_psd(p.omega, dt, gamma, D)
    sel = p.omega > 2.5 * p.resolution  # the lowest bins carry the segment mean and leakage
    z = (p.mean[sel] - exact[sel]) / p.stderr[sel]
    assert np.max(np.abs(z)) < 4.5, np.max(np.abs(z))
    assert abs(np.mean(z)) < 0.2  # no bias in units of stderr, over ~500 bins
    assert 0.7 < np.mean(z * z) < 1.4  # the standard errors are honest
    # each segment's mean is removed: it carries about 2 D/(gamma^2 T_seg) of the variance
    t_seg = 1024 * dt
    assert abs(p.variance() - (D / gamma - 2 * D / (gamma ** 2 * t_seg))) < 0.01 * D / gamma
    # about 95 % of the bins' truths inside the 95 % band
    inside = np.mean((exact[sel] >= p.lower[sel]) & (exact[sel] <= p.upper[sel]))
    assert 0.9 < inside <= 1.0
    assert p.resolution == pytest.approx(2 * math.pi / (1024 * dt))
    assert p.omega[-1] == pytest.approx(math.pi / dt)


def test_resolution_keyword_and_too_short_run():
    """A requested resolution sets the segment; a run shorter than it is refused with the
    resolution it would give."""
    x = np.zeros((8, 1000))
    x[:, ::2] = 1.0
    p = ensemble_psd(x, 0.1, resolution=2 * math.pi / 50.0)
    assert p.resolution == pytest.approx(2 * math.pi / 50.0)
    with pytest.raises(ResolutionError, match=r"give at best 0\.06283"):
        ensemble_psd(x, 0.1, resolution=0.01)
    assert issubclass(ResolutionError, NumericsError)
    with pytest.raises(ResolutionError):
        ensemble_psd(x, 0.1, nperseg=1001)


@settings(max_examples=25, deadline=None)
@given(st.integers(2, 6), st.integers(6, 10), st.floats(0.01, 2.0), st.floats(0.1, 10.0))
def test_parseval_and_scaling(n_traj, log_n, dt, scale):
    """Parseval: the PSD's integral is the mean windowed variance, and the PSD scales as
    the square of x (a property of any spectral estimator)."""
    rng = np.random.default_rng(n_traj * 1000 + log_n)
    x = rng.standard_normal((n_traj, 2 ** log_n))
    p = ensemble_psd(x, dt, nperseg=2 ** log_n)
    from scipy.signal import get_window

    w = get_window("hann", 2 ** log_n)
    xc = x - x.mean(axis=1, keepdims=True)
    assert p.variance() == pytest.approx(np.mean(np.sum((w * xc) ** 2, axis=1) / np.sum(w * w)),
                                         rel=1e-9)
    q = ensemble_psd(scale * x, dt, nperseg=2 ** log_n)
    np.testing.assert_allclose(q.mean, scale ** 2 * p.mean, rtol=1e-9, atol=1e-300)
    assert np.all(p.lower <= p.mean) and np.all(p.mean <= p.upper) and np.all(p.lower >= 0)
    assert isinstance(p, PSD)
