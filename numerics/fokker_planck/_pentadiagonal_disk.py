"""The order-by-order LU of :mod:`._pentadiagonal` with its kept factors in a temporary file
(:class:`DiskPentadiagonalLU`, out-of-core factors as in the out-of-core modes of sparse
direct solvers), and the choice between it and the factors in memory
(:func:`pentadiagonal_lu`: on disk when the factors in memory would exceed
:data:`FACTOR_MEMORY`).

Why: :class:`._pentadiagonal.HermitePentadiagonalLU` keeps ``3 m^2`` numbers per order,
``24 N m^2`` bytes, and six digits of the SEDF at rest below mu = 0.01 need more than the
machine's memory (mu = 0.005: about 364 functions x 1624 intervals, ``m`` = 813 folded
points, 5.8 GB; mu = 0.002 about 730 x 2032, 18 GB), while the operation count,
``8 N m^3``, is minutes.  Here the file keeps per order ``S^-1`` and
``X1 = S^-1 A(k, k-1)``, ``16 N m^2`` bytes on disk; the eliminated coupling
``P = A(k-1, k)`` is recomputed in the forward sweep from the original block and the
``X1`` of the order above by the factorisation's own element-wise operations, so that the
solutions are bit for bit those of the factors in memory (tests), and the memory is the
frontier of the elimination, a few ``m^2`` numbers.

Measured (SEDF at rest, Delta = 3, one BLAS thread, load 3 to 6 on 2 cores): at
mu = 0.01, D = 0.005, the ladder's 258 functions x 1040 intervals (3 inverse iteration
solves of 2 sweeps), in memory 1.79 GB peak RSS and 11.4-11.5 s CPU, on disk 0.17 GB and
13.1-13.6 s CPU (two interleaved pairs; 1.1 GB written in 0.5 s, 13 GB read by the 12
sweeps in 1.9 s from the page cache), the same moments and coefficients bit for bit.  At
mu = 0.005, D = 0.0025, the sizes the ladder's advice names for six digits, 364 x 1624
(5.8 GB in memory): 0.23 GB peak RSS, 3.8 GB on disk, 61 s CPU (7 s of it the system's,
the copies from the page cache); 512 x 1624 (8.1 GB in memory): 0.26 GB, 80 s.  There
``<x^2>``, ``<x'^2>`` moved by 3.5e-7, 6.4e-8 from 1300 to 1624 intervals, by 7.3e-8,
5.3e-8 from 364 to 512 functions and by 6.1e-8, 3.8e-8 from the scale 0.191 to 0.17:
six digits.  At mu = 0.002, D = 0.001, the advice's 730 x 2032 (18 GB in memory):
0.34 GB peak RSS, 12 GB on disk, 219 s CPU (32 s the system's), 5 min wall; five digits
(the moments moved by 4.7e-6, 4.2e-6 from 1624 intervals, by 1.1e-5, 8.6e-6 from 516
functions).  Without the page cache (the file not held in free memory) the sweeps read
at the disk's rate (here 0.77 GB/s, ``dd`` with direct I/O): 46 GB at 364 x 1624, about
a minute of waiting more.

The single-precision factorisation that preconditions GMRES (:mod:`._bordered`) keeps its
factors in single precision, ``12 N m^2`` bytes in memory and ``8 N m^2`` on disk
(``single``), so at mu = 0.005, 364 x 1624 (2.9 GB) it stays in memory; the direct solve,
its fallback, keeps the double factors and goes to disk by the same cap.

The alternatives, not taken: checkpointing the elimination (Griewank's revolve, the
frontier every ``K`` orders, a segment refactorised in the back substitution) costs about
two factorisations per sweep, and the inverse iteration makes 6 sweeps (3 solves with one
step of refinement each, counted at 258 x 1040 and 364 x 1624: the start, the
eigenvector, the check of convergence), about 11 factorisations for 1, where the sweeps
are 10 % of a solve (:mod:`._pentadiagonal`); the right-hand side carried along the
factorisation saves only the first forward sweep (its right-hand side is the Maxwellian,
in the order 0 alone), since the back substitution needs the factors in the reverse order
and every later solve needs them again.
"""

from __future__ import annotations

import shutil
import tempfile

import numpy as np

from ._pentadiagonal import HermitePentadiagonalLU

__all__ = ["DiskPentadiagonalLU", "FACTOR_MEMORY", "factor_bytes", "pentadiagonal_lu"]

#: the largest factors (bytes, :func:`factor_bytes`) kept in memory; beyond it
#: :func:`pentadiagonal_lu` keeps them on disk.  Above the largest solve of ``kbm noise``
#: at mu >= 0.01 (SEDF at rest, mu = 0.01, D = 0.005: 258 x 1300 for ``P(E)``, 2.6 GB in
#: double, 1.3 GB in single precision), whose solves stay in memory.
FACTOR_MEMORY = 3e9


