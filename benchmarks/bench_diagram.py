"""Time the two-parameter fold continuation of :mod:`numerics.bifurcation` against AUTO-07p.

Run: ``python benchmarks/bench_diagram.py``

1. The fold curve of the forced Duffing oscillator ``x'' + x = mu (-2 zeta x' - alpha x^3 +
   h cos nu t)``, ``nu = 1 + mu sigma`` (mu = 0.1, zeta = 0.1, alpha = 1) over ``sigma in
   [-1, 3]``, ``h in [0.02, 0.4]``, through its cusp: :func:`numerics.bifurcation.forced.
   forced_true_curves` from the one-parameter fold at ``h = 0.4`` (warm: the flow
   compiled), every point converged (``max |G| <= 1e-10``).  Where AUTO-07p is installed
   (``auto`` on the path, or ``$AUTO_DIR/bin/auto``), the same curve by AUTO in the same
   run: the system made autonomous with AUTO's forcing oscillator (``c' = c + nu s - c (c^2 +
   s^2)``, ``s' = -nu c + s - s (c^2 + s^2)``), a periodic orbit continued in ``h`` from the
   rest state at ``h = 0``, then in ``sigma`` to its fold (LP), then the fold in ``(sigma,
   h)`` (``ISW = 2``); the ratio AUTO/kbm of the wall times is printed.  Target: kbm faster.
2. The coupled-vdp locking tongue (mu = 0.1) over ``sigma in [-1, 1]``, ``c in [0.05,
   0.6]``: the two fold curves of the locked cycle
   (:func:`numerics.bifurcation.coupled.coupled_true_folds`), seeds included.
3. A homoclinic curve of the SEDF (paper eq. 3; mu = 0.1, lam = 1) over ``(Delta, beta)``:
   the connection found on the line ``beta = 0.5`` (:func:`numerics.bifurcation.
   connections.scan`, the loop through the saddles at ``x = +-2.61`` near ``Delta = 3.99``)
   and continued with the manifolds' gap as the defining function, every point converged to
   ``|gap| <= 1e-10`` (:data:`numerics.bifurcation.connections.GAP_TOL`).  AUTO's
   counterpart (HomCont, or a long-period orbit) is not scripted here.

AUTO-07p is not a dependency of the project; the AUTO part is skipped (and said so) where
it is not installed.
"""

from __future__ import annotations

import importlib.util
import os
import shutil
import subprocess
import tempfile
import textwrap
import time
from pathlib import Path

import numpy as np

from numerics.bifurcation.coupled import coupled_true_folds
from numerics.bifurcation.forced import DrivenProblem, forced_seeds, forced_true_curves

from _auto import EMPTY_SUBROUTINES, FUNC_HEAD, STPNT_HEAD

VALUES = {"mu": 0.1, "zeta": 0.1, "alpha": 1.0}
RANGES = {"sigma": (-1.0, 3.0), "h": (0.02, 0.4)}

AUTO_EQUATIONS = "!  forced Duffing, made autonomous by AUTO's forcing oscillator (c, s)\n" \
    + FUNC_HEAD + textwrap.dedent("""\
      DOUBLE PRECISION MU, ZETA, ALPHA, NU, R
      MU = 0.1d0
      ZETA = 0.1d0
      ALPHA = 1.0d0
      NU = 1.0d0 + MU*PAR(1)
      R = U(3)**2 + U(4)**2
      F(1) = U(2)
      F(2) = -U(1) + MU*(-2*ZETA*U(2) - ALPHA*U(1)**3 + PAR(2)*U(3))
      F(3) = U(3) + NU*U(4) - U(3)*R
      F(4) = -NU*U(3) + U(4) - U(4)*R
    END SUBROUTINE FUNC

""") + STPNT_HEAD + textwrap.dedent("""\
      DOUBLE PRECISION PI, NU
      PI = 4*ATAN(1.0d0)
      PAR(1) = 1.0d0
      PAR(2) = 0.0d0
      NU = 1.0d0 + 0.1d0*PAR(1)
      PAR(11) = 2*PI/NU
      U(1) = 0.0d0
      U(2) = 0.0d0
      U(3) = COS(2*PI*T)
      U(4) = -SIN(2*PI*T)
    END SUBROUTINE STPNT

""") + EMPTY_SUBROUTINES

