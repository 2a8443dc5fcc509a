"""Time a branch of limit cycles against solving each point from scratch, in the same run.

Run: ``python benchmarks/bench_branch.py``

1. The SEDF (mu = 0.1, beta = 1, lambda = 1) against Delta from 0 to 4: about 200 points
   by pseudo-arclength continuation (Floquet multipliers at every point, the fold test
   function dp/ds watched at every step, the homoclinic end located), then
   :func:`numerics.limit_cycle` from scratch (its own KBM / energy-balance guesses and
   transients) at every Delta of the branch; the ratio of the times is printed, and the
   largest difference of the periods where both found a cycle.
2. The fold of cycles of ``F = (-nu + x^2 - x^4) x'`` (mu = 0.1): about 200 points through
   the fold (located by the secant method on dp/ds) to the Hopf end, against from scratch.

Both are timed warm (the compiled integrators loaded by a first short run), on one core.
"""

from __future__ import annotations

import time

from kbm import custom_model
from numerics import limit_cycle
from numerics.cycles.continuation import continue_cycles
from numerics.errors import NumericsError


def _scratch(model, params, vary, branch):
    t0 = time.perf_counter()
    worst, fails = 0.0, 0
    for p in branch.points:
        try:
            c = limit_cycle(model, {**params, vary: p.parameter})
        except NumericsError:
            fails += 1
            continue
        if abs(c.amplitude_max - p.amplitude_max) < 1e-3:  # the same cycle, not another one
            worst = max(worst, abs(c.period - p.period) / p.period)
    return time.perf_counter() - t0, worst, fails


def case(label, model, params, vary, bounds, **kw):
    continue_cycles(model, params, vary, bounds, max_points=5)  # warm the compiled flow
    t0 = time.perf_counter()
    br = continue_cycles(model, params, vary, bounds, **kw)
    t_branch = time.perf_counter() - t0
    base = {k: v for k, v in params.items() if k != vary}
    t_scratch, worst, fails = _scratch(model, base, vary, br)
    print(f"\n{label}: {len(br.points)} points, {br.evaluations} integrations of a period")
    print(f"  continuation      {t_branch:7.2f} s")
    print(f"  from scratch      {t_scratch:7.2f} s  ({fails} points without a cycle found)")
    print(f"  ratio             {t_scratch / t_branch:7.1f}x")
    print(f"  largest relative period difference where both agree on the cycle: {worst:.1e}")
    for s in br.special:
        print(f"  {s.kind:10s} {vary} = {s.parameter:.10g}  ({s.message[:90]})")
    return t_branch


def main() -> None:
    t1 = case("SEDF against Delta (mu = 0.1, beta = 1)", "sedf",
              {"mu": 0.1, "beta": 1, "lam": 1, "Delta": 0.0}, "Delta", (0.0, 4.0),
              ds_max=0.03, max_points=1000)
    t2 = case("fold of cycles, F = (-nu + x^2 - x^4) x' (mu = 0.1)",
              custom_model("(-nu + x**2 - x**4)*xdot"), {"mu": 0.1, "nu": 0.05}, "nu",
              (0.0, 0.2), ds_max=0.008, max_points=1000)
    print(f"\nunder 5 s: SEDF {t1 < 5}, fold model {t2 < 5}")


if __name__ == "__main__":
    main()
