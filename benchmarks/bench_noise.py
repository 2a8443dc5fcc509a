"""Time the Langevin integrator of numerics.noise against baselines, in the same run.

Run: ``python benchmarks/bench_noise.py``

The model is the CDC at rest (paper eq. 12 with noise: ``x'' + mu x' + Delta sin(2 pi x)
+ x = sqrt(2 D) xi``, mu = 0.1, Delta = 3, D = 0.1, kT = 1), one core, warm (compiled
before the clock starts).

1. **Raw step rate** of the toolkit (Kloeden-Platen order-2.0 weak scheme, two force
   evaluations and one uniform number per step) against a hand-written numba
   Euler-Maruyama loop on the same model (one force evaluation and one
   ``np.random.standard_normal()`` per step).  Target: at least 0.7 of its rate.
2. **Steps for the same weak error**, on the linear oscillator ``x'' + 2 x' + x =
   sqrt(2 D) xi`` whose stationary ``<x^2> = D/2`` is exact (Risken sec. 10.1): each
   scheme's stationary ``<x^2>`` follows exactly from its linear map (the discrete
   Lyapunov equation), so the step ``h`` each needs for a relative weak error of
   1e-3 and 1e-4 is found by bisection and the steps per unit time compared.  The
   toolkit's error at its step is then confirmed by a Monte Carlo run (within 3 standard
   errors).  Target: at least 3x fewer steps than Euler-Maruyama.
3. The toolkit against a **pure-numpy vectorised ensemble** (the same scheme, arrays of
   trajectories advanced together, ``numpy.random.Generator`` for the increments).
"""

from __future__ import annotations

import math
import time

import numpy as np
from numba import njit
from scipy.linalg import solve_discrete_lyapunov

from numerics.noise import langevin_system
from numerics.noise.ensemble import stationary_ensemble

MU, DELTA, D = 0.1, 3.0, 0.1
K = 2 * math.pi


@njit(cache=True)
def _em_cdc(n_traj, n, h, sigma, mu, delta, k, seed):
    """Hand-written Euler-Maruyama on the CDC: one force evaluation, one normal per step."""
    np.random.seed(seed)
    acc = 0.0
    sq = math.sqrt(h)
    for _ in range(n_traj):
        x, v = 0.0, 0.0
        for _ in range(n):
            a = -x - mu * v - mu * delta * math.sin(k * x)
            x, v = x + v * h, v + a * h + sigma * sq * np.random.standard_normal()
        acc += x * x
    return acc


def _numpy_ensemble(n_traj, n, h, sigma, rng):
    """The same weak scheme, vectorised over trajectories in numpy."""
    x = np.zeros(n_traj)
    v = np.zeros(n_traj)
    r3 = math.sqrt(3 * h)
    for _ in range(n):
        u = rng.random(n_traj)
        dw = np.where(u < 1 / 6, -r3, np.where(u < 1 / 3, r3, 0.0)) * sigma
        a0 = -x - MU * v - DELTA * np.sin(K * x)
        xb = x + v * h
        vb = v + a0 * h + dw
        a1 = -xb - MU * vb - DELTA * np.sin(K * xb)
        x, v = x + 0.5 * (v + vb) * h, v + 0.5 * (a0 + a1) * h + dw
    return x


def rates() -> None:
    system = langevin_system("cdc", {"mu": MU, "Delta": DELTA, "lam": 1, "Omega": 1}, D)
    h, n, m = 0.025, 20000, 64
    y0 = np.zeros((m, 2))
    system.final_states(y0[:2], 10 * h, h)  # compile / load
    _em_cdc(2, 10, h, math.sqrt(2 * D), MU, DELTA / MU, K, 1)
    t0 = time.perf_counter()
    system.final_states(y0, n * h, h, seed=1)
    t_kit = time.perf_counter() - t0
    t0 = time.perf_counter()
    _em_cdc(m, n, h, math.sqrt(2 * D), MU, DELTA / MU, K, 1)
    t_em = time.perf_counter() - t0
    t0 = time.perf_counter()
    m_np = 4096
    n_np = 2000
    _numpy_ensemble(m_np, n_np, h, math.sqrt(2 * D), np.random.default_rng(1))
    t_np = time.perf_counter() - t0
    r_kit, r_em, r_np = m * n / t_kit, m * n / t_em, m_np * n_np / t_np
    print("1. raw step rate on the CDC (one core, warm)")
    print(f"   toolkit (KP 15.1.3, 2 force evaluations/step): {r_kit / 1e6:8.2f} M steps/s")
    print(f"   hand-written numba Euler-Maruyama:              {r_em / 1e6:8.2f} M steps/s")
    print(f"   ratio toolkit/EM = {r_kit / r_em:.2f} (target >= 0.7)")
    print(f"3. pure-numpy vectorised ensemble (same scheme, {m_np} trajectories): "
          f"{r_np / 1e6:.2f} M steps/s; toolkit/numpy = {r_kit / r_np:.1f}")


def _stationary_error(h: float, scheme: str, gamma: float = 2.0) -> float:
    A = np.array([[0.0, 1.0], [-1.0, -gamma]])
    eye = np.eye(2)
    if scheme == "kp":
        M = eye + h / 2 * (A + A @ (eye + A * h))
        c = h / 2 * A @ np.array([0.0, 1.0]) + np.array([0.0, 1.0])
    else:
        M = eye + A * h
        c = np.array([0.0, 1.0])
    var = solve_discrete_lyapunov(M, np.outer(c, c) * 2 * D * h)[0, 0]
    return (var - D / gamma) / (D / gamma)


def _step_for(target: float, scheme: str) -> float:
    lo, hi = 1e-6, 0.5
    for _ in range(100):
        mid = math.sqrt(lo * hi)
        if abs(_stationary_error(mid, scheme)) > target:
            hi = mid
        else:
            lo = mid
    return lo


def steps_for_error() -> None:
    print("2. steps per unit time for the same weak error of the stationary <x^2> = D/gamma "
          "(linear oscillator, gamma = 2)")
    for target in (1e-3, 1e-4):
        h_kp, h_em = _step_for(target, "kp"), _step_for(target, "em")
        print(f"   relative error {target:g}: toolkit h = {h_kp:.4g}, Euler-Maruyama h = "
              f"{h_em:.4g}: {h_kp / h_em:.0f}x fewer steps (target >= 3)")
    h = 0.2
    ens = stationary_ensemble("linear_damping", {"mu": 1, "zeta": 1}, D, trajectories=40,
                              t_end=1e5, burn_in=10.0, dt=h, seed=5, workers=1)
    exact = D / 2
    own = exact * (1 + _stationary_error(h, "kp"))
    z = (ens.x2.value - own) / ens.x2.stderr
    print(f"   Monte Carlo at h = {h}: <x^2> = {ens.x2.value:.6g} +- {ens.x2.stderr:.2g}; "
          f"exact {exact:g}, the scheme's own {own:.6g} "
          f"({z:+.2f} standard errors)")


if __name__ == "__main__":
    rates()
    steps_for_error()
