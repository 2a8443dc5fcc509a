"""Time kbm's two-parameter curves against AUTO-07p's on the same curves, in one run.

Run: ``python benchmarks/bench_diagram.py [--repeats 3] [--parts 123] [--no-auto]``

Every curve is timed warm, the median of ``--repeats`` runs, in wall and CPU seconds: kbm
after one untimed run (its compiled flows loaded), in this process; AUTO-07p after one
untimed ``auto-07p run.auto`` (gfortran compiles the equations), by its own clock around
its runs inside its Python (the CPU: its Fortran processes'), and as the whole process.
AUTO-07p is Debian's ``auto-07p`` (else ``auto`` on the path or ``$AUTO_DIR/bin/auto``;
gfortran needed); where it is not installed its parts print "skipped".  It runs with one
OpenMP thread (``OMP_NUM_THREADS=1`` unless set): kbm uses one core, and with its default
thread per core AUTO's threads wait for each other on a shared machine (the same runs took
4-45 times longer here).  Its files (``_auto_diagram.py``: the equations with their
Jacobians, the scripts) are written to a temporary folder; nothing of AUTO's is kept.

1. The fold curve of the forced Duffing oscillator ``x'' + x = mu (-2 zeta x' - alpha x^3
   + h cos nu t)``, ``nu = 1 + mu sigma`` (mu = 0.1, zeta = 0.1, alpha = 1) over ``sigma in
   [-1, 3]``, ``h in [0.02, 0.4]``, through its cusp.  kbm: the one-parameter response in
   ``sigma`` at ``h = 0.3`` (:func:`numerics.bifurcation.forced.forced_seeds`; a seed on
   the box's edge ``h = 0.4`` ends at once, ``the first point lies outside the box``), then
   :func:`~numerics.bifurcation.forced.forced_true_curves` (every point ``max |G| <=
   1e-10``).  AUTO: the system made autonomous by its forcing oscillator (``c' = c + nu s -
   c (c^2 + s^2)``, ``s' = -nu c + s - s (c^2 + s^2)``), a periodic orbit continued in
   ``h`` from rest at ``h = 0`` to ``0.3`` (``sigma = 1``), in ``sigma`` to its fold (LP),
   then the fold both ways in ``(sigma, h)`` (``ISW = 2``), NTST = 60, at ``EPSL = EPSU =
   1e-7`` (its demos') and ``1e-10``.  Checks: AUTO's cusp (the LP in ``sigma`` of its fold
   curve) against kbm's; at 16 of AUTO's points (``h`` above the cusp's by 0.01), kbm's
   fold solved at AUTO's ``h`` (Newton, ``|G| <= 1e-10``): ``|d sigma|``.
2. The coupled-vdp locking tongue (mu = 0.1) over ``sigma in [-1, 1]``, ``c in [0.05,
   0.6]``: kbm's two fold curves of the locked cycle (:func:`numerics.bifurcation.coupled.
   coupled_true_folds`, seeded at ``c = 0.3`` by ``locate_fold``); AUTO: the in-phase
   cycle at ``sigma = 0``, ``c = 0.3`` continued in ``sigma`` to each fold, each fold both
   ways (``ISW = 2``, one process an edge, NTST = 60, ``EPSL = EPSU = 1e-10``).  Check:
   kbm's edge solved at AUTO's ``c`` (its bordered test, ``|G| <= 1e-10``).
3. The heteroclinic cycle of the SEDF's saddles ``+-2.61`` (paper eq. 3 at rest; mu =
   0.1, lam = 1) over ``(Delta, beta)``, from ``beta = 0.5`` to ``Delta = 2.75`` (near the
   saddles' fold line ``2.7453854573``, where the connection ends at a saddle-node loop).
   kbm: :func:`numerics.bifurcation.connections.scan` of ``beta = 0.5``, then the curve
   with the manifolds' gap as the defining function (every point ``|gap| <= 1e-10``).
   AUTO, two ways.  The long-period approximation: the Hopf point of the origin in a gain
   ``s``, the van der Pol cycle to ``s = 1``, in ``Delta`` to period 12, in the period to
   ``T = 15``, then at that fixed period in ``(Delta, beta)`` (NTST = 200).  HomCont
   (``IPS = 9``, a heteroclinic orbit with its equilibria solved for, ``IEQUIB = -2``): the
   period-15 orbit's leg from the saddle near ``+2.61`` to the one near ``-2.61`` as its
   start (``dat``), the truncation interval continued from about 7.5 to 10 at ``beta =
   0.5``, then the connection in ``(Delta, beta)`` (NTST = 200); its seed time includes the
   long-period orbit's.  Checks: kbm's connection at AUTO's ``beta`` (the secant method on
   the gap), at the last point at AUTO's ``Delta``, and AUTO's long-period ``Delta``
   against the period at ``beta = 0.5``.  AUTO's Newton fails beyond ``T = 16-17`` (NTST
   200 to 800, NCOL 4 or 7, 12 Newton steps): the saddles' eigenvalues are about ``+-4.2``.

Measured 2026-11-27 (``--repeats 3``; two cores under a load of about 10, so the walls are
about 3x the CPU seconds, which are the numbers to compare):

1. kbm 0.25 s seed + 0.31 s curve CPU (0.68 + 0.89 s wall), 38 points, ``max |G|
   6.7e-15``.  AUTO at 1e-7: 0.07 + 0.84 s (70 points); at 1e-10: 0.13 + 1.47 s (151
   points).  AUTO / kbm (CPU, seed + curve): 1.64 and 2.88; the curve alone 2.73 and 4.77.
   The cusps agree to 1.3e-12 in ``sigma`` and 4.3e-12 in ``h`` (``0.1745973212,
   0.1313990559``); AUTO's points are within 1.1e-9 (at 1e-7) and 2.2e-10 (at 1e-10) in
   ``sigma`` of kbm's folds at their ``h``.
2. kbm 1.54 s CPU (4.56 s wall), seeds included, 46 points, ``max |G| 7.4e-15``; AUTO 0.74
   + 2.72 s (247 points): AUTO / kbm 2.24.  AUTO's points are within 2.4e-11 in ``sigma``
   of kbm's edges.
3. kbm 0.07-0.08 s seed + 0.05-0.07 s curve CPU (0.11-0.17 + 0.08-0.13 s wall; three
   runs of ``--repeats 5``), 9 points, ``max |gap| 1.2e-11``.  The long-period orbit:
   0.24-0.33 + 0.06-0.08 s (27 points), AUTO / kbm 2.38-2.85 (wall 3.70-4.77); its
   ``Delta`` is below kbm's by 1.2e-6 at ``beta = 0.5``, 1.1e-4 at 0.539, 5.1e-2 at 0.565,
   and its ``beta`` 2.2e-3 below kbm's at ``Delta = 2.75`` (towards the fold line the
   saddles' eigenvalues tend to 0 and a period of 15 is no longer long).  At ``beta =
   0.5`` against the period: ``-4.8e-4`` (T = 12), ``-6.8e-5`` (13), ``-9.7e-6`` (14),
   ``-1.2e-6`` (15), ``-1.5e-7`` (16.0), ``-1.1e-7`` (16.2, its last): a factor of about 7
   per unit of T.  HomCont: 0.28-0.40 + 0.08-0.10 s (31 points), AUTO / kbm 2.85-3.47
   (wall 4.94-6.29); its ``Delta`` is within 2.3e-9 of kbm's for ``beta <= 0.551``
   (2.2e-11 at 0.5), 7.1e-8 at 0.562, and at its last point (``Delta = 2.7481``: past
   2.75) its ``beta`` is 2.0e-4 below kbm's (its truncation interval is too short there).
   On the same path to its own end (the step below ``2e-6`` at ``Delta = 2.745395``),
   kbm's curve took 0.76 s CPU before
   :meth:`numerics.bifurcation.autonomous.OneDof.compiled` read its parameter values from
   two lines bound once (60 % of it was ``compile_model`` at each new point, 15 % looking
   numba up) and 0.21 s after.  kbm's seed, the scan of ``beta
   = 0.5`` over every candidate loop, took 0.30-0.43 s CPU (AUTO / kbm 0.58-1.22 and
   0.70-1.54 in the same three interleaved runs) until the stable manifolds of the section
   gaps were followed backward by scipy (half of it), ``f(x, 0)`` was evaluated point by
   point on the equilibria's grid of 4001 and the kit lambdified its derivatives anew; now
   the compiled stepper's ``to_section``, one array evaluation and a memo per template:
   the same seed and curve points to the bit, the section gaps within 4.6e-12 (the 27 of
   the scan against both integrators at rtol 1e-14: scipy's within 4.5e-12, the
   stepper's within 2.2e-13).
"""