AUTO_SCRIPT = textwrap.dedent("""\
    import time
    t0 = time.perf_counter()
    common = dict(e='fduff', NDIM=4, IPS=2, NTST=60, NCOL=4, ILP=1, ISP=2, NMX=2000,
                  DS=0.01, DSMIN=1e-6, DSMAX=0.05, EPSL=1e-10, EPSU=1e-10, EPSS=1e-8,
                  JAC=0, NPR=1000)
    r1 = run(ICP=[2, 11], UZSTOP={2: 0.4}, IRS=0, **common)
    r2 = run(r1('UZ1'), ICP=[1, 11], UZSTOP={1: [-1.0, 3.0]}, **common)
    r3 = run(r2('LP1'), ISW=2, ICP=[1, 2, 11], UZSTOP={2: [0.02, 0.4], 1: [-1.0, 3.0]},
             **common)
    r4 = run(r2('LP1'), ISW=2, ICP=[1, 2, 11], UZSTOP={2: [0.02, 0.4], 1: [-1.0, 3.0]},
             **{**common, 'DS': -0.01})
    print('SECONDS', time.perf_counter() - t0)
    print('POINTS', len(r3()) + len(r4()))
""")


def auto_command() -> str | None:
    """The ``auto`` program of AUTO-07p, or None."""
    found = shutil.which("auto")
    if found:
        return found
    home = os.environ.get("AUTO_DIR")
    if home and (Path(home) / "bin" / "auto").exists():
        return str(Path(home) / "bin" / "auto")
    return None


def run_auto(auto: str, timeout: float = 900) -> tuple[float | None, str]:
    """AUTO's wall time for the fold curve (all three runs) and its report line."""
    with tempfile.TemporaryDirectory() as tmp:
        Path(tmp, "fduff.f90").write_text(AUTO_EQUATIONS)
        Path(tmp, "bench.auto").write_text(AUTO_SCRIPT)
        t0 = time.perf_counter()
        try:
            out = subprocess.run([auto, "bench.auto"], cwd=tmp, capture_output=True, text=True,
                                 timeout=timeout)
        except subprocess.TimeoutExpired:
            return None, f"did not finish in {timeout:g} s"
        wall = time.perf_counter() - t0
    lines = out.stdout.splitlines()
    secs = [ln.split()[1] for ln in lines if ln.startswith("SECONDS")]
    pts = [ln.split()[1] for ln in lines if ln.startswith("POINTS")]
    if not secs:
        tail = (out.stderr.strip() or out.stdout.strip() or "no output").splitlines()[-1]
        return None, f"failed: {tail[:200]}"
    return wall, f"{float(secs[0]):.2f} s inside AUTO ({wall:.2f} s with compilation), " \
                 f"{pts[0] if pts else '?'} points"


def kbm_forced() -> tuple[float, float, int, float, tuple]:
    prob = DrivenProblem("duffing-forced", VALUES, ("sigma", "h"))
    t0 = time.perf_counter()
    seeds = forced_seeds(prob, RANGES["sigma"], [RANGES["h"][1]])
    t_seed = time.perf_counter() - t0
    t0 = time.perf_counter()
    _, curves, points = forced_true_curves(prob, RANGES, seeds)
    t_curve = time.perf_counter() - t0
    n = sum(len(c.points) for c in curves)
    res = max(c.detail["residual_max"] for c in curves)
    cusp = [p.point for p in points if p.kind == "cusp"]
    return t_seed, t_curve, n, res, cusp[0] if cusp else None


