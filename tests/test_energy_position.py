"""The position scheme (numerics.energy.position) where g is linear: against KBM and shooting.

For ``g = x`` order 1 of every scheme is the energy balance, which is KBM's order 1
exactly.  Beyond, the position scheme is not a truncated series: its order-N
frequency agrees with KBM's order N only up to the common error ``O(mu**(N+1))``
(``O(mu**4)`` at N = 2, 3 and ``O(mu**6)`` at N = 4 for van der Pol, whose
frequency is even in mu), while its first-harmonic amplitude and Floquet
multiplier are more accurate than KBM's at the same order (the whole waveform is
kept, not its expansion).
"""

import json

import numpy as np
import pytest

import kbm
import numerics
from kbm.errors import OrderError
from numerics.energy import predict_cycles

MUS = np.array([0.2, 0.1, 0.05])


def _slope(mus, errs):
    return np.polyfit(np.log(mus), np.log(np.abs(errs)), 1)[0]


@pytest.fixture(scope="module")
def vdp():
    true = {mu: numerics.limit_cycle("vdp", {"mu": mu}) for mu in MUS}
    out = {}
    for N in (1, 2, 3, 4):
        r = kbm.derive("vdp", N)
        for mu in MUS:
            (k,) = kbm.averaged_cycles(r, {"mu": mu})
            (p,) = predict_cycles("vdp", {"mu": mu}, order=N).cycles
            out[N, mu] = (p, k, true[mu])
    return out


def test_vdp_order_1_is_kbm(vdp):
    """Order 1 (energy balance) equals KBM order 1: amplitude, frequency, multiplier."""
    for mu in MUS:
        p, k, _ = vdp[1, mu]
        assert p.scheme == "energy balance"
        assert p.amplitude_first_harmonic == pytest.approx(k.amplitude, abs=1e-9)
        assert p.frequency == pytest.approx(k.frequency, abs=1e-12)
        assert p.floquet_multiplier == pytest.approx(k.floquet_multiplier, abs=1e-9)


@pytest.mark.parametrize("N,power", [(2, 4), (3, 4), (4, 6)])
def test_vdp_frequency_agrees_with_kbm_to_the_order(vdp, N, power):
    """|omega_position(N) - omega_KBM(N)| ~ mu**power (both err by that order), and the
    position scheme's frequency error against shooting has the same slope."""
    d = [vdp[N, mu][0].frequency - vdp[N, mu][1].frequency for mu in MUS]
    e = [vdp[N, mu][0].frequency - vdp[N, mu][2].frequency for mu in MUS]
    assert _slope(MUS, d) == pytest.approx(power, abs=0.3)
    assert _slope(MUS, e) == pytest.approx(power, abs=0.3)
    assert all(vdp[N, mu][0].scheme == "position" for mu in MUS)


def test_vdp_position_amplitude_and_multiplier(vdp):
    """Order 2: first-harmonic amplitude and multiplier errors ~ mu**4 (KBM's order 2: mu**2,
    its amplitude correction comes at order 3)."""
    for q, t in (("amplitude_first_harmonic", "amplitude_first_harmonic"),
                 ("floquet_multiplier", None)):
        err = []
        for mu in MUS:
            p, _, true = vdp[2, mu]
            ref = getattr(true, t) if t else true.floquet_multipliers[1].real
            err.append(getattr(p, q) - ref)
        assert _slope(MUS, err) > 3.7
    p, k, true = vdp[2, 0.1]
    assert (abs(p.amplitude_first_harmonic - true.amplitude_first_harmonic)
            < 0.1 * abs(k.amplitude - true.amplitude_first_harmonic))


def test_h_not_odd_period_orders():
    """h = (1 - x^2) x' + x x'^2/2 (not odd in x'), g = x: order N has period error
    ~ mu**(N+1) (order 1 is then refined by one integration), N = 1, 2, 3."""
    model = kbm.custom_model("(1 - x**2)*xdot + x*xdot**2/2", omega0=1)
    mus = np.array([0.1, 0.05, 0.025])
    err = {N: [] for N in (1, 2, 3)}
    for mu in mus:
        (c1,) = predict_cycles(model, {"mu": mu}, order=1).cycles
        assert c1.scheme == "position"
        true = numerics.limit_cycle(model, {"mu": mu}, guess=(c1.amplitude_max, c1.period))
        for N in (1, 2, 3):
            (c,) = predict_cycles(model, {"mu": mu}, order=N).cycles
            err[N].append(c.period - true.period)
    for N in (1, 2, 3):
        assert _slope(mus, err[N]) == pytest.approx(N + 1, abs=0.3)


def test_scheme_arguments_and_json():
    """Unknown scheme: ValueError; rate_order with the position scheme: OrderError; rate_order
    alone selects the energy-angle scheme; the scheme is in the JSON."""
    with pytest.raises(ValueError):
        predict_cycles("vdp", {"mu": 0.1}, order=2, scheme="series")
    with pytest.raises(OrderError):
        predict_cycles("vdp", {"mu": 0.1}, order=2, scheme="position", rate_order=3)
    (c,) = predict_cycles("vdp", {"mu": 0.1}, order=2, rate_order=3).cycles
    assert c.scheme == "energy-angle"
    P = predict_cycles("vdp", {"mu": 0.1}, order=2)
    js = json.loads(json.dumps(P.to_json(), allow_nan=False))
    assert js["cycles"][0]["scheme"] == "position" and js["reason"] == ""
