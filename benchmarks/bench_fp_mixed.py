"""Time the stationary Kramers solve's two routes on the largest grids of the ladder: the
direct inverse iteration on the double-precision order-by-order LU
(:mod:`numerics.fokker_planck._pentadiagonal`) against GMRES on the single-precision one
(:mod:`numerics.fokker_planck._bordered`), interleaved, in CPU time, with their agreement.

Run: ``python benchmarks/bench_fp_mixed.py [mu [rounds [budget]]]`` (mu 0.01 by default,
the SEDF at rest, Delta = 3, beta = 1, D = mu/2; 1 round; ``kbm noise``'s budget, or the
``--fp-budget`` given).  The ladder runs once in this process (``KBM_FP_WORKERS=1``) and
records the arguments of its two largest solves (at mu = 0.01 the climb's top grid, 258
functions x 1041 points, and P(E)'s grid step, 258 x 1301); each is then solved by both
routes, the order reversed every other round, and the bytes of each route's factors
(:func:`numerics.fokker_planck._pentadiagonal_disk.factor_bytes`) are printed with where
they go (memory, or disk beyond ``FACTOR_MEMORY``).  Measured (mu = 0.01, one BLAS
thread, CPU s, direct / GMRES), the factors of single precision kept in double (before
they were kept in single precision)::

    258 x 1041    10.04 / 6.30    10.27 / 5.82    (1.59x, 1.76x; load 3-4.5 on 2 cores)
                  10.31 / 6.39    10.74 / 6.76    (1.61x, 1.59x; this script, load 0.9)
    258 x 1301    17.93 / 11.17   18.11 / 9.91    (1.61x, 1.83x; load 3-4.5)
                  17.98 / 11.06                   (1.63x; this script, load 0.9)

the moments within 3.2e-13 and the coefficients within 6.4e-13 of the direct solve's.
With the factors kept in single precision (the sweeps by
:func:`numerics.fokker_planck._single_products.single_matvec`) and the inverses by LAPACK
directly, this script before and after, one after the other (load 1-2.8)::

    258 x 1041    before 10.16 / 6.31 (1.61x)   after  9.55 / 5.00 (1.91x)
    258 x 1301    before 18.00 / 11.19 (1.61x)  after 16.78 / 9.14, 17.49 / 9.22 (1.84x, 1.90x)

the GMRES factors 0.84 and 1.31 GB (1.68 and 2.62 GB in double), the moments within
1.3e-13 and the coefficients within 1.4e-12 of the direct solve's.
"""

from __future__ import annotations

import os
import sys
import time

os.environ["KBM_FP_WORKERS"] = "1"

import numpy as np  # noqa: E402


def record(mu: float, budget: float | None = None) -> list:
    """The arguments of every stationary solve of the ladder at ``budget`` (default
    ``kbm noise``'s) and of P(E)'s grid step (the solution's ``refine``, not solved
    here)."""
    import numerics.fokker_planck._stationary_orthonormal as so
    from numerics.fokker_planck import stationary_kramers
    from numerics.noise.budget import FP_BUDGET

    calls, inner = [], so.orthonormal_stationary

    def spy(*args, **kwargs):
        calls.append((args, kwargs))
        return inner(*args, **kwargs)

    so.orthonormal_stationary = spy
    try:
        sol = stationary_kramers("sedf", {"mu": mu, "Delta": 3, "beta": 1, "lam": 1},
                                 mu / 2, max_cost=FP_BUDGET if budget is None else budget)
    finally:
        so.orthonormal_stationary = inner
    if sol.refine is not None:
        calls.append((sol.refine.args, sol.refine.keywords))
    return calls


def main(argv: list) -> None:
    from numerics.fokker_planck._pentadiagonal_disk import FACTOR_MEMORY, factor_bytes
    from numerics.fokker_planck._stationary_solve import orthonormal_stationary

    mu = float(argv[0]) if argv else 0.01
    rounds = int(argv[1]) if len(argv) > 1 else 1
    budget = float(argv[2]) if len(argv) > 2 else None
    calls = record(mu, budget)
    biggest = sorted(calls, key=lambda c: c[0][4] * c[0][5] ** 2)[-2:]
    print(f"SEDF at rest, mu = {mu}, D = {mu / 2}; load {os.getloadavg()[0]:.2f}")
    for args, kwargs in biggest:
        n, full = args[4], args[5] + 1
        m = full // 2 + 1  # the folded points (the SEDF is symmetric)
        for name, single in (("direct", False), ("GMRES", True)):
            size = factor_bytes(n, m, single)
            where = "memory" if size <= FACTOR_MEMORY else "disk"
            print(f"{n} x {full}: {name} factors {size / 1e9:.2f} GB in {where}")
        for r in range(rounds):
            order = (False, True) if r % 2 == 0 else (True, False)
            sols, cpu = {}, {}
            for mixed in order:
                t = time.process_time()
                sols[mixed] = orthonormal_stationary(*args, **kwargs, mixed=mixed)
                cpu[mixed] = time.process_time() - t
            a, b = sols[True], sols[False]
            moments = max(abs(a.x2 / b.x2 - 1), abs(a.v2 / b.v2 - 1), abs(a.a2 / b.a2 - 1))
            coef = float(np.max(np.abs(a.coef - b.coef)) / np.max(np.abs(b.coef)))
            print(f"{args[4]} x {args[5] + 1}: direct {cpu[False]:.2f} s, GMRES "
                  f"{cpu[True]:.2f} s ({cpu[False] / cpu[True]:.2f}x); moments "
                  f"{moments:.1e}, coefficients {coef:.1e} apart; load "
                  f"{os.getloadavg()[0]:.2f}", flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