def main() -> None:
    print("1. forced Duffing fold curve over (sigma, h), mu = 0.1, zeta = 0.1, alpha = 1")
    DrivenProblem("duffing-forced", VALUES, ("sigma", "h")).monodromy(np.array([1, 0, 0, .1]))
    t_seed, t_curve, n, res, cusp = kbm_forced()
    print(f"  kbm: seed (one-parameter response at h = 0.4) {t_seed:.2f} s; the fold curve "
          f"{t_curve:.2f} s for {n} converged points ({1e3 * t_curve / max(n, 1):.1f} ms a "
          f"point, max |G| {res:.1e}); cusp at sigma = {cusp[0]:.8f}, h = {cusp[1]:.8f}")
    auto = auto_command()
    if auto is None:
        print("  AUTO-07p: not installed (no `auto` on the path, no $AUTO_DIR): skipped")
    else:
        wall, line = run_auto(auto)
        print(f"  AUTO-07p ({auto}): {line}")
        if wall is not None:
            print(f"  ratio AUTO / kbm (seed + curve): {wall / (t_seed + t_curve):.1f}x "
                  f"(target > 1: {wall > t_seed + t_curve})")

    print("2. coupled-vdp locking tongue over (sigma, c), mu = 0.1")
    t0 = time.perf_counter()
    curves, _ = coupled_true_folds("coupled-vdp", {"mu": 0.1}, ("sigma", "c"),
                                   {"sigma": (-1.0, 1.0), "c": (0.05, 0.6)}, [0.3])
    t = time.perf_counter() - t0
    n = sum(len(c.points) for c in curves)
    print(f"  kbm: two fold curves, {n} converged points in {t:.2f} s (seeds by "
          f"locate_fold included; max |G| "
          f"{max(c.detail['residual_max'] for c in curves):.1e})")

    print("3. SEDF homoclinic curve over (Delta, beta), mu = 0.1, lam = 1")
    if importlib.util.find_spec("numerics.bifurcation.connections") is None:
        print("  the homoclinic continuation is not in this tree: skipped")
        return
    t_scan, t_curve, n, gap, end = sedf_homoclinic()
    print(f"  kbm: scan of beta = 0.5 {t_scan:.2f} s; the curve {t_curve:.2f} s for {n} "
          f"converged points ({1e3 * t_curve / max(n, 1):.0f} ms a point, max |gap| "
          f"{gap:.1e}; the path ended: {end})")


def sedf_homoclinic() -> tuple[float, float, int, float, str]:
    from kbm.models import get_model
    from numerics.bifurcation import connections as C
    from numerics.bifurcation.autonomous import OneDof
    from numerics.bifurcation.curve import continue_curve

    t0 = time.perf_counter()
    kit = OneDof(get_model("sedf"), {"mu": 0.1, "lam": 1}, ("Delta", "beta"), (4.0, 0.5))
    seeds = C.scan(kit, [(a, 0.5) for a in np.linspace(3.7, 4.3, 7)], 8.0)
    t_scan = time.perf_counter() - t0
    loop0, z0 = seeds[0]
    loop = C.Loop(loop0.x_from, loop0.x_to, loop0.leave, loop0.arrive)
    t0 = time.perf_counter()
    path = continue_curve(C.gap_function(kit, loop), np.array(z0), tangent=[0.0, 1.0], ds=0.02,
                          ds_max=0.1, bounds={0: (0.0, 6.0), 1: (0.3, 1.6)}, max_points=200,
                          tol=C.GAP_TOL, fd_step=1e-6, scale=[6.0, 1.3],
                          on_point=lambda pt: C.accept(kit, loop, pt.z))
    t_curve = time.perf_counter() - t0
    return t_scan, t_curve, len(path.points), max(p.residual for p in path.points), \
        f"{path.end} ({path.message})"


if __name__ == "__main__":
    main()
