"""The Hermite and Chebyshev ladders of the escape rate (:func:`.escape.kramers_escape`),
one loop for both velocity bases: :func:`.\\_rungs.pair_escape` (Risken's pair, linear
damping) and :func:`.\\_orthonormal.nonlinear_escape` (orthonormal Hermite functions, every
damping) differ only in the solve of one rung and in the orthonormal basis's second
velocity scale, which they pass in.

The Hermite truncation grows by ``sqrt 2`` (``ladder(start, stop)``,
:func:`._problem.hermite_ladder`) until two successive rates agree to ``tol`` (and the
basis's check, where it has one); the rate is then recomputed on 1.2 times the intervals
(:func:`._model.grid_check`), and where it moves by more than ``tol`` the ladder runs
again there.  The last change is ``truncation_error``, the grid's ``chebyshev_error``, and
the change under the sharper sink one rung below the top ``sink_error``.

The budget bounds every solve (``kbm escape --fp-budget``): the first two rungs and the
first grid check are refused before anything is solved when they exceed it
(:class:`numerics.errors.BudgetError`, with their costs); a ladder stops at the last rung
that fits, and a grid that cannot grow within it ends the ladder with the change it last
measured as ``chebyshev_error``.
"""

from __future__ import annotations

import math

from ..errors import BudgetError
from ._model import grid_check

__all__ = ["hermite_chebyshev_ladder", "GROW", "budget_to_give"]

#: the position grid's growth per check (:func:`._model.grid_check`)
GROW = 1.2


def budget_to_give(cost: float) -> str:
    """``cost`` rounded up to two significant digits, as ``--fp-budget`` takes it (``1.07e6``
    gives ``"1.1e+06"``, never a budget below the cost)."""
    step = 10.0 ** (math.floor(math.log10(cost)) - 1)
    return f"{math.ceil(cost / step) * step:.2g}"


def _refuse(first: tuple, nc: int, finer: int, cost, budget: float) -> BudgetError:
    """The refusal of a ladder whose first two rungs or first grid check exceed the budget."""
    sizes = [(first[0], nc), (first[1], nc), (first[0], finer)]
    need = max(cost(n, m) for n, m in sizes)
    said = ", ".join(f"{n} x {m + 1} ({cost(n, m):.3g})" for n, m in sizes)
    return BudgetError(f"the escape rate's Kramers solves cost {need:.3g} at least (Hermite "
                       f"functions x Chebyshev points (cost): the first two rungs and the "
                       f"grid's check, {said}), above --fp-budget {budget:.3g}; raise "
                       f"--fp-budget to {budget_to_give(need)} or more")


