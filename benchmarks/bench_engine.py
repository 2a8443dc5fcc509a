"""Time the symbolic KBM engine against the naive sympy route, in the same run.

Run: ``python benchmarks/bench_engine.py [--quick]``

Prints wall-clock times of

- ``derive("vdp", N)`` for N = 2, 4, 8, 12, 30 (targets: N = 12 under 3 s, N = 30 under 2 s),
- ``limit_cycle_series("vdp", N)`` for N = 12, 24, 40, 80 (targets: mu**24 under 5 s,
  mu**40 under 3 s), and ``numeric_cycle_series("vdp", 300)`` (double precision),
- ``derive("sedf", 2)`` with symbolic beta, delta, k, Omega (target: under 5 s),
- the ``kbm derive vdp --order 12`` command line (including interpreter start-up),

and two baselines in the same run, with the ratios:

- the textbook route for van der Pol at order 2: the secular conditions as
  ``sympy.integrate`` over psi and ``u_n`` by ``sympy.dsolve``;
- the specialised exact Lindstedt expansion of van der Pol over ``fractions.Fraction``
  (``tests/reference/lindstedt_fraction.py``, written straightforwardly: dicts of
  harmonics, product-to-sum formulas) at mu**40, against the general engine.

Each timing is the best of ``repeat`` runs (one run for the long cases).
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import time

from pathlib import Path

import sympy as sp

from kbm import custom_model, derive, derive_values, limit_cycle_series, numeric_derive
from kbm.slowflow.numeric_series import numeric_cycle_series

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))
from reference.lindstedt_fraction import vdp_lindstedt_fraction  # noqa: E402


def best_of(fn, repeat: int) -> float:
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def naive_vdp_order2() -> tuple[sp.Expr, sp.Expr]:
    """Bogoliubov-Mitropolsky order 2 for van der Pol the way it is done by hand in sympy."""
    a, psi, eps = sp.symbols("a psi epsilon", positive=True)
    th = sp.Function("u1")
    F = lambda x, v: (1 - x**2) * v  # noqa: E731
    x0, v0 = a * sp.cos(psi), -a * sp.sin(psi)
    f0 = F(x0, v0)
    A1 = -sp.integrate(f0 * sp.sin(psi), (psi, 0, 2 * sp.pi)) / (2 * sp.pi)
    B1 = -sp.integrate(f0 * sp.cos(psi), (psi, 0, 2 * sp.pi)) / (2 * sp.pi * a)
    rhs = sp.expand(f0 + 2 * A1 * sp.sin(psi) + 2 * a * B1 * sp.cos(psi))
    sol = sp.dsolve(sp.Eq(th(psi).diff(psi, 2) + th(psi), rhs), th(psi))
    u1 = sol.rhs.subs({s: 0 for s in sol.rhs.free_symbols if s.name.startswith("C")})
    x1 = x0 + eps * u1
    v1 = (sp.diff(x1, a) * eps * A1 + sp.diff(x1, psi) * (1 + eps * B1))
    f1 = sp.expand(sp.diff(F(x1, v1), eps).subs(eps, 0))
    extra = sp.expand(-(A1 * sp.diff(A1, a) - a * B1**2) * sp.cos(psi)
                      + (2 * A1 * B1 + a * A1 * sp.diff(B1, a)) * sp.sin(psi)
                      - 2 * A1 * sp.diff(u1, a, psi) - 2 * B1 * sp.diff(u1, psi, 2))
    R = f1 + extra
    A2 = -sp.integrate(R * sp.sin(psi), (psi, 0, 2 * sp.pi)) / (2 * sp.pi)
    B2 = -sp.integrate(R * sp.cos(psi), (psi, 0, 2 * sp.pi)) / (2 * sp.pi * a)
    return sp.simplify(A2), sp.simplify(B2)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="one repetition, skip order 40")
    ap.add_argument("--repeat", type=int, default=3)
    ns = ap.parse_args()
    rep = 1 if ns.quick else ns.repeat
    rows = []
    for N in (2, 4, 8, 12, 30):
        targets = {12: 3.0, 30: 2.0}
        rows.append((f"derive vdp order {N}",
                     best_of(lambda N=N: derive("vdp", N), 1 if N == 30 else rep),
                     targets.get(N)))
    for N in ((12, 24, 40) if ns.quick else (12, 24, 40, 80)):
        rows.append((f"series vdp to mu^{N}",
                     best_of(lambda N=N: limit_cycle_series("vdp", N), 1 if N == 80 else rep),
                     {24: 5.0, 40: 3.0}.get(N)))
    t_series40 = min(t for name, t, _ in rows if name == "series vdp to mu^40")
    if not ns.quick:
        rows.append(("series vdp to mu^300 (float)",
                     best_of(lambda: numeric_cycle_series("vdp", 300), 1), 60.0))
    rows.append(("derive sedf order 2 (symbolic)", best_of(lambda: derive("sedf", 2), rep), 5.0))
    sedf_p = {"beta": 1.0, "delta": 0.5, "k": 2.0}
    amps = [0.5 + 0.25 * i for i in range(11)]
    for N in (2, 3, 4):
        rows.append((f"sedf order {N} evaluated (11 amplitudes)",
                     best_of(lambda N=N: derive_values("sedf", N, amps, sedf_p), rep), None))
    tanh = custom_model("-tanh(xdot/0.05) + (1 - x**2)*xdot")
    for N in (2, 4, 8):
        rows.append((f"numeric backend vdp order {N}",
                     best_of(lambda N=N: numeric_derive("vdp", N, (0.1, 4)), rep), None))
    rows.append(("numeric backend tanh-friction order 3",
                 best_of(lambda: numeric_derive(tanh, 3, (0.1, 4)), 1), None))
    cmd = [sys.executable, "-m", "numerics.cli", "derive", "vdp", "--order", "12", "--json"]
    rows.append(("CLI kbm derive vdp --order 12",
                 best_of(lambda: subprocess.run(cmd, check=True, capture_output=True), rep),
                 None))
    cmd = [sys.executable, "-m", "numerics.cli", "series", "vdp", "--order", "40"]
    rows.append(("CLI kbm series vdp --order 40",
                 best_of(lambda: subprocess.run(cmd, check=True, capture_output=True), rep),
                 3.0))
    t_naive = best_of(naive_vdp_order2, 1)
    t_ours = best_of(lambda: derive("vdp", 2), rep)
    t_fraction = best_of(lambda: vdp_lindstedt_fraction(40), 1)
    print(f"{'case':38s} {'time [s]':>10s} {'target [s]':>11s}  verdict")
    for name, t, target in rows:
        verdict = "" if target is None else ("ok" if t < target else "MISSED")
        tg = "" if target is None else f"{target:.1f}"
        print(f"{name:38s} {t:10.3f} {tg:>11s}  {verdict}")
    print(f"\nbaseline: naive sympy integrate/dsolve, vdp order 2: {t_naive:.3f} s")
    print(f"engine,                              vdp order 2: {t_ours:.4f} s")
    print(f"speed-up ratio (baseline / engine): {t_naive / t_ours:.0f}x")
    print(f"\nbaseline: specialised Fraction Lindstedt, vdp mu^40: {t_fraction:.3f} s")
    print(f"engine (limit_cycle_series),         vdp mu^40: {t_series40:.3f} s")
    print(f"speed-up ratio (baseline / engine): {t_fraction / t_series40:.1f}x")


if __name__ == "__main__":
    main()