from __future__ import annotations

import argparse
import importlib.util
import statistics
import time

import numpy as np

from numerics.bifurcation.coupled import coupled_true_folds
from numerics.bifurcation.forced import DrivenProblem, forced_seeds, forced_true_curves
from numerics.bifurcation.twoway import joined

from _diagram_checks import (beta_gap_at_end, coupled_agreement, forced_agreement,
                             sedf_agreement)
from _auto_diagram import (COUPLED_EQUATIONS, COUPLED_SCRIPT, DUFFING_EQUATIONS,
                           DUFFING_SCRIPT, SEDF_CONSTANTS, SEDF_EQUATIONS, SEDF_SCRIPT,
                           auto_command, run_auto)

VALUES = {"mu": 0.1, "zeta": 0.1, "alpha": 1.0}
RANGES = {"sigma": (-1.0, 3.0), "h": (0.02, 0.4)}
#: the seed line of the fold curve (inside the box: a seed on its edge ends at once)
H_SEED = 0.3
#: the period of AUTO's long-period orbit (part 3); AUTO's Newton fails beyond T = 16-17
T_LONG = 15.0
#: HomCont's truncation interval (part 3)
T_HOMCONT = 10.0
#: part 3's curves run from beta = 0.5 to Delta = D_END, near the saddles' fold line
#: 2.7453854573 (where the connection ends at a saddle-node loop)
D_END = 2.75


