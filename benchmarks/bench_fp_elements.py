"""Time the stationary Kramers solve's element ladder (:mod:`numerics.fokker_planck.
_elements_ladder`, the default for the multi-well SEDF) against the Chebyshev ladder it
replaced (:mod:`numerics.fokker_planck._stationary_orthonormal`, ``basis="orthonormal"``,
the baseline), each with ``P(E)`` and its stated error as ``kbm noise --method
fokker-planck`` asks for them (``refine_ahead=True``, then
:func:`numerics.fokker_planck._energy_density.energy_density_report`), to six digits.

Run: ``python benchmarks/bench_fp_elements.py [--mu MU ...] [--rounds R] [--budget B]
[--baseline-budget B]`` (default ``--mu 0.02 0.01``, 1 round, ``kbm noise``'s budget
:data:`numerics.noise.budget.FP_BUDGET` for both routes; the table's mu = 0.005 row:
``--mu 0.005 --baseline-budget 8.6e7 --rounds 2``).  The SEDF at rest, Delta = 3, beta = 1,
D = mu/2.  Each route runs in a fresh process (``KBM_FP_WORKERS=1``, one BLAS thread:
no second process, so the CPU time is the cost), the order reversed every other round;
printed per route: the sizes (functions x points, elements), the stated error of the
moments (``hermite_change``) and of ``P(E)`` (``change_peak``, relative to its peak),
``<x^2>``, ``<v^2>``, the CPU time (user + system) of the ladder and the report, the
process's wall time and peak memory (``ru_maxrss`` of the child, whose imports are some
0.1 GB of it); per pair the CPU ratio Chebyshev / elements and whether the moments of
the two routes agree within the sum of their stated errors.  ``P(E)``'s agreement is
checked by ``tests/test_fokker_planck_elements_ladder.py`` (each report's energies
depend on its solution, so the two are not compared here).

At mu = 0.005 the Chebyshev ladder at the budget 2.5e7 does not state six digits
(364 x 877, stated 3.9e-6, ``P`` 5.9e-5; 59.7 s CPU, 1.84 GB against the elements'
29.9 s, 1.66 GB), so its row below is at ``--baseline-budget 8.6e7``, the budget at
which its moments state six digits (the table of docs/noise.rst; its ``P``, 1.2e-6, is
taken from the grid step 364 x 2035, whose factors, 4.5 GB by ``factor_bytes``, exceed
``FACTOR_MEMORY`` and are kept on disk).  Neither
route's ``P`` states six digits there at these budgets; the elements' does at
``--budget 3.2e7`` (512 x 240, stated 3.0e-7, ``P`` 5.0e-7, 42.1 s CPU, 1.88 GB).

Measured 2026-11-29 on main at 897d262 (two cores shared with the lead's test runs,
load 1.4-3.3 by ``uptime``): CPU seconds of the ladder and ``P(E)`` per round
(three rounds: an earlier run with the elements first, then ``--rounds 2``, the
elements first and then the Chebyshev ladder first), peak memory of the process::

    mu     elements (budget 2.5e7)          Chebyshev (2.5e7; 8.6e7 at 0.005)  CPU ratio
           N x E, stated, P stated;         N x m, stated, P stated;           Chebyshev /
           CPU s per round; peak memory     CPU s per round; peak memory       elements
    0.1    128 x 58, 5.7e-8, 5.0e-7;        128 x 449, 1.8e-8, 7.9e-7;
           2.8, 3.7, 2.6 s; 0.28 GB         3.4, 3.6, 3.9 s; 0.36 GB           1.2, 1.0, 1.5
    0.02   256 x 120, 5.7e-8, 7.7e-8;       182 x 741, 5.5e-7, 3.3e-7;
           5.8, 6.6, 7.0 s; 0.49 GB         13.6, 13.6, 14.1 s; 0.82 GB        2.3, 2.1, 2.0
    0.01   362 x 172, 5.5e-8, 2.6e-7;       258 x 1041, 3.0e-7, 9.8e-7;
           18.2, 14.7, 18.0 s; 0.91 GB      33.8, 31.1, 34.8 s; 1.77 GB        1.9, 2.1, 1.9
    0.005  512 x 190, 3.4e-7, 3.7e-6;       364 x 1627, 5.6e-7, 1.2e-6;
           29.7, 33.9, 36.0 s; 1.66 GB      155.9, 159.8, 164.7 s; 3.24 GB     5.2, 4.7, 4.6

The moments of the two routes agree within the sum of their stated errors at every mu:
``<x^2>``, ``<v^2>`` 1.7e-9, 4.9e-9 apart (stated 7.5e-8) at mu = 0.1; 5.1e-8, 1.1e-7
(6.1e-7) at 0.02; 1.3e-8, 5.1e-9 (3.5e-7) at 0.01; 8.0e-8, 3.9e-8 (9.0e-7) at 0.005.
The wall times are 1-9 % above the CPU times (27 % in a 3 s run at mu = 0.1); the
processes' own CPU, imports included, is 1-2 s more.  Of the Chebyshev route's CPU at
mu = 0.01 and 0.005, 14-15 s and 79-90 s are ``P(E)``'s grid step (from the report);
of the elements', 0.4-2.5 s (``P`` of the solution and its two pairs).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
ROUTES = ("elements", "orthonormal")
NAMES = {"elements": "elements", "orthonormal": "Chebyshev"}
SEDF = {"Delta": 3, "beta": 1, "lam": 1, "Omega": 1}
SIX_DIGITS = 1e-6
ONE_THREAD = {"KBM_FP_WORKERS": "1", "OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1",
              "MKL_NUM_THREADS": "1"}


def solve(route: str, mu: float, budget: float) -> dict:
    """One route's ladder and ``P(E)`` report in this process, timed; what to print."""
    from numerics.fokker_planck import stationary_kramers
    from numerics.fokker_planck._energy_density import energy_density_report

    wall, cpu = time.perf_counter(), time.process_time()
    sol = stationary_kramers("sedf", dict(SEDF, mu=mu), mu / 2, max_cost=budget,
                             basis=route, refine_ahead=True)
    ladder = time.process_time() - cpu
    report = energy_density_report(sol)
    cpu, wall = time.process_time() - cpu, time.perf_counter() - wall
    return {"route": route, "hermite": int(sol.coef.shape[0]), "points": int(sol.x.size),
            "elements": len(sol.edges) - 1 if hasattr(sol, "edges") else None,
            "stated": float(sol.hermite_change), "P_stated": report["change_peak"],
            "x2": float(sol.x2), "v2": float(sol.v2), "a2": float(sol.a2),
            "cpu_ladder": ladder, "cpu": cpu, "wall": wall}


