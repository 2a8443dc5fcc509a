"""The AUTO-07p files of ``bench_diagram.py`` (Fortran 90 equations with their Jacobians,
the constants and the ``run.auto`` scripts) and the runner that times them.

Part 1, the forced Duffing oscillator made autonomous by AUTO's forcing oscillator
(``c' = c + nu s - c (c^2 + s^2)``, ``s' = -nu c + s - s (c^2 + s^2)``, whose stable cycle
is ``(cos nu t, -sin nu t)``): a periodic orbit continued in ``h`` from rest at ``h = 0``
to ``h = 0.3`` (at ``sigma = 1``), then in ``sigma`` to its fold (LP), then the fold in
``(sigma, h)`` (``ISW = 2``: its start data, then both directions).  Part 2, coupled-vdp:
the in-phase cycle from ``2 cos t`` at ``sigma = 0``, ``c = 0.3``, in ``sigma`` to a fold,
the fold both ways in ``(sigma, c)``; one process an edge.  Part 3, the SEDF (paper eq. 3
at rest, ``x'' + mu (beta x^2 - s) x' + Delta sin(2 pi x/lam) + x = 0``, the gain ``s`` as
in ``bench_branch.py``): the Hopf point of the origin at ``s = 0``, the van der Pol cycle
continued to ``s = 1``, then in ``Delta`` to period 12, then in the period to ``T``, then
at that fixed period in ``(Delta, beta)`` (the long-period approximation of the
heteroclinic cycle) from ``beta = 0.5`` to ``Delta = 2.75``, as kbm's path goes; then
HomCont (``IPS = 9``) from that orbit's leg between the saddles.  Each script prints
``CLOCK part wall cpu`` (``cpu``: the Fortran processes' user + system seconds) and its
points, ``P`` (``H`` for HomCont's) lines with ``repr`` floats.
"""

from __future__ import annotations

import os
import re
import resource
import statistics
import subprocess
import tempfile
import textwrap
import time
from pathlib import Path

from _auto import EMPTY_SUBROUTINES, FUNC_HEAD, STPNT_HEAD, sedf_constants, sedf_equations

def _head(setting: str, e: str | None = None, eps: str = "") -> str:
    """The opening of a ``run.auto`` script: its imports, ``setting`` (a line reading the
    script's environment), ``clock()`` (wall seconds and the Fortran processes' user +
    system seconds), for the periodic orbits of equations ``e`` the options ``common``
    (NTST = 60, NCOL = 4, Newton's tolerances EPSL = EPSU = ``eps``), and ``c0 = clock()``."""
    common = "" if e is None else (
        f"common = dict(e='{e}', NDIM=4, IPS=2, NTST=60, NCOL=4, ILP=1, ISP=2, NMX=2000,\n"
        f"              DS=0.01, DSMIN=1e-6, DSMAX=0.05, EPSL={eps}, EPSU={eps}, EPSS=1e-8, "
        "JAC=1,\n              NPR=10000)\n")
    return ("import math, os, shutil, time\n" + setting + "\ndef clock():\n"
            "    t = os.times()\n"
            "    return time.perf_counter(), t.children_user + t.children_system\n"
            + common + "c0 = clock()\n")


DUFFING_EQUATIONS = "!  forced Duffing, made autonomous by AUTO's forcing oscillator (c, s)\n" \
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
      IF (IJAC == 0) RETURN
      DFDU(:, :) = 0.0d0
      DFDU(1, 2) = 1.0d0
      DFDU(2, 1) = -1.0d0 - 3*MU*ALPHA*U(1)**2
      DFDU(2, 2) = -2*MU*ZETA
      DFDU(2, 3) = MU*PAR(2)
      DFDU(3, 3) = 1.0d0 - R - 2*U(3)**2
      DFDU(3, 4) = NU - 2*U(3)*U(4)
      DFDU(4, 3) = -NU - 2*U(3)*U(4)
      DFDU(4, 4) = 1.0d0 - R - 2*U(4)**2
      IF (IJAC /= 2) RETURN
      DFDP(:, 1:2) = 0.0d0
      DFDP(3, 1) = MU*U(4)
      DFDP(4, 1) = -MU*U(3)
      DFDP(2, 2) = MU*U(3)
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