def _clock() -> tuple[float, float]:
    return time.perf_counter(), time.process_time()


def _since(c0: tuple[float, float]) -> list[float]:
    c1 = _clock()
    return [c1[0] - c0[0], c1[1] - c0[1]]


def _median(runs: list[list[float]]) -> list[float]:
    return [statistics.median(r[j] for r in runs) for j in (0, 1)]


def kbm_forced(prob: DrivenProblem, repeats: int) -> dict:
    """kbm's seed (the one-parameter response in sigma at ``h = H_SEED``) and fold curve,
    timed ``repeats`` times warm: ``{"seed", "curve": [wall, cpu] medians, "z": the
    curve's points (x0, v0, sigma, h), "residual", "cusp"}``."""
    seed_t, curve_t = [], []
    for _ in range(repeats):
        c0 = _clock()
        seeds = forced_seeds(prob, RANGES["sigma"], [H_SEED])
        seed_t.append(_since(c0))
        c0 = _clock()
        tasks, curves, points = forced_true_curves(prob, RANGES, seeds)
        curve_t.append(_since(c0))
    z = np.concatenate([joined(t.paths) for t in tasks if t.kind == "fold"])
    cusp = [p.point for p in points if p.kind == "cusp"]
    return {"seed": _median(seed_t), "curve": _median(curve_t), "z": z,
            "residual": max(c.detail["residual_max"] for c in curves),
            "cusp": cusp[0] if cusp else None}