def run(route: str, mu: float, budget: float) -> dict:
    """:func:`solve` in a fresh process (this tree first on the path, one thread); adds
    the child's user + system CPU and peak memory (``os.wait4``)."""
    env = dict(os.environ, **ONE_THREAD)
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT)] + [p for p in
                                         env.get("PYTHONPATH", "").split(os.pathsep) if p])
    proc = subprocess.Popen([sys.executable, __file__, "--child", route, str(mu),
                             repr(budget)], stdout=subprocess.PIPE, env=env, cwd=ROOT)
    out = proc.stdout.read()
    proc.stdout.close()
    _, status, usage = os.wait4(proc.pid, 0)
    proc.returncode = os.waitstatus_to_exitcode(status)
    if proc.returncode != 0:
        raise SystemExit(f"{route} at mu = {mu} failed (exit {proc.returncode})")
    rec = json.loads(out.decode().strip().splitlines()[-1])
    rec["user"], rec["sys"] = usage.ru_utime, usage.ru_stime
    rec["rss_gb"] = usage.ru_maxrss * 1024 / 1e9  # Linux: kilobytes
    return rec


def line(r: dict) -> str:
    """One route's printed line."""
    sizes = f"{r['hermite']} x {r['points']}"
    if r["elements"] is not None:
        sizes = f"{r['hermite']} x {r['elements']} el ({r['points']} pts)"
    p = "-" if r["P_stated"] is None else f"{r['P_stated']:.1e}"
    return (f"  {NAMES[r['route']]:9s} {sizes:24s} stated {r['stated']:.1e}, P {p}; "
            f"<x^2> {r['x2']:.10f}, <v^2> {r['v2']:.10f}; CPU {r['cpu']:.1f} s "
            f"(ladder {r['cpu_ladder']:.1f}; process {r['user']:.1f} + {r['sys']:.1f}), "
            f"wall {r['wall']:.1f} s, {r['rss_gb']:.2f} GB")


