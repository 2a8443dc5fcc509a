"""Time a friction map of the stage-attached SEDF: compiled against scipy, local pool against Dask.

Run: ``python benchmarks/bench_friction.py [--size 64] [--quick]``

1. A ``size x size`` map over ``(v, Delta)`` (``v`` log-spaced from 3e-3 to 3, ``Delta``
   from 0.25 to 4; ``mu = 0.1``, ``beta = 1``, ``lam = 1``, ``Omega = 1``), each point its
   steady state with 20 slips (or 20 wells / 20 natural periods when it does not stick),
   on the local process pool of two workers: the wall time, points per second, and how
   the points ended (regimes, steady, failures).
2. The compiled path (numba DOP853) against the scipy path (``solve_ivp``, DOP853, the
   same equations lambdified) on a sample of the map's points (the whole map through scipy
   would take hours), each in this process, one after the other: the ratio of the times
   (target >= 20) and the largest difference of the mean forces.
3. The same map on a Dask ``LocalCluster`` of two single-threaded worker processes against
   the local pool: the overhead of the cluster, and that the results are identical.

All timings are warm: the compiled integrator is loaded by a first short run.
"""

from __future__ import annotations

import argparse
import json
import time
from collections import Counter

import numpy as np

from kbm.output.strict_json import finite
from numerics.sliding.friction import friction_point
from numerics.sliding.friction_records import FrictionSettings
from numerics.sliding.maps import friction_map

FIXED = {"mu": 0.1, "lam": 1.0, "Omega": 1.0, "beta": 1.0}


def axes(size: int) -> dict:
    return {"v": np.geomspace(3e-3, 3.0, size), "Delta": np.linspace(0.25, 4.0, size)}


def describe(m) -> str:
    regimes = Counter(p.regime or "failed" for p in m.points)
    steady = sum(p.steady for p in m.points)
    return (f"{dict(regimes)}; steady {steady}/{len(m.points)}; failures {len(m.failures)}")


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--size", type=int, default=64)
    ap.add_argument("--sample", type=int, default=6, help="points timed through scipy")
    ap.add_argument("--quick", action="store_true", help="a 12 x 12 map, 3 scipy points")
    ap.add_argument("--no-dask", action="store_true")
    args = ap.parse_args()
    size, sample = (12, 3) if args.quick else (args.size, args.sample)
    ax = axes(size)
    settings = FrictionSettings(slips=20)
    friction_point("sedf_comoving", {**FIXED, "Delta": 1.0, "v": 1.0})  # load the compiled code

    t0 = time.perf_counter()
    pool = friction_map("sedf_comoving", FIXED, ax, settings=settings, workers=2)
    t_pool = time.perf_counter() - t0
    n = size * size
    print(f"1. {size} x {size} (v, Delta) map, local pool of 2: {t_pool:.1f} s "
          f"({n / t_pool:.1f} points/s); {describe(pool)}")

    rng = np.random.default_rng(1)
    idx = rng.choice(n, size=sample, replace=False)
    t_c = t_s = 0.0
    worst = 0.0
    for i in idx:
        p = dict(pool.points[i].params)
        t1 = time.perf_counter()
        a = friction_point("sedf_comoving", p, settings=settings)
        t2 = time.perf_counter()
        b = friction_point("sedf_comoving", p, settings=settings, engine="scipy")
        t3 = time.perf_counter()
        t_c, t_s = t_c + t2 - t1, t_s + t3 - t2
        if a.ok and b.ok and np.isfinite(a.mean_force) and a.regime == b.regime:
            worst = max(worst, abs(a.mean_force - b.mean_force) / max(abs(a.mean_force), 1e-12))
        print(f"   v = {p['v']:.4g}, Delta = {p['Delta']:.4g}: compiled {t2 - t1:.3f} s "
              f"({a.regime}), scipy {t3 - t2:.3f} s ({b.regime})")
    print(f"2. compiled against scipy on {sample} points: {t_c:.2f} s vs {t_s:.2f} s, "
          f"speed-up {t_s / t_c:.0f}x; largest relative difference of the mean force "
          f"{worst:.1e} (where both found the same regime)")

    if args.no_dask:
        return
    from distributed import Client, LocalCluster

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                      dashboard_address=None) as cluster, Client(cluster) as client:
        t4 = time.perf_counter()
        dask = friction_map("sedf_comoving", FIXED, ax, settings=settings, executor=client)
        t_dask = time.perf_counter() - t4
    same = (json.dumps(finite(dask.to_json()), sort_keys=True)
            == json.dumps(finite(pool.to_json()), sort_keys=True))
    print(f"3. Dask LocalCluster (2 workers): {t_dask:.1f} s vs local pool {t_pool:.1f} s, "
          f"overhead {100 * (t_dask / t_pool - 1):+.0f} %; identical results: {same}")


if __name__ == "__main__":
    main()