def kbm_sedf(repeats: int) -> dict:
    """kbm's homoclinic curve of part 3, timed ``repeats`` times warm: the scan of ``beta
    = 0.5`` (the seed) and the continuation with every point's gap at most 1e-10."""
    from kbm.model.builtins import get_model
    from numerics.bifurcation import connections as C
    from numerics.bifurcation.autonomous import OneDof
    from numerics.bifurcation.curve import continue_curve

    seed_t, curve_t = [], []
    for _ in range(repeats):
        c0 = _clock()
        kit = OneDof(get_model("sedf"), {"mu": 0.1, "lam": 1}, ("Delta", "beta"), (4.0, 0.5))
        seeds = C.scan(kit, [(a, 0.5) for a in np.linspace(3.7, 4.3, 7)], 8.0)
        seed_t.append(_since(c0))
        loop0, z0 = seeds[0]
        loop = C.Loop(loop0.x_from, loop0.x_to, loop0.leave, loop0.arrive)
        c0 = _clock()
        path = continue_curve(C.gap_function(kit, loop), np.array(z0), tangent=[0.0, 1.0],
                              ds=0.02, ds_max=0.1, bounds={0: (D_END, 6.0), 1: (0.3, 1.6)},
                              max_points=200, tol=C.GAP_TOL, fd_step=1e-6, scale=[6.0, 1.3],
                              on_point=lambda pt: C.accept(kit, loop, pt.z))
        curve_t.append(_since(c0))
    return {"seed": _median(seed_t), "curve": _median(curve_t), "kit": kit, "loop0": loop0,
            "z": np.array([p.z for p in path.points]),
            "gap": max(p.residual for p in path.points),
            "end": f"{path.end} ({path.message})", "delta_05": float(z0[0])}


def _times(label: str, t: dict) -> str:
    return (f"{label}: seed {t['seed'][0]:.2f} s wall / {t['seed'][1]:.2f} s CPU, curve "
            f"{t['curve'][0]:.2f} / {t['curve'][1]:.2f}")


def _ratio(k: dict, a: dict) -> str:
    ks = [k["seed"][j] + k["curve"][j] for j in (0, 1)]
    as_ = [a["seed"][j] + a["curve"][j] for j in (0, 1)]
    return (f"AUTO / kbm, seed + curve: {as_[0] / ks[0]:.2f} wall, {as_[1] / ks[1]:.2f} CPU; "
            f"curve alone {a['curve'][0] / k['curve'][0]:.2f} wall, "
            f"{a['curve'][1] / k['curve'][1]:.2f} CPU (> 1: kbm faster); AUTO's whole "
            f"process {a['whole'][0]:.2f} s wall, {a['whole'][1]:.2f} s CPU")


def _floats(rows) -> np.ndarray:
    return np.array([[float(v) for v in r] for r in rows])


def _installed(auto: str | None) -> bool:
    """Whether AUTO-07p runs here (else the part's line saying it is skipped)."""
    if auto is None:
        print("  AUTO-07p: not installed (no auto-07p or auto, or no gfortran): skipped")
    return auto is not None


def _auto_runs(auto: str | None, files: dict[str, str], envs: list[dict[str, str]],
               repeats: int) -> list[dict] | None:
    """:func:`run_auto` once per environment of ``envs``, or ``None`` with the line saying
    why (AUTO-07p not installed, or the first failure)."""
    if not _installed(auto):
        return None
    runs = [run_auto(auto, files, env, repeats) for env in envs]
    bad = [a for a in runs if isinstance(a, str)]
    if bad:
        print(f"  AUTO-07p: {bad[0]}")
        return None
    return runs


