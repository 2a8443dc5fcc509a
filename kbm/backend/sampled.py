"""The one numeric KBM backend of one degree of freedom, forced or not.

For ``x'' + omega0**2 x = mu F(x, x'[, theta])`` with any smooth ``F`` (Taylor tables,
:class:`kbm.algebra.smooth.TaylorTable`), :func:`sampled_expansion` runs
:func:`kbm.expansion.recursion.kbm_recursion` over the grid algebra
:class:`kbm.algebra.grid.SampledAlgebra` (``P`` Chebyshev points in ``a``, ``M`` phases in ``psi``;
at a declared resonance also ``N`` forcing angles and the detuning ``sigma``).  The angles start
where ``F``'s Fourier tails along the unperturbed orbits fall below the tolerance
(:func:`resolved_angles`); the grid is refined while a Chebyshev (in ``a``) or Fourier (per angle)
tail of ``A_n``, ``B_n``, ``u_n`` exceeds ``tol`` times the size of that order's quantities
(:func:`measure`), then a second grid half as fine again measures the rounding errors the
differentiations in ``a`` amplify (:func:`differences`; :func:`resolve` is the loop).
:func:`kbm.numeric_derive` is its case without a resonance,
:func:`kbm.backend.forced.numeric_derive_forced` its case with one.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..algebra import chebyshev
from ..algebra.smooth import TaylorTable
from ..errors import ParameterError, ResolutionError, UnsupportedTermError
from .sampling import (check_bounded, check_grid, chebyshev_tail, comparison_matrices,
                       fourier_tail, order_scale, widened)
from ..algebra.grid import SampledAlgebra, SampledSeries, sampled_recursion
from ..model.forced import Resonance

__all__ = ["sampled_expansion", "SampledRun", "resolved_angles", "resolve", "measure",
           "differences"]


# ----------------------------------------------------------------------------- the angles
def resolved_angles(tables: dict, w0: float, lo: float, hi: float, tol: float, M: int, N: int,
                    max_M: int, max_N: int) -> tuple[int, int]:
    """The phases ``(M, N)`` (``psi``, ``theta``; ``N = 1`` without forcing), doubled from
    the given ones, at which ``F`` along the unperturbed orbits of five amplitudes of
    ``[lo, hi]`` is resolved: its Fourier tails below ``tol/100`` of its size.

    Raises
    ------
    kbm.errors.ParameterError
        ``F`` not finite, or not bounded (:func:`~kbm.backend.sampling.check_bounded`), on the
        orbits.
    kbm.errors.ResolutionError
        Past ``max_M`` or ``max_N``.
    """
    amps, M0, first = chebyshev.points(lo, hi, 5), M, None
    F = sum(t.F for t in tables.values())
    while True:
        psi = 2 * np.pi * np.arange(M) / M
        x0 = np.repeat((amps[:, None] * np.cos(psi)[None, :])[..., None], N, axis=2)
        v0 = np.repeat((-w0 * amps[:, None] * np.sin(psi)[None, :])[..., None], N, axis=2)
        TH = np.broadcast_to(2 * np.pi * np.arange(N) / N, x0.shape)
        with np.errstate(all="ignore"):
            f = sum(np.broadcast_to(np.asarray(t.function(0, 0)(x0, v0, *(TH,) * len(t.extra)),
                                               dtype=float), x0.shape) for t in tables.values())
        if not np.all(np.isfinite(f)):
            r, c, l = np.argwhere(~np.isfinite(f))[0]
            at = f", theta = {TH[r, c, l]:.6g}" if N > 1 else ""
            raise ParameterError(
                f"F = {F} is not finite at x = {x0[r, c, l]:.6g}, xdot = {v0[r, c, l]:.6g}{at} "
                f"(a = {amps[r]:.6g}): the numeric backend needs F finite and smooth on the "
                f"orbits of the a-range [{lo:g}, {hi:g}]; shrink the a-range or change F")
        scale = float(np.max(np.abs(f)))
        first = scale if first is None else first
        tm, tn = fourier_tail(f, 1), (fourier_tail(f, 2) if N > 1 else 0.0)
        grow = (tm > 0.01 * tol * scale, tn > 0.01 * tol * scale)
        if scale == 0 or not any(grow):
            return M, N
        over = (grow[0] and 2 * M > max_M) or (grow[1] and 2 * N > max_N)
        check_bounded(F, f, first, over, f"on the orbits of the a-range [{lo:g}, {hi:g}]",
                      f" ({M0} -> {M})")
        if over:
            raise ResolutionError(
                f"F = {F} varies too sharply along the orbits of the a-range "
                f"[{lo:g}, {hi:g}]: with M = {M} phases" + (f" x N = {N}" if N > 1 else "")
                + f" its Fourier coefficients at a = {hi:g} have fallen only to "
                f"{max(tm, tn) / scale:.1e} of its size (tolerance {tol:.0e}); use a smaller "
                "a_max, a smoother F (e.g. a larger eps in tanh(xdot/eps)) or a looser tol")
        M, N = (2 * M if grow[0] else M), (2 * N if grow[1] else N)


# ----------------------------------------------------------------------------- the loop
def resolve(make_run, measure, compare, grid: tuple[int, ...], tol: float,
            budget: tuple[int, ...], what: str):
    """The adaptive loop of the grid backends: runs on ``grid = (P, M[, N])`` refined (``P``
    to ``2 P - 1``, an angle doubled) while a tail exceeds ``tol``, then checked against a
    second grid half as fine again (:func:`~kbm.backend.sampling.check_grid`), which measures the
    rounding errors the differentiations in ``a`` amplify.

    ``make_run(grid)`` runs the recursion; ``measure(run) -> (errs, rel)`` gives the tails
    relative to each order's size, ``rel`` one per axis; ``compare(run, check, errs) ->
    (diffs, rel)`` the same from the two grids' differences.  Returns ``(run, errs, diffs)``.

    Raises
    ------
    kbm.errors.ResolutionError
        When the next grid is over ``budget`` (``(max P, max per angle..., max samples)``),
        or when refining ``a`` no longer lowers the tails (the floor of the rounding errors
        that each differentiation in ``a`` amplifies); ``what`` opens the message.
    """
    advice = "narrow the a-range, lower the order, smooth F, or loosen tol"
    previous = None
    while True:
        run = make_run(grid)
        errs, rel = measure(run)
        if max(rel) <= tol:
            diffs, rel = compare(run, make_run(check_grid(*grid)), errs)
            if max(rel) <= tol:
                return run, errs, diffs
        if previous is not None and grid[0] > previous[0][0] and 0.5 * previous[1] < rel[0] < 1e-6:
            low = min(rel[0], previous[1])
            raise ResolutionError(
                f"{what}: its Chebyshev tails in a stopped falling at {low:.1e} (P = "
                f"{previous[0][0]} -> {grid[0]} points), the floor of the rounding errors that "
                f"each differentiation in a amplifies; ask for tol >= {3 * low:.0e}, or {advice}")
        previous = (grid, rel[0])
        new = tuple((2 * g - 1 if i == 0 else 2 * g) if r > tol else g
                    for i, (g, r) in enumerate(zip(grid, rel)))
        if new == grid:
            new = (2 * grid[0] - 1, *grid[1:])
        if any(g > b for g, b in zip(new, budget)) or math.prod(new) > budget[-1]:
            names = ("a (Chebyshev)", "psi (Fourier)", "theta (Fourier)")
            where = names[max(range(len(rel)), key=lambda i: (rel[i], i))]
            sizes = ", ".join(f"{s} = {g} {n}" for s, g, n in
                              zip("PMN", grid, ("Chebyshev points", "phases", "forcing angles")))
            raise ResolutionError(
                f"{what} within the grid budget ({sizes}): the coefficient tails in {where} "
                f"are still {max(rel):.1e} of the size of the quantities; {advice}")
        grid = new


# ----------------------------------------------------------------------------- one run
@dataclass
class SampledRun:
    """The recursion on one grid, per order (list index ``n - 1``): ``A``, ``B`` arrays
    ``(S, P, J)`` of the coefficients of ``sigma**s exp(i j p phi)`` of ``A_n`` and of
    ``a B_n`` (smooth where ``B_n`` has a ``1/a``); without forcing the values ``(1, P, 1)``
    of ``A_n`` and ``B_n``.  ``U``: samples ``(S, P, M, N)`` of ``u_n``."""

    alg: SampledAlgebra
    A: list
    B: list
    U: list


def _slow(alg: SampledAlgebra, f: SampledSeries, times_a: bool) -> np.ndarray:
    """A rate as :attr:`SampledRun.A` holds it."""
    if alg.detuned:
        return alg.slow_coefficients(f, times_a=times_a)
    out = np.zeros((1, alg.P, 1))  # without forcing the rates are functions of a
    if f.values is not None:
        out[0, :, 0] = f.values[0, :, 0, 0]
    return out


def _run(tables: dict, w0: float, res: Resonance | None, lo: float, hi: float, order: int,
         P: int, M: int, N: int = 1) -> SampledRun:
    alg = SampledAlgebra(w0, res, lo, hi, P, M, N, cap=order - 1 if res is not None else 0)
    A, B, U = sampled_recursion(alg, tables, order)
    As = [_slow(alg, An, False) for An in A]
    Bs = [_slow(alg, Bn, alg.detuned) for Bn in B]
    Us = [np.zeros((1, P, M, N)) if u.values is None else u.values for u in U]
    if not all(np.all(np.isfinite(q)) for q in (*As, *Bs, *Us)):
        grid = f"P = {P}, M = {M}" + (f", N = {N}" if alg.detuned else "")
        raise ResolutionError(f"the numeric expansion of F = {sum(t.F for t in tables.values())} "
                              f"overflowed on a in [{lo:g}, {hi:g}] ({grid}); narrow the a-range")
    return SampledRun(alg, As, Bs, Us)


def _tail(v: np.ndarray) -> float:
    """The Chebyshev tail in ``a`` (axis 1) of a rate, real and imaginary parts."""
    if np.iscomplexobj(v):
        return max(chebyshev_tail(v.real, 1), chebyshev_tail(v.imag, 1))
    return chebyshev_tail(v, 1)


def measure(run: SampledRun):
    """Per order ``(scale, tail A_n, tail B_n, tail u_n in a, tail u_n per angle...)`` and
    the largest tail relative to its order's scale per axis (``a``, ``psi``[, ``theta``]).

    The scale of order ``n`` is the largest ``|A_n|``, ``|a B_n|``, ``|u_n|`` on the grid, or
    that of a lower order if larger (:func:`~kbm.backend.sampling.order_scale`).
    """
    out, floor, alg = [], 0.0, run.alg
    for An, Bn, Un in zip(run.A, run.B, run.U):
        aB = Bn if alg.detuned else alg.a[None, :, None] * Bn
        scale = floor = order_scale(An, aB, Un, floor)
        angles = (fourier_tail(Un, 2),) + ((fourier_tail(Un, 3),) if alg.detuned else ())
        out.append((scale, _tail(An), _tail(Bn), chebyshev_tail(Un, 1), *angles))
    rel = [max(max(e[1:4]) / (e[0] or 1) for e in out)]
    rel += [max(e[i] / (e[0] or 1) for e in out) for i in range(4, len(out[0]))]
    return out, rel


def differences(run: SampledRun, check: SampledRun, lo: float, hi: float) -> list[tuple]:
    """Per order: the largest differences of ``A_n``, ``B_n`` (the slow harmonics both grids
    hold) and, without forcing, of ``u_n`` (the sum of its harmonics' differences) between
    two grids, on ``[lo, hi]``."""
    W0, W1 = comparison_matrices(lo, hi, run.alg.lo, run.alg.hi, run.alg.P, check.alg.P)
    J0, J1 = run.A[0].shape[-1], check.A[0].shape[-1]
    J = min(J0, J1)
    s0, s1 = slice((J0 - J) // 2, (J0 + J) // 2), slice((J1 - J) // 2, (J1 + J) // 2)
    h = min(run.alg.M, check.alg.M) // 2

    def diff(fine, coarse) -> float:
        return float(np.max(np.abs(W1 @ fine[..., s1] - W0 @ coarse[..., s0])))

    def wave(U: np.ndarray, W: np.ndarray, M: int) -> np.ndarray:
        return W @ (np.fft.rfft(U[0, :, :, 0], axis=1) * (2.0 / M))

    out = []
    for n in range(len(run.A)):
        d = (diff(check.A[n], run.A[n]), diff(check.B[n], run.B[n]))
        if not run.alg.detuned:
            u1, u0 = wave(check.U[n], W1, check.alg.M), wave(run.U[n], W0, run.alg.M)
            du = np.sum(np.abs(u1[:, :h] - u0[:, :h]), axis=1) + np.sum(np.abs(u1[:, h:]), axis=1)
            d += (float(np.max(du)),)
        out.append(d)
    return out


# ----------------------------------------------------------------------------- the driver
def sampled_expansion(tables: dict[int, TaylorTable], w0: float, res: Resonance | None,
                      lo: float, hi: float, order: int, tol: float, angles: tuple[int, int],
                      budget: tuple[int, ...], what: str):
    """The resolved run of :func:`kbm.algebra.grid.sampled_recursion` for
    ``F = sum_i (mu sigma)**i F_i`` (``tables``: ``{i: TaylorTable of F_i}``) to ``order`` on
    ``a`` in ``[lo, hi]`` at the resonance ``res`` (``None``: no forcing angle).

    ``angles`` are the starting phases ``(M, N)`` of :func:`resolved_angles`, ``budget``
    ``(max P, max M[, max N], max samples)``, ``what`` the opening of a
    :class:`~kbm.errors.ResolutionError`.  Returns ``(run, errs, diffs)``: the
    :class:`SampledRun` of the final grid (on ``[lo, hi]`` :func:`~kbm.backend.sampling.widened`),
    the per-order tails of :func:`measure` and the differences from the check grid
    (:func:`differences`).  An ``F`` numpy cannot evaluate raises
    :class:`~kbm.errors.UnsupportedTermError`.
    """
    max_M, max_N = budget[1], (budget[2] if res is not None else 1)
    try:
        M, N = resolved_angles(tables, w0, lo, hi, tol, *angles, max_M, max_N)
    except (NameError, TypeError) as exc:  # a function numpy cannot evaluate
        F = sum(t.F for t in tables.values())
        raise UnsupportedTermError(f"F = {F} cannot be evaluated with numpy/scipy ({exc}); "
                                   "write F with elementary and special functions") from None
    if res is not None:  # room for the resonant harmonics of every order
        M, N = max(M, 4 * res.p * order + 8), max(N, 4 * res.q * order + 4)
        grid = (17, 2 ** math.ceil(math.log2(M)), 2 ** math.ceil(math.log2(N)))
    else:
        grid = (17, M)
    clo, chi = widened(lo, hi)

    def compare(run, check, errs):
        diffs = differences(run, check, lo, hi)
        rel = max(max(d) / (e[0] or 1) for d, e in zip(diffs, errs))
        if res is not None:  # no u difference: every axis on the rates' differences
            return diffs, [rel] * 3
        return diffs, [rel, max(d[2] / (e[0] or 1) for d, e in zip(diffs, errs))]

    return resolve(lambda g: _run(tables, w0, res, clo, chi, order, *g), measure, compare,
                   grid, tol, budget, what)