def factor_bytes(n: int, m: int, single: bool = False) -> int:
    """The bytes :class:`._pentadiagonal.HermitePentadiagonalLU` keeps for ``n`` orders of
    ``m`` points: three ``m x m`` blocks per order, of 8 bytes (4 with ``single``)."""
    return (12 if single else 24) * int(n) * int(m) ** 2


def pentadiagonal_lu(terms, m: int, pinned=(), single: bool = False) -> HermitePentadiagonalLU:
    """The order-by-order LU of ``terms`` (in single precision with ``single``, the
    preconditioner of :mod:`._bordered`): in memory
    (:class:`._pentadiagonal.HermitePentadiagonalLU`) when :func:`factor_bytes` is at most
    :data:`FACTOR_MEMORY`, else on disk (:class:`DiskPentadiagonalLU`, the same
    solutions)."""
    n = terms[0][0].shape[0]
    if factor_bytes(n, m, single) <= FACTOR_MEMORY:
        return HermitePentadiagonalLU(terms, m, pinned, single=single)
    return DiskPentadiagonalLU(terms, m, pinned, single=single)


class DiskPentadiagonalLU(HermitePentadiagonalLU):
    """:class:`._pentadiagonal.HermitePentadiagonalLU` with ``S^-1`` and ``S^-1 A(k, k-1)``
    of every order in an unnamed temporary file (removed when the object is freed) and the
    eliminated ``A(k-1, k)`` recomputed in the forward sweep (module docstring).

    Parameters
    ----------
    terms, m, pinned, single
        As :class:`._pentadiagonal.HermitePentadiagonalLU` (``single``: the records in
        single precision, ``8 N m^2`` bytes).
    directory : str, optional
        Where the file goes (default :func:`tempfile.gettempdir`, ``TMPDIR``).

    Raises
    ------
    kbm.errors.ModelError
        When the directory has less free space than the factors need.
    numpy.linalg.LinAlgError
        As :class:`._pentadiagonal.HermitePentadiagonalLU`.
    """

    def __init__(self, terms, m: int, pinned=(), directory: str | None = None,
                 single: bool = False):
        from kbm.errors import ModelError

        n = terms[0][0].shape[0]
        dtype = np.dtype(np.float32 if single else np.float64)
        directory = tempfile.gettempdir() if directory is None else directory
        need, free = 2 * dtype.itemsize * n * m * m, shutil.disk_usage(directory).free
        if need > free:
            raise ModelError(f"the Kramers solve's factors ({n} orders x {m} points) need "
                             f"{need / 1e9:.3g} GB on disk in {directory}, which has "
                             f"{free / 1e9:.3g} GB free: set TMPDIR to a directory with "
                             "more space, or take fewer functions or points")
        self._record = 2 * m * m * dtype.itemsize  # S^-1, then X1, per order from the top
        self._file = tempfile.TemporaryFile(dir=directory)
        self._buffers = np.empty((2, 2, m, m), dtype)  # this order's record, the one above
        self._tmp = np.empty((m, m), dtype)
        self._above = -1  # the order whose X1 is in the second buffer
        super().__init__(terms, m, pinned, single=single)
        self._file.flush()

    def _keep(self, k: int, sinv: np.ndarray, x1: np.ndarray, p: np.ndarray) -> None:
        """Append ``S^-1`` and ``X1`` of the order ``k`` (written in the factorisation's
        order, ``k`` from ``n - 1`` down)."""
        self._file.seek((self.n - 1 - k) * self._record)
        self._file.write(np.ascontiguousarray(sinv).data)
        self._file.write(np.ascontiguousarray(x1).data)

    def _read(self, k: int, into: np.ndarray) -> None:
        self._file.seek((self.n - 1 - k) * self._record)
        if self._file.readinto(into.data) != self._record:
            raise OSError(f"the factors of the order {k} could not be read back")

    def _forward_factors(self, k: int):
        """``S^-1`` from the file; ``A(k-1, k)`` as the factorisation made it: the original
        block less ``A(k-1, k+1)``'s diagonal times the ``X1`` of the order ``k + 1``."""
        cur, above = self._buffers
        if k == self.n - 1:
            p = self._coupling(k - 1, 1, True)
        else:
            if self._above != k + 1:
                self._read(k + 1, above)
            p = self._coupling(k - 1, 1, True)
            p -= np.multiply(self._q2[k + 1][:, None], above[1], out=self._tmp)
        self._read(k, cur)
        self._buffers = self._buffers[::-1]  # this order's record is the next one's above
        self._above = k
        return cur[0], p

    def _back_factors(self, k: int):
        cur = self._buffers[0]
        self._read(k, cur)
        return cur[1], cur[0]