def part1(auto: str | None, repeats: int) -> None:
    print(f"1. forced Duffing fold curve over (sigma, h) in [-1, 3] x [0.02, 0.4], mu = 0.1, "
          f"zeta = 0.1, alpha = 1 (seeded at h = {H_SEED})")
    prob = DrivenProblem("duffing-forced", VALUES, ("sigma", "h"))
    kbm_forced(prob, 1)  # warm: the compiled flow loaded, the KBM slow flow derived
    k = kbm_forced(prob, repeats)
    print(f"  {_times('kbm', k)} (medians of {repeats}); {len(k['z'])} converged points, "
          f"max |G| {k['residual']:.1e}; cusp at sigma = {k['cusp'][0]:.10f}, "
          f"h = {k['cusp'][1]:.10f}")
    if not _installed(auto):
        return
    files = {"fduff.f90": DUFFING_EQUATIONS, "run.auto": DUFFING_SCRIPT}
    for eps in ("1e-7", "1e-10"):
        a = run_auto(auto, files, {"BENCH_EPS": eps}, repeats)
        if isinstance(a, str):
            print(f"  AUTO-07p, EPSL = EPSU = {eps}: {a}")
            continue
        pts = _floats(a["lines"]["P"])
        print(f"  {_times(f'AUTO-07p (NTST = 60, NCOL = 4, EPSL = EPSU = {eps})', a)} "
              f"(medians of {repeats}); {len(pts)} points")
        if a["lines"].get("CUSP"):
            cs, ch = (float(v) for v in a["lines"]["CUSP"][0])
            print(f"    AUTO's cusp (its LP in sigma on the fold curve) sigma = {cs:.10f}, "
                  f"h = {ch:.10f}: {abs(cs - k['cusp'][0]):.1e}, {abs(ch - k['cusp'][1]):.1e} "
                  f"from kbm's")
        worst, m, fails = forced_agreement(prob, k["z"], pts)
        print(f"    AUTO's points against kbm's fold solved at their h (|G| <= 1e-10): "
              f"largest |d sigma| {worst:.1e} over {m} points ({fails} failed)")
        print(f"    {_ratio(k, a)}")


def kbm_coupled(repeats: int) -> dict:
    """kbm's two tongue edges (seeds by :func:`numerics.locking.fold.locate_fold` from the
    locked cycle at ``c = 0.3``, then the fold curves), timed ``repeats`` times warm."""
    runs, tasks = [], []
    for _ in range(repeats):
        tasks = []
        c0 = _clock()
        curves, _ = coupled_true_folds("coupled-vdp", {"mu": 0.1}, ("sigma", "c"),
                                       {"sigma": (-1.0, 1.0), "c": (0.05, 0.6)}, [0.3],
                                       tasks_out=tasks)
        runs.append(_since(c0))
    return {"seed": [0.0, 0.0], "curve": _median(runs), "tasks": tasks,
            "n": sum(len(c.points) for c in curves),
            "residual": max(c.detail["residual_max"] for c in curves)}


def part2(auto: str | None, repeats: int) -> None:
    print("2. coupled-vdp locking tongue over (sigma, c) in [-1, 1] x [0.05, 0.6], mu = 0.1")
    kbm_coupled(1)  # warm
    k = kbm_coupled(repeats)
    print(f"  kbm: both edges, seeds (locate_fold) included, {k['curve'][0]:.2f} s wall / "
          f"{k['curve'][1]:.2f} s CPU (medians of {repeats}); {k['n']} converged points, "
          f"max |G| {k['residual']:.1e}")
    files = {"cvdp.f90": COUPLED_EQUATIONS, "run.auto": COUPLED_SCRIPT}
    sides = _auto_runs(auto, files, [{"BENCH_SIDE": side} for side in ("1", "-1")], repeats)
    if sides is None:
        return
    a = {key: [sum(x[key][j] for x in sides) for j in (0, 1)]
         for key in ("seed", "curve", "whole")}
    pts = np.concatenate([_floats(x["lines"]["P"]) for x in sides])
    label = "AUTO-07p (NTST = 60, NCOL = 4, EPSL = EPSU = 1e-10; one process an edge)"
    print(f"  {_times(label, a)}"
          f" (medians of {repeats}, the edges' sums); {len(pts)} points")
    worst, m, fails = coupled_agreement(k, pts)
    print(f"    AUTO's points against kbm's edge solved at their c (|G| <= 1e-10): largest "
          f"|d sigma| {worst:.1e} over {m} points ({fails} failed)")
    both = [a["seed"][j] + a["curve"][j] for j in (0, 1)]
    print(f"    AUTO / kbm (all of each): {both[0] / k['curve'][0]:.2f} wall, "
          f"{both[1] / k['curve'][1]:.2f} CPU (> 1: kbm faster); AUTO's whole processes "
          f"{a['whole'][0]:.2f} s wall, {a['whole'][1]:.2f} s CPU")