def agreement(a: dict, b: dict) -> str:
    """The moments' relative differences against the sum of the stated errors."""
    bound = a["stated"] + b["stated"]
    diffs = {k: abs(a[k] - b[k]) / abs(b[k]) for k in ("x2", "v2")}
    ok = all(d <= bound for d in diffs.values())
    return (f"<x^2> {diffs['x2']:.1e}, <v^2> {diffs['v2']:.1e} apart, "
            f"{'within' if ok else 'NOT within'} the stated {bound:.1e}")


def main(argv: list) -> None:
    sys.path.insert(0, str(ROOT))  # this tree's numerics, as in the children
    from numerics.noise.budget import FP_BUDGET

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--mu", type=float, nargs="+", default=[0.02, 0.01])
    ap.add_argument("--rounds", type=int, default=1)
    ap.add_argument("--budget", type=float, default=FP_BUDGET)
    ap.add_argument("--baseline-budget", type=float, default=None,
                    help="the Chebyshev ladder's budget (default --budget)")
    args = ap.parse_args(argv)
    budgets = {"elements": args.budget, "orthonormal": args.budget
               if args.baseline_budget is None else args.baseline_budget}
    head = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"],
                          capture_output=True, text=True).stdout.strip()
    print(f"SEDF at rest, Delta = 3, beta = 1, D = mu/2, budget {args.budget:.2g} "
          f"(Chebyshev {budgets['orthonormal']:.2g}), "
          f"commit {head}, {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}", flush=True)
    for mu in args.mu:
        for k in range(args.rounds):
            order = ROUTES if k % 2 == 0 else ROUTES[::-1]
            load = os.getloadavg()[0]
            recs = {route: run(route, mu, budgets[route]) for route in order}
            el, ch = recs["elements"], recs["orthonormal"]
            print(f"mu = {mu}, round {k + 1} ({' first, '.join(NAMES[r] for r in order)} "
                  f"second; load {load:.2f} -> {os.getloadavg()[0]:.2f})", flush=True)
            for route in ROUTES:
                print(line(recs[route]))
            for route in ROUTES:
                short = [what for what, key in (("the moments", "stated"),
                                                ("P(E)", "P_stated"))
                         if (recs[route][key] or 0) > SIX_DIGITS]
                if short:
                    print(f"  ({NAMES[route]}: {' and '.join(short)} beyond six digits at "
                          f"its budget)")
            print(f"  CPU Chebyshev / elements {ch['cpu'] / el['cpu']:.2f}x, memory "
                  f"{ch['rss_gb'] / el['rss_gb']:.2f}x; {agreement(el, ch)}", flush=True)


if __name__ == "__main__":
    if sys.argv[1:2] == ["--child"]:
        for key, value in ONE_THREAD.items():
            os.environ.setdefault(key, value)
        print(json.dumps(solve(sys.argv[2], float(sys.argv[3]), float(sys.argv[4]))))
    else:
        main(sys.argv[1:])
