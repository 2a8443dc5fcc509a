"""Time ``numerics.limit_cycle`` against the obvious user baselines, in the same run.

Run: ``python benchmarks/bench_cycle.py [--quick]``

Baselines (what a user writes by hand with scipy):

1. *transient*: ``solve_ivp`` (DOP853, rtol = atol = 1e-12) for 200 periods, the last
   cycle read off with an event on ``x' = 0``;
2. *hand shooting*: ``scipy.optimize.fsolve`` on ``(x(T) - x0, x'(T))`` with ``solve_ivp``
   (DOP853, 1e-12) inside, started from amplitude 2 and period 2 pi (for the relaxation
   oscillation at mu = 10, the leading relaxation period (3 - 2 ln 2) mu).

The error of each method is measured against a 30-digit mpmath Taylor-series cycle.
Cases: van der Pol mu = 0.1 and 1, SEDF at the paper's Fig. 3 parameters
(mu = 0.1, Delta = 1.5, lambda = 1, beta = 1).  ``kbm cycle`` is timed warm (its
compiled integrator loaded), as the baselines are; the one-off cost of compiling
a model's integrator into an empty cache folder is timed separately, in a fresh
process.  Also shown: ``kbm cycle`` through scipy's LSODA (``method="LSODA"``,
what it falls back to without numba).  Also timed: the 30-digit cycle itself and
sweeps of 10,000 van der Pol-type cycles on both cores (van der Pol over mu, and
the SEDF over a 100 x 100 grid in beta x Delta), at rtol = 1e-10.
"""

from __future__ import annotations

import argparse
import math
import os
import subprocess
import sys
import tempfile
import time

import mpmath
import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import fsolve

from numerics import grid, limit_cycle, sweep
from numerics.flow import compile_model


def timed(fn, repeat=3):
    best, out = float("inf"), None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def transient_baseline(cm, periods=200):
    def ev(t, y):
        return y[1]
    ev.direction = -1
    T0 = 2 * math.pi / cm.omega0
    sol = solve_ivp(cm.rhs, (0, periods * T0), [1.0, 0.0], method="DOP853", rtol=1e-12,
                    atol=1e-12, events=ev)
    te, ye = sol.t_events[0], sol.y_events[0]
    big = [i for i in range(len(te)) if ye[i][0] > 0]
    return te[big[-1]] - te[big[-2]], ye[big[-1]][0]


def hand_shooting(cm, x0=2.0, T0=2 * math.pi):
    def resid(z):
        x0, T = z
        sol = solve_ivp(cm.rhs, (0, T), [x0, 0.0], method="DOP853", rtol=1e-12, atol=1e-12)
        return [sol.y[0, -1] - x0, sol.y[1, -1]]
    x0, T = fsolve(resid, [x0, T0], xtol=1e-13)
    return T, x0


CASES = [("vdp mu=0.1", "vdp", {"mu": 0.1}), ("vdp mu=1", "vdp", {"mu": 1}),
         ("sedf Fig.3 beta=1", "sedf", {"mu": 0.1, "Delta": 1.5, "lam": 1, "beta": 1})]
#: a relaxation oscillation (full run only; the hand shooting starts from its own guess)
STIFF_CASE = ("vdp mu=10", "vdp", {"mu": 10})


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    ns = ap.parse_args()
    rep = 1 if ns.quick else 3
    print(f"{'case':20s} {'method':16s} {'time [ms]':>10s} {'|dT|':>9s} {'|dx_max|':>9s} "
          f"{'time ratio':>10s}")
    for label, name, params in CASES + ([] if ns.quick else [STIFF_CASE]):
        cm = compile_model(name, params)
        ref = limit_cycle(name, params, digits=30)
        T_ref, x_ref = float(ref.mp["period"]), float(ref.mp["amplitude_max"])
        limit_cycle(name, params)
        t_ours, c = timed(lambda: limit_cycle(name, params), rep)
        t_ls, c_ls = timed(lambda: limit_cycle(name, params, method="LSODA"), rep)
        t_tr, (T_tr, x_tr) = timed(lambda: transient_baseline(cm), 1)
        T_guess = 2 * math.pi if params["mu"] < 5 else (3 - 2 * math.log(2)) * params["mu"]
        t_hs, (T_hs, x_hs) = timed(lambda: hand_shooting(cm, T0=T_guess), rep)
        rows = [("kbm cycle", t_ours, c.period, c.amplitude_max),
                ("kbm cycle LSODA", t_ls, c_ls.period, c_ls.amplitude_max),
                ("200-period IVP", t_tr, T_tr, x_tr), ("hand shooting", t_hs, T_hs, x_hs)]
        for meth, t, T, x in rows:
            print(f"{label:20s} {meth:16s} {1e3 * t:10.1f} {abs(T - T_ref):9.1e} "
                  f"{abs(x - x_ref):9.1e} {t / t_ours:10.1f}")
    t0 = time.perf_counter()
    c30 = limit_cycle("vdp", {"mu": 1}, digits=30)
    t30 = time.perf_counter() - t0
    print(f"\n30-digit van der Pol mu = 1 cycle: {t30:.1f} s (target < 20 s); "
          f"T = {mpmath.nstr(c30.mp['period'], 30)}")
    with tempfile.TemporaryDirectory() as tmp:
        code = ("import time; t0 = time.perf_counter(); from numerics import limit_cycle; "
                "limit_cycle('sedf', {'mu': 0.1, 'Delta': 1.5, 'lam': 1, 'beta': 1}); "
                "print(time.perf_counter() - t0)")
        env = {**os.environ, "KBM_CACHE_DIR": tmp}
        cold = [float(subprocess.run([sys.executable, "-c", code], env=env, check=True,
                                     capture_output=True, text=True).stdout) for _ in range(2)]
    print(f"one sedf cycle in a fresh process: {cold[0]:.1f} s with an empty cache folder "
          f"(compiles the integrator), {cold[1]:.1f} s once it is cached (imports included)")
    n = 1000 if ns.quick else 10000
    mus = np.linspace(0.05, 2.0, n)
    t0 = time.perf_counter()
    pts = sweep("vdp", grid(mu=list(mus)), rtol=1e-10, progress=False)
    ts = time.perf_counter() - t0
    ok = sum(p.success for p in pts)
    print(f"sweep of {n} van der Pol cycles (mu in [0.05, 2]) on both cores: {ts:.1f} s "
          f"({ok} converged); per 10,000: {ts * 10000 / n:.0f} s (target < 60 s)")
    side = 32 if ns.quick else 100
    t0 = time.perf_counter()
    pts = sweep("sedf", grid(beta=list(np.linspace(0.5, 2.0, side)),
                             Delta=list(np.linspace(0.0, 1.5, side))),
                fixed={"mu": 0.1, "lam": 1}, rtol=1e-10, progress=False)
    ts = time.perf_counter() - t0
    ok = sum(p.success for p in pts)
    print(f"sweep of {side}x{side} SEDF cycles (beta in [0.5, 2] x Delta in [0, 1.5], mu = 0.1) "
          f"on both cores: {ts:.1f} s ({ok} converged, the rest reported); per 10,000: "
          f"{ts * 10000 / side**2:.0f} s (target < 60 s)")


if __name__ == "__main__":
    main()