def hermite_chebyshev_ladder(solve, ladder, fits, *, start: int, n_cheb: int, tol: float,
                             max_hermite: int, max_cheb: int, check=None, cost=None,
                             budget: float = math.inf) -> dict:
    """The escape rate's Hermite ladder on a growing position grid.

    Parameters
    ----------
    solve : callable
        ``solve(n, nc, sharp=1)``: the rate with ``n`` Hermite functions on ``nc`` position
        intervals, with the first sink (``sharp = 1``) or the sharper one (``2``).
    ladder : callable
        ``ladder(start, stop)``: the truncations (:func:`._problem.hermite_ladder`).
    fits : callable
        ``fits(n, nc)``: whether the solve is affordable (the factorisation's storage).
    start, n_cheb : int
        The first truncation and intervals.
    tol : float
        The relative change at which the ladders stop.
    max_hermite, max_cheb : int
        The ladders' tops.
    check : callable, optional
        ``check(n, nc, rate)``: the basis's own error of a converged rung (the orthonormal
        functions' change at another velocity scale); the ladder stops only where it is
        within ``tol`` too, and it is evaluated at the last rung where no rung passed.
    cost : callable, optional
        ``cost(n, nc)``: the solve's cost in the budget's units (``fits`` is ``cost <=
        budget``), for the refusal's message.
    budget : float
        The budget ``fits`` holds to (the refusal's message).

    Raises
    ------
    numerics.errors.BudgetError
        Before any solve, when the first two rungs or the first grid check do not fit.

    Returns
    -------
    dict
        ``rate``, ``sink_error``, ``truncation_error`` (the last change), ``hermite``,
        ``chebyshev`` (points), ``ladder`` (``(n, nc, rate)`` of every solve, each once),
        ``chebyshev_error`` and ``check_error`` (``check``'s value; ``nan`` without one).
    """
    nc = int(n_cheb)
    table: list = []
    extra = math.inf
    first = ladder(start, 2 * start)[:2]
    finer = 2 * int(round(GROW * nc / 2))
    if not (fits(first[0], nc) and fits(first[1], nc) and fits(first[0], finer)):
        raise _refuse(first, nc, finer, cost or (lambda n, m: math.nan), budget)
    cheb_err = math.nan
    while True:  # the ladder on a finer grid calls ladder() again
        steps = [n for n in ladder(start, max(int(max_hermite), 2 * start)) if fits(n, nc)]
        rates, extra = [], math.inf
        for n in steps:
            rates.append(solve(n, nc))
            if (n, nc, rates[-1]) not in table:
                table.append((n, nc, rates[-1]))
            if len(rates) > 1 and abs(rates[-1] - rates[-2]) <= tol * abs(rates[-1]):
                if check is None:
                    break
                extra = check(n, nc, rates[-1])
                if extra <= tol * abs(rates[-1]):
                    break
        if check is not None and not math.isfinite(extra):
            extra = check(steps[len(rates) - 1], nc, rates[-1])
        k = len(rates) - 1
        prev = max(k - 1, 0)
        finer = 2 * int(round(GROW * nc / 2))
        if not any(fits(n, finer) for n in steps[:k + 1]):
            break  # no check of this grid fits: the change last measured stands
        cheb_err, done, finer, k, prev = grid_check(steps, rates, nc, GROW, fits, solve,
                                                    table, tol, max_cheb)
        if done or not all(fits(n, finer) for n in ladder(steps[prev], 2 * steps[prev])[:2]):
            break  # converged, or the finer grid's first two rungs do not fit
        nc, start = finer, steps[prev]
    r_sharp = solve(steps[prev], nc, sharp=2)
    out = dict(rate=rates[-1], sink_error=abs(r_sharp - rates[prev]),
               truncation_error=abs(rates[-1] - rates[prev]), hermite=steps[k],
               chebyshev=nc + 1, ladder=tuple(table), chebyshev_error=cheb_err,
               check_error=extra if check is not None else math.nan)
    return dict(out, budget_note=_short_note(out, steps, k, nc, ladder, tol, max_hermite,
                                             fits, cost, budget))


def _short_note(out: dict, steps: list, k: int, nc: int, ladder, tol: float,
                max_hermite: int, fits, cost, budget: float) -> str:
    """The warning of a ladder that stopped with a measured change above ``tol`` of the
    rate (its budget or its top, not convergence): the changes and what the next solve
    needs; ``""`` where every change is within ``tol``.  CDC Delta = 3, kT = 0.2, mu = 0.002
    at the default budget stopped at 128 Hermite functions with the rate 2.34e-4, 5.8 times
    the spectral elements' 4.05e-5, and its truncation change 2.8e-4 stated but no warning
    (docs/noise-escape.rst)."""
    rate = abs(out["rate"])
    trunc = max(out["truncation_error"], out["check_error"]
                if math.isfinite(out["check_error"]) else 0.0)
    grid = out["chebyshev_error"]
    if trunc <= tol * rate and not grid > tol * rate:
        return ""
    more = [n for n in ladder(steps[k], 2 * steps[k] + 2) if n > steps[k]][:1]
    if trunc > tol * rate and more and more[0] <= max_hermite and not fits(more[0], nc):
        need = f"; the next rung, {more[0]} x {nc + 1}, costs {cost(more[0], nc):.3g}" \
            if cost is not None else ""
        why = f"--fp-budget {budget:.3g}{need}"
    else:
        why = "the ladders' tops (max_hermite, max_cheb) or the budget"
    return (f"the escape rate is not converged to {tol:g}: its last Hermite change is "
            f"{trunc / rate:.2g} and its grid change "
            f"{f'{grid / rate:.2g}' if math.isfinite(grid) else 'unmeasured'} of the rate at "
            f"{out['hermite']} Hermite functions x {nc + 1} position points, where the "
            f"ladders stopped at {why}; the rate is uncertain by about that much")
