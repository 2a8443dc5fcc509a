"""The same input gives the same bytes (the developers' guide) for the Kramers solutions:
independent of the BLAS's thread count and of the process's history.

* OpenBLAS's ``dgemm`` splits a product among its threads, and the split changes the last
  bits; the stationary solution's Chebyshev series (``KramersSolution._series``, hence
  ``P(E)`` of ``kbm noise --json``) was computed on the BLAS's default threads, so the JSON
  of ``OPENBLAS_NUM_THREADS=1`` and ``=2`` differed (SEDF mu = 0.1: ``P`` by 2.5e-14, its
  stated change by 1e-9 relative).  Checked here in two processes, one thread and two, the
  second with other allocations first (other addresses for the arrays: the kernels' rounding
  must not depend on the alignment either).  On a one-core machine OpenBLAS runs one thread
  whatever the variable says, and the check holds trivially.
* ARPACK draws its start vector from a seed it keeps between calls, so an Arnoldi run
  without ``v0`` gave another rate's last bits after any other Arnoldi run in the process.
"""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys

import numpy as np
import scipy.sparse.linalg as spla

from numerics.fokker_planck._bases import cheb
from numerics.fokker_planck._orthonormal import orthonormal_slowest
from numerics.fokker_planck._sink_pairs import tanh_sink

from test_fokker_planck_blocks import _cdc_wells

#: a stationary SEDF solution of 64 Hermite functions x 128 Chebyshev intervals (its
#: series is a 129 x 129 by 129 x 64 product, which OpenBLAS splits among two threads),
#: its moments and P(E) on 8 energies, printed as JSON
SCRIPT = """
import json, sys
import numpy as np
if sys.argv[1] == "scatter":  # other addresses for the arrays allocated after this
    keep = [np.empty(n) for n in (3, 17, 1, 250, 5, 4097, 9, 33)]
    keep += [np.empty(n)[1:] for n in (7, 129, 65)]
from numerics.fokker_planck import stationary_kramers
from numerics.fokker_planck._energy_density import energy_density, energy_grid
sol = stationary_kramers("sedf", {"mu": 0.1, "Delta": 3, "beta": 1, "Omega": 1, "lam": 1},
                         0.05, n_hermite=64, n_cheb=128)
P = energy_density(sol, energy_grid(sol, 8))
print(json.dumps([sol.x2, sol.v2] + [float(p) for p in P]))
"""


def _run(threads: int, allocations: str) -> subprocess.Popen:
    env = dict(os.environ, OPENBLAS_NUM_THREADS=str(threads), OMP_NUM_THREADS=str(threads))
    return subprocess.Popen([sys.executable, "-c", SCRIPT, allocations], env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def test_stationary_density_bytes_do_not_depend_on_blas_threads():
    """The moments and ``P(E)`` of one stationary solve, in a process with one BLAS
    thread and in one with two (and other allocations first), are the same bytes."""
    runs = [_run(1, "plain"), _run(2, "scatter")]
    outs = []
    for proc in runs:
        out, err = proc.communicate(timeout=300)
        assert proc.returncode == 0, err
        outs.append(out)
    values = json.loads(outs[0])
    assert all(math.isfinite(v) for v in values) and max(values[2:]) > 0
    assert outs[0] == outs[1]


def test_escape_rate_bits_do_not_depend_on_earlier_arnoldi_runs():
    """The slowest decay rate with the sink (CDC mu = 1, 32 orthonormal Hermite functions x
    96 Chebyshev intervals, block LU and shift-invert Arnoldi,
    :func:`numerics.fokker_planck._orthonormal.orthonormal_slowest`) is the same to the bit
    before and after an unrelated Arnoldi run in the process."""
    mu, kT = 1.0, 0.15
    split, g, xs, wells = _cdc_wells(mu)
    half, width = 1.2 * wells[1], 0.1 * (wells[1] - xs)
    args = (split, kT * mu, math.sqrt(kT), lambda n: cheb(n, half), 32, 96,
            lambda x: tanh_sink(x, wells, 5.0, width))
    first = orthonormal_slowest(*args)
    spla.eigs(np.diag(np.arange(1.0, 21.0)), k=2, which="LM", return_eigenvectors=False)
    assert first > 0
    assert orthonormal_slowest(*args) == first
