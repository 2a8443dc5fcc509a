"""Time the forced-oscillator tools, against a hand-written scipy shooting in the same run.

Run: ``python benchmarks/bench_forced.py``

1. Duffing primary resonance, the forced KBM expansion to order 3 (symbolic, exact):
   :func:`kbm.expansion.forced.derive_forced` from scratch (target: under 1 s).
2. The true frequency-response curve of Duffing (mu = 0.05, zeta = 0.1, alpha = 1,
   h = 0.5, sigma from -1 to 3) with about 400 points per branch, stable and unstable, each
   with its Floquet multipliers:
   :func:`numerics.shooting.forced_branch.numeric_response` (compiled DOP853,
   pseudo-arclength; warm: the compiled flow loaded by a first short run; target: under
   10 s).
3. The baseline: a hand-written shooting with :func:`scipy.integrate.solve_ivp` (DOP853,
   Newton with a finite-difference Jacobian, the monodromy matrix by finite differences
   for the multipliers), started from the continuation's own solution at each point (so
   it only has to confirm it).  It is run on every 10th point of the curve and its time
   per point is multiplied out; the largest difference of the responses is printed.
4. Smooth F: the slider seen from its stage (``sin(k x + theta)``) to order 3 by the numeric
   backend (:func:`kbm.backend.forced.numeric_derive_forced`, to 1e-9) against the exact engine on
   the degree-17 Taylor polynomial of the same ``F`` (the only exact route there is), and
   their largest difference.
"""

from __future__ import annotations

import math
import time

import numpy as np
import sympy as sp
from scipy.integrate import solve_ivp

from kbm.model.forced import ForcedOscillator
from kbm.expansion.forced import derive_forced
from kbm.backend.forced import numeric_derive_forced
from kbm.model.forced import nu, phi, sigma, theta
from kbm.symbols import a, x, xdot
from numerics.flow.forced_system import ForcedSystem
from numerics.shooting.forced_branch import numeric_response

VALS = {"mu": 0.05, "zeta": 0.1, "alpha": 1, "h": 0.5}


def scipy_shooting(sigma: float, y0, mu=0.05, zeta=0.1, alpha=1.0, h=0.5, rtol=1e-10):
    """Newton on ``y(T) - y0`` with scipy's DOP853; returns the response and multipliers."""
    nu = 1 + mu * sigma
    T = 2 * math.pi / nu

    def f(t, y):
        return [y[1], -y[0] + mu * (-2 * zeta * y[1] - alpha * y[0]**3 + h * math.cos(nu * t))]

    def P(y):
        return solve_ivp(f, (0, T), y, method="DOP853", rtol=rtol, atol=rtol).y[:, -1]

    def monodromy(y, Py):
        return np.column_stack([(P(y + 1e-7 * e) - Py) / 1e-7 for e in np.eye(2)])

    y = np.array(y0, float)
    for _ in range(30):
        Py = P(y)
        M = monodromy(y, Py)
        dy = np.linalg.solve(M - np.eye(2), y - Py)
        y = y + dy
        if np.max(np.abs(dy)) < 1e-10:
            Py = P(y)
            return y, np.linalg.eigvals(monodromy(y, Py))
    raise RuntimeError(f"scipy shooting did not converge at sigma = {sigma}")


def main() -> None:
    derive_forced("duffing-forced", 1)  # imports
    t0 = time.perf_counter()
    res = derive_forced("duffing-forced", 3)
    t_sym = time.perf_counter() - t0
    print(f"Duffing primary resonance, KBM order 3 (symbolic, exact): {t_sym:.3f} s "
          f"(under 1 s: {t_sym < 1})")

    sf = res.slow_flow(VALS, order=2)
    system = ForcedSystem("duffing-forced", VALS)
    numeric_response(system, sf, (-1, 3), (1e-3, 4), n_points=20)  # warm the compiled flow
    system = ForcedSystem("duffing-forced", VALS)
    t0 = time.perf_counter()
    nr = numeric_response(system, sf, (-1, 3), (1e-3, 4), n_points=400)
    t_num = time.perf_counter() - t0
    pts = [o for b in nr.branches for o in b]
    n_st = sum(o.stable for o in pts)
    print(f"true response curve: {len(pts)} responses ({n_st} stable, {len(pts) - n_st} "
          f"unstable) on {len(nr.branches)} branch(es), {len(nr.folds)} folds, "
          f"{nr.evaluations} integrations of a period: {t_num:.2f} s (under 10 s: "
          f"{t_num < 10})")
    for f in nr.folds:
        print(f"  fold at sigma = {f.sigma:.10f}, a = {f.amplitude:.8f}")

    sub = pts[::10]
    t0 = time.perf_counter()
    worst, worst_m = 0.0, 0.0
    for o in sub:
        y, m = scipy_shooting(o.sigma, o.y0)
        worst = max(worst, float(np.max(np.abs(y - np.array(o.y0)))))
        worst_m = max(worst_m, float(np.max(np.abs(np.sort(np.abs(m))
                                                    - np.sort(np.abs(o.multipliers))))))
    t_sc = time.perf_counter() - t0
    per = t_sc / len(sub)
    print(f"hand-written solve_ivp shooting on {len(sub)} of the points: {t_sc:.2f} s, "
          f"{per * 1e3:.1f} ms per point -> {per * len(pts):.1f} s for all {len(pts)} "
          f"(the continuation: {t_num / len(pts) * 1e3:.2f} ms per point, "
          f"{per * len(pts) / t_num:.0f}x faster)")
    print(f"  largest difference of the responses {worst:.1e}, of the multipliers' moduli "
          f"{worst_m:.1e}")
    smooth_f()


def smooth_f() -> None:
    """The numeric backend on the slider against the exact engine on its Taylor polynomial."""
    z = sp.Symbol("z")
    sin_, cos_ = (sp.series(f(z), z, 0, 18).removeO() for f in (sp.sin, sp.cos))
    F = (1 - x**2) * (xdot + nu) - sp.Rational(4, 5) * (sin_.subs(z, x) * sp.cos(theta)
                                                       + cos_.subs(z, x) * sp.sin(theta))
    t0 = time.perf_counter()
    ex = derive_forced(ForcedOscillator("taylor-slider", F), 3)
    t_ex = time.perf_counter() - t0
    numeric_derive_forced("slider", 1, (0.5, 1.5), {"delta": 0.8, "k": 1})  # compile
    t0 = time.perf_counter()
    num = numeric_derive_forced("slider", 3, (0.5, 1.5), {"delta": 0.8, "k": 1})
    t_num = time.perf_counter() - t0
    av, ph, sg = np.linspace(0.5, 1.5, 11), np.linspace(0, 6, 11), np.linspace(-2, 2, 11)
    diff = max(float(np.max(np.abs(num.A[n](av, ph, sg)
                                   - sp.lambdify((a, phi, sigma), ex.A[n])(av, ph, sg))))
               for n in range(3))
    print(f"slider (sin(k x + theta)) to order 3: numeric backend {t_num:.2f} s "
          f"(grid {num.resolution}), exact engine on the degree-17 Taylor polynomial "
          f"{t_ex:.2f} s ({t_ex / t_num:.1f}x slower); largest difference of A_n {diff:.1e}")


if __name__ == "__main__":
    main()