#: AUTO's tolerances are its Newton's relative corrections (EPSL, EPSU); the fold run is
#: timed at both ``1e-7`` (AUTO's demos) and ``1e-10``
DUFFING_SCRIPT = _head("EPS = float(os.environ['BENCH_EPS'])", "fduff", "EPS") \
    + textwrap.dedent("""\
    r1 = run(ICP=[2, 11], UZSTOP={2: 0.3}, IRS=0, **common)
    r2 = run(r1('UZ1'), ICP=[1, 11], UZSTOP={1: [-1.0, 3.0]},
             **{**common, 'DS': -0.01, 'STOP': ['LP1']})
    c1 = clock()
    box = dict(ISW=2, ICP=[1, 2, 11], UZSTOP={1: [-1.0, 3.0], 2: [0.02, 0.4]}, STOP=[])
    r3 = run(r2('LP1'), **box, **common)
    r4 = run(r3, **box, **common)
    r5 = run(r3, **box, **{**common, 'DS': -0.01})
    c2 = clock()
    print('CLOCK seed', c1[0] - c0[0], c1[1] - c0[1])
    print('CLOCK curve', c2[0] - c1[0], c2[1] - c1[1])
    for b in (r4[0], r5[0]):
        for s, h in zip(b['PAR(1)'], b['PAR(2)']):
            print('P', repr(float(s)), repr(float(h)))
    for lp in r5('LP') + r4('LP'):
        print('CUSP', repr(float(lp['PAR(1)'])), repr(float(lp['PAR(2)'])))
""")

COUPLED_EQUATIONS = "!  coupled-vdp (mu = 0.1): PAR(1) = sigma, PAR(2) = c\n" + FUNC_HEAD \
    + textwrap.dedent("""\
      DOUBLE PRECISION MU, S, C
      MU = 0.1d0
      S = PAR(1)
      C = PAR(2)
      F(1) = U(2)
      F(2) = -U(1) + MU*(U(2)*(1 - U(1)**2) + C*(U(4) - U(2)))
      F(3) = U(4)
      F(4) = -U(3) + MU*(U(4)*(1 - U(3)**2) + C*(U(2) - U(4)) - 2*S*U(3))
      IF (IJAC == 0) RETURN
      DFDU(:, :) = 0.0d0
      DFDU(1, 2) = 1.0d0
      DFDU(2, 1) = -1.0d0 - 2*MU*U(1)*U(2)
      DFDU(2, 2) = MU*(1 - U(1)**2 - C)
      DFDU(2, 4) = MU*C
      DFDU(3, 4) = 1.0d0
      DFDU(4, 3) = -1.0d0 - 2*MU*U(3)*U(4) - 2*MU*S
      DFDU(4, 4) = MU*(1 - U(3)**2 - C)
      DFDU(4, 2) = MU*C
      IF (IJAC /= 2) RETURN
      DFDP(:, 1:2) = 0.0d0
      DFDP(4, 1) = -2*MU*U(3)
      DFDP(2, 2) = MU*(U(4) - U(2))
      DFDP(4, 2) = MU*(U(2) - U(4))
    END SUBROUTINE FUNC

""") + STPNT_HEAD + textwrap.dedent("""\
      DOUBLE PRECISION PI
      PI = 4*ATAN(1.0d0)
      PAR(1) = 0.0d0
      PAR(2) = 0.3d0
      PAR(11) = 2*PI
      U(1) = 2*COS(2*PI*T)
      U(2) = -2*SIN(2*PI*T)
      U(3) = 2*COS(2*PI*T)
      U(4) = -2*SIN(2*PI*T)
    END SUBROUTINE STPNT

""") + EMPTY_SUBROUTINES

#: one edge of the tongue (``BENCH_SIDE`` = +1 or -1) per process: from the in-phase
#: cycle at ``sigma = 0``, ``c = 0.3`` (van der Pol's ``2 cos t``, corrected by AUTO) in
#: sigma to the fold, then the fold both ways in ``(sigma, c)``.  (With NTST = 40 this
#: AUTO aborted in ``free()`` after its third fold run; NTST = 60 runs through.)
COUPLED_SCRIPT = _head("SIDE = float(os.environ['BENCH_SIDE'])", "cvdp", "1e-10") \
    + textwrap.dedent("""\
    r = run(ICP=[1, 11], UZSTOP={1: [-1.0, 1.0]}, IRS=0,
            **{**common, 'DS': 0.01 * SIDE, 'STOP': ['LP1']})
    c1 = clock()
    box = dict(ISW=2, ICP=[1, 2, 11], UZSTOP={1: [-1.0, 1.0], 2: [0.05, 0.6]}, STOP=[])
    s = run(r('LP1'), **box, **common)
    out = [run(s, **box, **common), run(s, **box, **{**common, 'DS': -0.01})]
    c2 = clock()
    print('CLOCK seed', c1[0] - c0[0], c1[1] - c0[1])
    print('CLOCK curve', c2[0] - c1[0], c2[1] - c1[1])
    for b in out:
        for s_, c_ in zip(b[0]['PAR(1)'], b[0]['PAR(2)']):
            print('P', repr(float(s_)), repr(float(c_)))
""")