def part3(auto: str | None, repeats: int) -> None:
    print("3. SEDF heteroclinic cycle of the saddles +-2.61 over (Delta, beta), mu = 0.1, "
          "lam = 1")
    if importlib.util.find_spec("numerics.bifurcation.connections") is None:
        print("  the homoclinic continuation is not in this tree: skipped")
        return
    kbm_sedf(1)  # warm
    k = kbm_sedf(repeats)
    print(f"  {_times('kbm', k)} (medians of {repeats}); {len(k['z'])} converged points, "
          f"max |gap| {k['gap']:.1e}; Delta = {k['delta_05']:.12f} at beta = 0.5; the path "
          f"ended: {k['end']}")
    files = {"sedf.f90": SEDF_EQUATIONS, "c.sedf": SEDF_CONSTANTS, "run.auto": SEDF_SCRIPT}
    runs = _auto_runs(auto, files, [{"BENCH_T": f"{T_LONG:g}", "BENCH_TH": f"{T_HOMCONT:g}"}],
                      repeats)
    if runs is None:
        return
    a = runs[0]
    pts = _floats(a["lines"]["P"])
    end = [float(v) for v in a["lines"]["END"][-1]]
    print(f"  {_times(f'AUTO-07p, long-period orbit (period {T_LONG:g}, NTST = 200)', a)} "
          f"(medians of {repeats}); {len(pts)} points, to Delta = {end[0]:.6f}, "
          f"beta = {end[1]:.6f}")
    diffs, fails = sedf_agreement(k, pts)
    print(f"    its Delta less kbm's connection at the same beta ({fails} failed): "
          + ", ".join(f"{d:+.1e} (beta {b:.3f})" for b, d in diffs)
          + f"; {beta_gap_at_end(k, pts)}")
    print(f"    {_ratio(k, a)}")
    if "hcurve" in a:
        hp = _floats(a["lines"]["H"])
        h = {"seed": [a["seed"][j] + a["hseed"][j] for j in (0, 1)], "curve": a["hcurve"],
             "whole": a["whole"]}
        print(f"  {_times(f'AUTO-07p HomCont (IPS = 9, truncation {T_HOMCONT:g}, NTST = 200)', h)}"
              f"; {len(hp)} points (its seed: the long-period orbit's, then its leg from "
              f"saddle to saddle, the truncation interval continued from "
              f"about {T_LONG / 2:g} to {T_HOMCONT:g})")
        diffs, fails = sedf_agreement(k, hp, n=12)
        print(f"    its Delta less kbm's connection at the same beta ({fails} failed): "
              + ", ".join(f"{d:+.1e} (beta {b:.3f})" for b, d in diffs)
              + f"; {beta_gap_at_end(k, hp)}")
        print(f"    {_ratio(k, h)} (AUTO's whole process: both curves)")
    t = run_auto(auto, files, {"BENCH_T": f"{T_LONG:g}", "BENCH_TMAX": "18"}, 0)
    if isinstance(t, dict) and t["lines"].get("TD"):
        td = _floats(t["lines"]["TD"])
        row = []
        for T in (12, 13, 14, 15, 16, 17, float(td[:, 0].max())):
            i = int(np.argmin(np.abs(td[:, 0] - T)))
            row.append(f"T = {td[i, 0]:.2f}: {td[i, 1] - k['delta_05']:+.1e}")
        print("    at beta = 0.5, AUTO's long-period orbit's Delta less kbm's connection "
              "(AUTO's Newton fails beyond the last period): " + "; ".join(dict.fromkeys(row)))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3, help="timed runs of each (3)")
    parser.add_argument("--no-auto", action="store_true", help="leave AUTO-07p out")
    parser.add_argument("--parts", default="123", help="the parts to run (123)")
    args = parser.parse_args()
    auto = None if args.no_auto else auto_command()
    if "1" in args.parts:
        part1(auto, args.repeats)
    if "2" in args.parts:
        part2(auto, args.repeats)
    if "3" in args.parts:
        part3(auto, args.repeats)


if __name__ == "__main__":
    main()
