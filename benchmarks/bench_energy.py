"""Time the energy-averaging prediction of all cycles against shooting the same cycles.

Run: ``python benchmarks/bench_energy.py [--repeat N]``

For the slider (sedf, mu = 0.1, Omega = 1, lam = 1) at (Delta, beta) = (1.5, 1),
(3, 1), (1.5, 0.25) and (1.5, 1.3) (the last with unstable side-well cycles):
``numerics.energy.predict_cycles`` at order 1 (target < 50 ms) and order 2
(target < 1 s; the default position scheme and the energy-angle scheme), warm
(second call, best of ``--repeat``), and
``numerics.limit_cycle`` (warm: its compiled integrator loaded) started from each
order-1 prediction (cycles with ``max x > 0`` only; "not shot" when Newton from
the prediction fails, as at Delta = 3 where it lands on the equilibrium x = 1.89).  Prints the times, the ratio shooting/prediction
and the errors of the predictions against the shot cycles.

Then the map (``--map N``, default 100; 0 skips it): ``numerics.energy.map_predictions``
of order 2 on an ``N x N`` grid of ``(mu, Delta)`` (``mu`` 0.5 .. 0.005, ``Delta`` 0.001 .. 3,
geometric; beta = 1 and 0.25) on ``--workers`` processes (target < 60 s each), with
the time of shooting a sample of the same cycles (``--shots`` points, started from the
map's prediction) extrapolated to the whole grid.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import numerics
from numerics.energy import map_predictions, predict_cycles

CASES = [(1.5, 1.0), (3.0, 1.0), (1.5, 0.25), (1.5, 1.3)]


def best(fun, repeat):
    times, out = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fun()
        times.append(time.perf_counter() - t0)
    return min(times), out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--map", type=int, default=100, help="grid size N of the N x N map")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--shots", type=int, default=20, help="map points shot for the ratio")
    args = ap.parse_args()
    numerics.limit_cycle("sedf", {"mu": 0.1, "Delta": 1.5, "beta": 1, "lam": 1})  # load the JIT
    print(f"{'Delta':>5} {'beta':>5} {'order 1':>9} {'order 2':>9} {'o2 e-a':>9} "
          f"{'shooting':>9} {'ratio':>6}  cycles (annulus: |dx_max| o1, o2, o2 e-a; "
          "|dT| o1, o2, o2 e-a)")
    for D, beta in CASES:
        pars = {"mu": 0.1, "Delta": D, "beta": beta, "lam": 1}
        predict_cycles("sedf", pars, order=1)  # warm: lambdify caches, imports
        t1, p1 = best(lambda: predict_cycles("sedf", pars, order=1), args.repeat)
        t2, p2 = best(lambda: predict_cycles("sedf", pars, order=2), args.repeat)
        t3, p3 = best(lambda: predict_cycles("sedf", pars, order=2, scheme="energy-angle"),
                      args.repeat)
        shots = []
        t0 = time.perf_counter()
        for c in p1.cycles:
            if c.amplitude_max <= 0:
                shots.append(None)
                continue
            try:
                shots.append(numerics.limit_cycle("sedf", pars,
                                                  guess=(c.amplitude_max, c.period)))
            except numerics.NumericsError:
                shots.append(None)
        ts = time.perf_counter() - t0
        notes = []
        keys = [{(c.annulus, c.amplitude_max > 0): c for c in p.cycles} for p in (p2, p3)]
        for c1, s in zip(p1.cycles, shots):
            cs = [c1] + [k.get((c1.annulus, c1.amplitude_max > 0)) for k in keys]
            if s is None or not s.success or None in cs:
                notes.append(f"{c1.annulus}: not shot")
                continue
            dx = ", ".join(f"{abs(c.amplitude_max - s.amplitude_max):.1e}" for c in cs)
            dT = ", ".join(f"{abs(c.period - s.period):.1e}" for c in cs)
            notes.append(f"{c1.annulus}: {dx}; {dT}")
        print(f"{D:5.2g} {beta:5.2g} {t1 * 1e3:7.1f}ms {t2 * 1e3:7.1f}ms {t3 * 1e3:7.1f}ms "
              f"{ts * 1e3:7.1f}ms {ts / t1:6.1f}  " + " | ".join(notes))
    if args.map:
        bench_map(args.map, args.workers, args.shots)


def bench_map(n: int, workers: int, shots: int) -> None:
    """Time an n x n order-2 map per beta, and shooting a sample of its cycles."""
    mus = np.geomspace(0.5, 0.005, n)
    Ds = np.geomspace(0.001, 3.0, n)
    rng = np.random.default_rng(0)
    print(f"\norder-2 map of {n} x {n} (mu, Delta) points on {workers} process(es) "
          "(target < 60 s)")
    for beta in (1.0, 0.25):
        t0 = time.perf_counter()
        out = map_predictions("sedf", {"beta": beta, "lam": 1}, mus, "Delta", Ds, order=2,
                              workers=workers)
        tm = time.perf_counter() - t0
        found = sum(bool(p.cycles) for col in out for p in col)
        pick = [(i, j) for i, j in zip(rng.integers(0, n, shots), rng.integers(0, n, shots))
                if out[i][j].cycles]
        t0, shot = time.perf_counter(), 0
        for i, j in pick:
            c = max(out[i][j].cycles, key=lambda c: c.amplitude_max)
            try:
                numerics.limit_cycle("sedf", {"mu": mus[j], "Delta": Ds[i], "beta": beta,
                                              "lam": 1}, guess=(c.amplitude_max, c.period))
                shot += 1
            except numerics.NumericsError:
                pass
        per_shot = (time.perf_counter() - t0) / max(len(pick), 1)
        est = per_shot * n * n / workers
        print(f"beta = {beta:g}: {tm:6.1f} s ({tm / n / n * workers * 1e3:.1f} ms per point "
              f"per process), {found}/{n * n} points with a cycle; shooting {len(pick)} "
              f"sampled points ({shot} shot): {per_shot * 1e3:.0f} ms each, estimated "
              f"{est:.0f} s for the grid on {workers} process(es), ratio {est / tm:.1f}")


if __name__ == "__main__":
    main()