SEDF_EQUATIONS = sedf_equations("0.5D0")
SEDF_CONSTANTS = sedf_constants(npr=10000, itnw=12, nwtn=12, jac=1)

#: the period of the long-period orbit (``BENCH_T``), the longest period tried for the table
#: of Delta against T at beta = 0.5 (``BENCH_TMAX``, a run of its own), and HomCont's
#: truncation interval (``BENCH_TH``).  The curves stop at ``Delta = 2.75``, as kbm's does.
SEDF_SCRIPT = _head("T = float(os.environ['BENCH_T'])") + textwrap.dedent("""\
    eq = run('sedf')
    po = run(eq('HB1'), IPS=2, ICP=['s', 11], UZSTOP={'s': 1.0}, NMX=2000)
    de = run(po('UZ1'), IPS=2, ICP=['Delta', 11], UZSTOP={11: 12.0, 'Delta': 6.0}, NMX=5000)
    lt = run(de('UZ1'), IPS=2, ICP=[11, 'Delta'], UZSTOP={11: T}, NMX=5000, THL={},
             DSMAX=5.0)
    shutil.copy('fort.8', 'long.8')  # its solution at period T, for HomCont's start
    c1 = clock()
    box = dict(IPS=2, ICP=['Delta', 'beta'], NMX=2000, DSMAX=0.1, THL={},
               UZSTOP={'Delta': [2.75, 6.0], 'beta': [0.3, 1.6]})
    start = lt('UZ')[-1]
    h2 = run(start, DS='-', **box)  # from beta = 0.5 towards the fold line, as kbm's path
    c2 = clock()
    print('CLOCK seed', c1[0] - c0[0], c1[1] - c0[1])
    print('CLOCK curve', c2[0] - c1[0], c2[1] - c1[1])
    for b in (h2[0],):
        print('END', repr(float(b['Delta'][-1])), repr(float(b['beta'][-1])))
        for d, be in zip(b['Delta'], b['beta']):
            print('P', repr(float(d)), repr(float(be)))
    if os.environ.get('BENCH_TMAX'):
        lt2 = run(start, IPS=2, ICP=[11, 'Delta'], UZSTOP={11: float(os.environ['BENCH_TMAX'])},
                  NMX=5000, THL={}, DSMAX=5.0)
        for b in (lt[0], lt2[0]):
            for p, d in zip(b['PERIOD'], b['Delta']):
                print('TD', repr(float(p)), repr(float(d)))
        raise SystemExit
    # HomCont (IPS = 9): the leg of the period-T orbit from the saddle near +2.61 to the one
    # near -2.61 (AUTO's solution file read here: its Python's reader fails on this numpy),
    # its truncation interval continued to BENCH_TH, then the connection in (Delta, beta)
    c2 = clock()
    lines = open('long.8').read().split('\\n')
    head = [int(w) for w in lines[0].split()]
    ntpl, npar = head[6], head[11]
    rows = [[float(w) for w in ln.split()] for ln in lines[1:1 + ntpl]]
    par = [float(w) for ln in lines[1 + ntpl:1 + head[8]] for w in ln.split()][-npar:]
    D = par[0]
    def saddle(x):
        for _ in range(50):
            k = 2 * math.pi
            x -= (x + D * math.sin(k * x)) / (1 + k * D * math.cos(k * x))
        return x
    xp, xm = saddle(2.61), saddle(-2.61)
    near = lambda xs: min(range(ntpl), key=lambda i: math.hypot(rows[i][1] - xs, rows[i][2]))
    i1, i2 = near(xp), near(xm)
    idx = list(range(i1, i2 + 1)) if i2 > i1 else list(range(i1, ntpl)) + list(range(1, i2 + 1))
    tt = [(rows[i][0] - rows[i1][0]) % 1.0 for i in idx]
    tt[0] = 0.0
    for k in range(1, len(tt)):
        if tt[k] <= tt[k - 1]:
            tt[k] += 1.0
    with open('leg.dat', 'w') as f:
        for k, i in enumerate(idx):
            f.write(f"{tt[k] / tt[-1]!r} {rows[i][1]!r} {rows[i][2]!r}\\n")
    hc = dict(IPS=9, NUNSTAB=1, NSTAB=1, IEQUIB=-2, ITWIST=0, NTST=200, NCOL=4, ILP=0, ISP=0,
              NMX=500, JAC=1, THL={}, EPSL=1e-10, EPSU=1e-10)
    h0 = run(e='sedf', dat='leg.dat', IRS=0, ISTART=1, ICP=[11, 'Delta'], DS=0.1, DSMAX=1.0,
             PAR={'Delta': D, 's': 1.0, 'mu': 0.1, 'beta': 0.5, 'lam': 1.0,
                  11: tt[-1] * par[10], 12: xp, 13: 0.0, 14: xm, 15: 0.0},
             UZSTOP={11: float(os.environ['BENCH_TH'])}, **hc)
    c3 = clock()
    hh = run(h0('UZ1'), ICP=['Delta', 'beta'], DS=-0.01, DSMAX=0.1,
             UZSTOP={'Delta': [2.75, 6.0], 'beta': [0.3, 1.6]}, **hc)
    c4 = clock()
    print('CLOCK hseed', c3[0] - c2[0], c3[1] - c2[1])
    print('CLOCK hcurve', c4[0] - c3[0], c4[1] - c3[1])
    print('H0', repr(float(h0[0]['Delta'][-1])))
    for d, be in zip(hh[0]['Delta'], hh[0]['beta']):
        print('H', repr(float(d)), repr(float(be)))
""")


