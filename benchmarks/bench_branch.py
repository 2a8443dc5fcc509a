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

Both are timed warm (the compiled integrators loaded by a first short run), on one core, the
best of three runs.

3. AUTO-07p on the SEDF branch of case 1 (issue 25), when the ``auto-07p`` command is installed
   (Debian's package, with gfortran; the project does not depend on it): orthogonal
   collocation, NTST = 200, NCOL = 4, from the van der Pol cycle (continued from the Hopf
   point of the origin in a gain ``s`` up to ``s = 1``) in ``Delta`` from 0 to 4.  Its
   continuation in ``Delta`` alone is timed (AUTO's own clock around its ``run``, the best of
   three), and the ratio to kbm's time of case 1 is printed with where each branch stops and
   how far AUTO's periods are from kbm's cycles (the same branch to about 1e-10).  The two
   best-of-threes are minutes apart; eight interleaved rounds (one kbm run, one AUTO run)
   then compare them in the same state of the machine, and the whole commands (process,
   imports and start included) are timed.
"""

from __future__ import annotations

import math
import re
import statistics
import shutil
import subprocess
import tempfile
import textwrap
import time
from pathlib import Path

from kbm import custom_model
from numerics import limit_cycle
from numerics.cycles.continuation import continue_cycles
from numerics.errors import NumericsError

from _auto import sedf_constants, sedf_equations


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
    t_branch = math.inf
    for _ in range(3):  # the best of three, as for AUTO-07p
        t0 = time.perf_counter()
        br = continue_cycles(model, params, vary, bounds, **kw)
        t_branch = min(t_branch, time.perf_counter() - t0)
    base = {k: v for k, v in params.items() if k != vary}
    t_scratch, worst, fails = _scratch(model, base, vary, br)
    print(f"\n{label}: {len(br.points)} points, {br.evaluations} integrations of a period")
    print(f"  continuation      {t_branch:7.3f} s (best of 3)")
    print(f"  from scratch      {t_scratch:7.2f} s  ({fails} points without a cycle found)")
    print(f"  ratio             {t_scratch / t_branch:7.1f}x")
    print(f"  largest relative period difference where both agree on the cycle: {worst:.1e}")
    for s in br.special:
        print(f"  {s.kind:10s} {vary} = {s.parameter:.10g}  ({s.message[:90]})")
    return t_branch


#: the SEDF's equations (their Jacobians unused: ``JAC = 0``) from beta = 1, and constants
AUTO_EQUATIONS = sedf_equations("1.0D0")
AUTO_CONSTANTS = sedf_constants(npr=1000, itnw=5, nwtn=3, jac=0)

AUTO_SCRIPT = textwrap.dedent("""\
    import time
    eq = run('sedf')
    po = run(eq('HB1'), IPS=2, ICP=['s', 11], UZSTOP={'s': 1.0}, NMX=2000)
    t0 = time.time()
    br = run(po('UZ1'), IPS=2, ICP=['Delta', 11], UZSTOP={'Delta': 4.0}, NMX=5000)
    t1 = time.time()
    b = br[0]
    print("AUTOTIME", t1 - t0, len(b['Delta']), b['Delta'][-1], b['PERIOD'][-1])
    pairs = zip(b["Delta"], b["PERIOD"])
    print("AUTOPOINTS", " ".join(f"{float(d)!r}:{float(T)!r}" for d, T in pairs))
    """)


def auto_env() -> dict[str, str]:
    """AUTO-07p's environment: one OpenMP thread unless ``OMP_NUM_THREADS`` is set.  kbm runs
    on one core; with AUTO's default of a thread per core, its threads' waits on a shared
    machine made the same run 4-45 times slower (2026-11-27)."""
    import os

    env = dict(os.environ)
    env.setdefault("OMP_NUM_THREADS", "1")
    return env


def auto07p(repeats: int = 3) -> tuple[float, int, float, float, float, list] | None:
    """``(seconds, points, last Delta, last period, wall seconds, [(Delta, period)])`` of
    AUTO-07p's continuation in Delta (its own clock) and of the whole ``auto-07p run.auto``
    (compiling the equations, the Hopf point and the start cycle included), the best of
    ``repeats`` runs, or ``None`` (with the reason printed) when AUTO-07p cannot run here.

    The start cycle is the van der Pol cycle continued in the gain ``s`` to the user zero
    ``s = 1``; AUTO locates a user zero to ``EPSS`` (relative), and with its usual 1e-4 the
    start was at ``s = 0.999969``: a slightly different slider, whose periods differed from
    kbm's by 1e-5 to 2e-4.  With ``EPSS = 1e-9`` they agree to about 1e-10."""
    if shutil.which("auto-07p") is None or shutil.which("gfortran") is None:
        print("\nAUTO-07p: not installed (apt-get install auto-07p gfortran); skipped")
        return None
    best = None
    for _ in range(repeats):
        with tempfile.TemporaryDirectory() as tmp:
            d = Path(tmp)
            (d / "sedf.f90").write_text(AUTO_EQUATIONS)
            (d / "c.sedf").write_text(AUTO_CONSTANTS)
            (d / "run.auto").write_text(AUTO_SCRIPT)
            t0 = time.perf_counter()
            out = subprocess.run(["auto-07p", "run.auto"], cwd=d, capture_output=True,
                                 text=True, timeout=900, env=auto_env())
            wall = time.perf_counter() - t0
        m = re.search(r"AUTOTIME (\S+) (\d+) (\S+) (\S+)", out.stdout)
        pts = re.search(r"AUTOPOINTS (.*)", out.stdout)
        if not (m and pts):
            print(f"\nAUTO-07p failed: {(out.stdout + out.stderr).strip()[-300:]}")
            return None
        branch = [tuple(float(v) for v in item.split(":")) for item in pts.group(1).split()]
        run = (float(m.group(1)), int(m.group(2)), float(m.group(3)), float(m.group(4)), wall,
               branch)
        best = run if best is None else (min(best[0], run[0]), *run[1:4],
                                         min(best[4], run[4]), branch)
    return best


def interleaved(rounds: int = 8) -> list[tuple[float, float]]:
    """``(kbm, AUTO)`` seconds of the SEDF continuation in ``rounds`` alternating runs (kbm's
    ``continue_cycles`` in this process, warm; AUTO's own clock around its ``run``): both
    programs see the same state of the machine."""
    params = {"mu": 0.1, "beta": 1, "lam": 1, "Delta": 0.0}
    out = []
    for _ in range(rounds):
        t0 = time.perf_counter()
        continue_cycles("sedf", params, "Delta", (0.0, 4.0), ds_max=0.05, max_points=1000)
        k = time.perf_counter() - t0
        a = auto07p(repeats=1)
        if a is None:
            break
        out.append((k, a[0]))
    return out


def auto_agreement(branch: list, n: int = 8) -> float:
    """The largest relative difference between AUTO-07p's periods and kbm's cycles shot at
    the same Delta (rtol 1e-12), at ``n`` of AUTO's points below Delta = 3.2."""
    params = {"mu": 0.1, "beta": 1, "lam": 1}
    inside = [(d, T) for d, T in branch if d < 3.2]
    worst = 0.0
    for d, T in inside[:: max(1, len(inside) // n)]:
        c = limit_cycle("sedf", {**params, "Delta": d}, rtol=1e-12, atol=1e-12)
        worst = max(worst, abs(c.period - T) / c.period)
    return worst


def kbm_command(*extra: str, repeats: int = 3) -> tuple[float, float]:
    """``(seconds, homoclinic end)`` of the whole ``kbm branch`` command on the same branch in a
    new process (imports, the start cycle, the analytic curves unless ``extra`` leaves them
    out; numba's cache warm from case 1), the best of ``repeats``."""
    import json
    import sys

    wall = math.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = subprocess.run([sys.executable, "-m", "numerics.cli", "branch", "sedf", "-p",
                              "mu=0.1", "-p", "beta=1", "-p", "lam=1", "--vary", "Delta=0:4",
                              "--json", *extra],
                             capture_output=True, text=True, timeout=900, check=True)
        wall = min(wall, time.perf_counter() - t0)
    special = json.loads(out.stdout)["special"]
    end = next((s["parameter"] for s in special if s["kind"] == "homoclinic"), float("nan"))
    return wall, end


def main() -> None:
    t1 = case("SEDF against Delta (mu = 0.1, beta = 1; ds_max = 0.05, AUTO's DSMAX)", "sedf",
              {"mu": 0.1, "beta": 1, "lam": 1, "Delta": 0.0}, "Delta", (0.0, 4.0),
              ds_max=0.05, max_points=1000)
    t2 = case("fold of cycles, F = (-nu + x^2 - x^4) x' (mu = 0.1)",
              custom_model("(-nu + x**2 - x**4)*xdot"), {"mu": 0.1, "nu": 0.05}, "nu",
              (0.0, 0.2), ds_max=0.008, max_points=1000)
    print(f"\nunder 5 s: SEDF {t1 < 5}, fold model {t2 < 5}")
    auto = auto07p()
    if auto is not None:
        secs, n, last, period, wall, branch = auto
        print(f"\nAUTO-07p (NTST = 200, NCOL = 4) on the SEDF branch in Delta: {secs:.3f} s "
              f"(best of 3), {n} points, last Delta = {last:.9f} at period {period:.4f}")
        print(f"  AUTO's periods against kbm's cycles at the same Delta: largest relative "
              f"difference {auto_agreement(branch):.1e}")
        print(f"  continuation alone, kbm / AUTO-07p time: {t1 / secs:.2f} "
              f"(faster than AUTO: {t1 < secs}; the two best-of-threes minutes apart)")
        rounds = interleaved()
        ratios = [k / a for k, a in rounds]
        print(f"  interleaved, {len(rounds)} rounds of one kbm and one AUTO run each "
              f"(the machine's speed drifts by 30 % from minute to minute):")
        print("    kbm  " + " ".join(f"{k:.3f}" for k, _ in rounds))
        print("    AUTO " + " ".join(f"{a:.3f}" for _, a in rounds))
        print(f"    kbm / AUTO {min(ratios):.2f} to {max(ratios):.2f}, median "
              f"{statistics.median(ratios):.2f}; faster in {sum(r < 1 for r in ratios)} of "
              f"{len(ratios)} rounds")
        k_wall, k_end = kbm_command()
        b_wall, _ = kbm_command("--orders", "none", "--no-energy")
        print(f"  whole command: auto-07p run.auto {wall:.2f} s (best of 3: compiling, Hopf "
              f"point, start cycle, branch)")
        print(f"    kbm branch {k_wall:.2f} s (homoclinic end {k_end:.10f}; with the KBM and "
              f"energy-balance curves): ratio {k_wall / wall:.2f}")
        print(f"    kbm branch --orders none --no-energy {b_wall:.2f} s (the branch alone, as "
              f"AUTO's output): ratio {b_wall / wall:.2f}")


if __name__ == "__main__":
    main()
