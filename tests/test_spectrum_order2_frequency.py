"""The expected error of ``kbm spectrum --order 2``'s line centre without a simulation
(:func:`numerics.spectrum.result.line_errors`, source ``"true cycle"``).

The reference the code does not produce: van der Pol's limit-cycle frequency as a series in
``mu`` (Andersen & Geer, SIAM J. Appl. Math. 42 (1982) 678; Nayfeh, *Perturbation Methods*
(1973) sec. 4.2.2, through ``mu^4``),

``omega = 1 - mu^2/16 + 17 mu^4/3072 + 35 mu^6/884736 + O(mu^8)``.

Second-order averaging gives the cycle's frequency ``omega0 + B(a*) = 1 - mu^2/16``, so its
true error is ``17 mu^4/3072 + O(mu^6)``; the averaged line centre adds the noise-induced
shift ``<B> - B(a*)`` (about ``-7 mu D/32`` here), which the true cycle does not measure and
a ``D/mu`` of 1e-6 makes negligible (under 0.4 % of the error at mu >= 0.1).
"""

from __future__ import annotations

import pytest

from numerics.spectrum.result import line_report, true_cycle


def _series(m: float) -> float:
    """Andersen & Geer's van der Pol frequency through ``mu^6``."""
    return 1 - m**2 / 16 + 17 * m**4 / 3072 + 35 * m**6 / 884736


@pytest.mark.parametrize("m", [0.1, 0.2, 0.3])
def test_true_cycle_frequency_is_the_series(m):
    """The adjoint-Floquet true cycle's frequency against the series to ``O(mu^6)``: the
    remainder is ``O(mu^8)`` (measured -1.32e-4 mu^8 at mu = 0.1, 0.2, 0.3, the series'
    next term ``-678899 mu^8/5096079360 = -1.332e-4 mu^8``; through
    ``mu^4`` only, the remainder is 3.8e-5, 3.4e-5, 2.8e-5 times ``mu^6``: the
    ``35/884736 = 3.96e-5`` term)."""
    f = true_cycle("vdp", {"mu": m}).frequency
    assert abs(f - _series(m)) < 2e-4 * m**8
    assert abs(f - _series(m) + 35 * m**6 / 884736) > 0.5 * 35 * m**6 / 884736


@pytest.mark.parametrize("m", [0.1, 0.2, 0.3])
def test_order_2_line_centre_states_the_true_error(m):
    """``--order 2 --no-simulation``: the line centre's stated error (was null, "none") is
    its true error ``|averaged - series|`` within 1 % (17 mu^4/3072 = 5.5e-07, 8.9e-06,
    4.5e-05), and it is the error of the cycle's frequency ``frequency.cycle`` exactly as
    the series states it (within its ``O(mu^8)`` remainder), plus the noise-induced shift
    counted whole (about -7 mu D/32: 0.4 % of it at D/mu = 1e-6)."""
    rep = line_report("vdp", {"mu": m}, 1e-6 * m, order=2, simulate=False)
    fr = rep["frequency"]
    assert fr["expected_error_source"] == "true cycle"
    true_error = abs(fr["averaged"] - _series(m))
    assert abs(fr["expected_error"] / true_error - 1) < 0.01, (fr, true_error)
    # the cycle's part plus the whole (here negligible) noise-induced shift
    stated = abs(fr["cycle"] - _series(m)) + abs(fr["averaged"] - fr["cycle"])
    assert abs(fr["expected_error"] - stated) < 2e-4 * m**8