def auto_command() -> str | None:
    """The AUTO-07p command: Debian's ``auto-07p``, else ``auto`` on the path or
    ``$AUTO_DIR/bin/auto``; ``None`` where AUTO-07p or gfortran is not installed."""
    import shutil

    if shutil.which("gfortran") is None:
        return None
    for name in ("auto-07p", "auto"):
        found = shutil.which(name)
        if found:
            return found
    home = os.environ.get("AUTO_DIR")
    if home and (Path(home) / "bin" / "auto").exists():
        return str(Path(home) / "bin" / "auto")
    return None


def _env(extra: dict[str, str]) -> dict[str, str]:
    """AUTO's environment: one OpenMP thread unless ``OMP_NUM_THREADS`` is set (kbm runs
    on one core; with AUTO's default of a thread per core its waits on a shared machine
    made the same runs 5-40 times slower)."""
    env = {**os.environ, **extra}
    env.setdefault("OMP_NUM_THREADS", "1")
    return env


def run_auto(auto: str, files: dict[str, str], env: dict[str, str], repeats: int = 3,
             timeout: float = 900) -> dict | str:
    """Run ``run.auto`` in a temporary folder holding ``files``: once untimed (gfortran
    compiles the equations), then ``repeats`` times.  Returns AUTO's own clocks by name
    (``seed``, ``curve``, ...: ``[wall, cpu]`` medians), ``"whole"`` (``[wall, cpu]``
    medians of the whole ``auto-07p run.auto`` process: its Python, the Fortran runs; no
    clocks for ``repeats = 0``), and the lines of the last run by their first word; or the
    reason it failed."""
    runs, lines = [], {}
    with tempfile.TemporaryDirectory() as tmp:
        for name, text in files.items():
            Path(tmp, name).write_text(text)
        for i in range(repeats + 1):
            r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
            t0 = time.perf_counter()
            try:
                out = subprocess.run([auto, "run.auto"], cwd=tmp, capture_output=True,
                                     text=True, timeout=timeout, env=_env(env))
            except subprocess.TimeoutExpired:
                return f"did not finish in {timeout:g} s"
            wall = time.perf_counter() - t0
            r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
            clocks = dict((m.group(1), [float(m.group(2)), float(m.group(3))]) for m in
                          re.finditer(r"^CLOCK (\w+) (\S+) (\S+)$", out.stdout, re.M))
            if not {"seed", "curve"} <= set(clocks):
                tail = (out.stderr.strip() or out.stdout.strip() or "no output").splitlines()
                return f"failed: {tail[-1][:200]}"
            cpu = r1.ru_utime - r0.ru_utime + r1.ru_stime - r0.ru_stime
            if i:
                runs.append({**clocks, "whole": [wall, cpu]})
        for ln in out.stdout.splitlines():
            head, _, rest = ln.partition(" ")
            if head in ("P", "CUSP", "END", "TD", "H", "H0"):
                lines.setdefault(head, []).append(rest.split())
    med = {k: [statistics.median(r[k][j] for r in runs) for j in (0, 1)]
           for k in (runs[0] if runs else ())}
    return {**med, "lines": lines, "repeats": repeats}
