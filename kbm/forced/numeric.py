"""The numeric forced KBM backend: any smooth ``F(x, x', theta)``, any order, on an
amplitude interval.

For ``x'' + omega0**2 x = mu F(x, x', theta)`` with ``F`` built from any functions numpy and
scipy evaluate — the washboard force ``sin(k x + theta)`` of a slider seen from its moving
stage, ``tanh``, ``exp(-x**2) cos(theta)`` — :func:`numeric_derive_forced` runs the same
recursion as the exact engine (:func:`kbm.recursion.kbm_recursion`: same conventions,
no resonant harmonic in any ``u_n``) on *samples* (:mod:`kbm.forced.grid`):

- ``psi`` and ``theta`` on ``M x N`` equispaced angles (derivatives, the resonant part and
  ``u_n`` by the FFT);
- ``a`` on ``P`` Chebyshev points of the interval (derivatives spectrally);
- the detuning ``sigma`` exactly, as polynomial coefficients;
- ``F(x_0 + Dx, v_0 + Dv, theta)`` by its Taylor series with the partial derivatives taken
  symbolically and compiled (:class:`kbm.algebra.smooth.TaylorTable`).

A forcing frequency in ``F`` (a stage velocity ``v = nu/k``) is expanded exactly:
``nu = nu0 + mu sigma``.  The resolution is adaptive, by the one driver of the grid
backends (:func:`resolved_angles`, :func:`resolve`; the autonomous :mod:`kbm.numeric_kbm`
is its case without a forcing angle): ``M`` and ``N`` start where the Fourier coefficients
of ``F`` along the unperturbed orbits have fallen below the tolerance, and ``P``, ``M``,
``N`` are refined until the coefficient tails of every ``A_n``, ``B_n``, ``u_n`` are below
``tol`` times the size of that order's quantities; a second grid half as fine again then
measures the error that the tails cannot (rounding amplified by the differentiations in
``a``).  Those are the reported error estimates; a budget that does not suffice, or tails
that stop falling as ``a`` is refined, raise :class:`~kbm.errors.ResolutionError` with the
numbers.

The result holds ``A_n(a, phi, sigma)``, ``B_n(a, phi, sigma)`` as Chebyshev series in
``a`` times Fourier series in ``phi`` times polynomials in ``sigma``, and gives the slow
flow at a value of ``mu`` as a :class:`~kbm.forced.result.SlowFlow` (the steady states,
folds and response curves of :mod:`kbm.forced.steady` then apply unchanged).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from math import comb

import numpy as np
import sympy as sp

from ..algebra import chebyshev
from ..algebra.smooth import TaylorTable
from ..errors import ModelError, ParameterError, ResolutionError
from ..sampling import (check_bounded, check_grid, check_order, check_tol, chebyshev_tail,
                        comparison_matrices, fourier_tail, order_scale, parse_a_range,
                        require_values, widened)
from ..symbols import x, xdot
from .builtins import get_forced_model
from .engine import derive_forced
from .grid import SampledAlgebra, sampled_recursion
from .model import ForcedOscillator, Resonance, nu, theta
from .numeric_result import NumericForcedExpansion, SlowSeries

__all__ = ["numeric_derive_forced", "forced_expansion", "NumericForcedExpansion", "SlowSeries",
           "resolved_angles", "resolve", "DEFAULT_TOL", "MAX_ORDER_NUMERIC"]

#: default tolerance, relative to the size of each order's quantities on the interval
DEFAULT_TOL = 1e-9
#: highest order of the numeric forced backend
MAX_ORDER_NUMERIC = 8
#: grid budget: Chebyshev points, phases in psi and in theta, and samples in all
MAX_P, MAX_M, MAX_N, MAX_SAMPLES = 129, 1024, 256, 2**21


# ----------------------------------------------------------------------------- the input
def _numeric_model(model, params, resonance):
    if isinstance(model, str):
        model = get_forced_model(model)
    vals = model.resolve(params or {})
    vals.pop("mu", None)
    vals.pop("sigma", None)
    if vals:
        model = model.substitute(vals)
    if model.hard != 0:
        raise ModelError(f"the numeric forced backend does not take a hard forcing (K = "
                         f"{model.hard}); write it as a weak forcing mu*h*cos(theta) in F")
    require_values(model, model.F, {x, xdot, theta, nu}, "the numeric forced backend")
    w0 = float(model.omega0)
    if not (math.isfinite(w0) and w0 > 0):
        raise ParameterError(f"omega0 must be a positive number, got {model.omega0}")
    res = Resonance.parse(resonance) if resonance is not None else model.resonance
    return model, res, w0, {k: float(v) for k, v in vals.items()}


def _parts(F: sp.Expr, nu0: float) -> dict[int, sp.Expr]:
    """``F`` with ``nu = nu0 + mu sigma``: ``{i: F_i}`` with the term ``(mu sigma)**i F_i``."""
    if nu not in F.free_symbols:
        return {0: F}
    poly = sp.Poly(F, nu)
    out: dict[int, sp.Expr] = {}
    for (r,), c in poly.terms():
        for i in range(r + 1):
            out[i] = out.get(i, 0) + comb(r, i) * sp.Float(nu0) ** (r - i) * c
    return {i: sp.expand(e) for i, e in sorted(out.items()) if e != 0}


# ----------------------------------------------------------------------------- resolution
def resolved_angles(tables: dict, w0: float, lo: float, hi: float, tol: float, M: int, N: int,
                    max_M: int, max_N: int) -> tuple[int, int]:
    """The phases ``(M, N)`` (``psi``, ``theta``; ``N = 1`` without forcing), doubled from
    the given ones, at which ``F`` along the unperturbed orbits of five amplitudes of
    ``[lo, hi]`` is resolved: its Fourier tails below ``tol/100`` of its size.

    Raises
    ------
    kbm.errors.ParameterError
        ``F`` not finite, or not bounded (:func:`~kbm.sampling.check_bounded`), on the orbits.
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


def resolve(make_run, measure, compare, grid: tuple[int, ...], tol: float,
            budget: tuple[int, ...], what: str):
    """The adaptive loop of the grid backends: runs on ``grid = (P, M[, N])`` refined (``P``
    to ``2 P - 1``, an angle doubled) while a tail exceeds ``tol``, then checked against a
    second grid half as fine again (:func:`~kbm.sampling.check_grid`), which measures the
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


@dataclass
class _Run:
    alg: SampledAlgebra
    A: list
    aB: list
    U: list


def _run(tables, w0, res, lo, hi, P, M, N, order) -> _Run:
    alg = SampledAlgebra(w0, res, lo, hi, P, M, N, cap=order - 1)
    A, B, U = sampled_recursion(alg, tables, order)  # N = 1 with the forcing angle
    # A_n and a B_n as slow spectra; B_n = (a B_n)/a is formed in the result
    As = [alg.slow_coefficients(An) for An in A]
    aBs = [alg.slow_coefficients(Bn, times_a=True) for Bn in B]
    Us = [np.zeros((1, P, M, N)) if u.values is None else u.values for u in U]
    if not all(np.all(np.isfinite(q)) for q in (*As, *aBs, *Us)):
        raise ResolutionError(f"the numeric forced expansion overflowed on a in [{lo:g}, "
                              f"{hi:g}] (P = {P}, M = {M}, N = {N}); narrow the a-range")
    return _Run(alg, As, aBs, Us)


def _errors(run: _Run):
    """Per order: the scale and the tails (Chebyshev in ``a``, Fourier in ``psi`` and
    ``theta``) of ``A_n``, ``a B_n``, ``u_n``; and the largest relative tail per axis."""
    out, floor = [], 0.0
    for An, aBn, Un in zip(run.A, run.aB, run.U):
        scale = floor = order_scale(An, aBn, Un, floor)
        ta = max(chebyshev_tail(v, 1) for v in (An.real, An.imag, aBn.real, aBn.imag, Un))
        out.append((scale, ta, fourier_tail(Un, 2), fourier_tail(Un, 3)))
    return out, [max(e[i] / (e[0] or 1) for e in out) for i in (1, 2, 3)]


def _differences(run: _Run, check: _Run, lo: float, hi: float) -> list[tuple[float, float]]:
    """Per order: the largest differences of ``A_n`` and ``a B_n`` between two grids, on
    ``[lo, hi]`` (the slow harmonics both grids hold)."""
    W0, W1 = comparison_matrices(lo, hi, run.alg.lo, run.alg.hi, run.alg.P, check.alg.P)
    J0, J1 = run.A[0].shape[-1], check.A[0].shape[-1]
    J = min(J0, J1)
    s0, s1 = slice((J0 - J) // 2, (J0 + J) // 2), slice((J1 - J) // 2, (J1 + J) // 2)

    def diff(fine, coarse) -> float:
        return float(np.max(np.abs(np.einsum("nP,sPj->snj", W1, fine[..., s1])
                                   - np.einsum("nP,sPj->snj", W0, coarse[..., s0]))))

    return [(diff(check.A[n], run.A[n]), diff(check.aB[n], run.aB[n]))
            for n in range(len(run.A))]


def numeric_derive_forced(model: ForcedOscillator | str, order: int, a_range,
                          params: dict | None = None, *, resonance: Resonance | str | None = None,
                          tol: float = DEFAULT_TOL) -> NumericForcedExpansion:
    """Forced KBM expansion near a resonance computed numerically, any smooth ``F``.

    Parameters
    ----------
    model
        A :class:`~kbm.forced.model.ForcedOscillator` or a built-in forced model's name
        (e.g. ``"slider"``, whose ``F`` holds ``sin(k x + theta)``).
    order
        Highest order ``N`` (``1 <= N <=`` :data:`MAX_ORDER_NUMERIC`).
    a_range
        ``(a_min, a_max)`` or ``"a_min:a_max"``, ``0 < a_min < a_max``.
    params
        A value for every parameter of the model (defaults fill the rest; ``mu`` and
        ``sigma`` are not needed and are ignored).
    resonance
        The declared resonance ``p/q`` (default the model's).
    tol
        Target error relative to the size of each order's quantities.

    Returns
    -------
    NumericForcedExpansion

    Raises
    ------
    kbm.errors.ParameterError
        A bad a-range or tol, a parameter without a value, ``F`` not finite.
    kbm.errors.ModelError
        A hard forcing (write it as a weak one).
    kbm.errors.ResolutionError
        If the grid budget does not reach ``tol`` (the numbers in the message).

    Examples
    --------
    >>> r = numeric_derive_forced("duffing-forced", 1, (0.5, 2),
    ...                           {"zeta": 0.1, "alpha": 1, "h": 1})
    >>> round(float(r.A[0](1.0, 0.0, 0.0)), 10)     # A_1 = -zeta a - h sin(phi)/2
    -0.1
    """
    check_order(order, MAX_ORDER_NUMERIC, "numeric forced backend")
    lo, hi = parse_a_range(a_range)
    tol = check_tol(tol, 1e-14)
    model, res, w0, used = _numeric_model(model, params, resonance)
    nu0 = w0 * res.p / res.q
    parts = _parts(sp.expand(model.F), nu0)
    tables = {i: TaylorTable(Fi, extra=(theta,)) for i, Fi in parts.items()}
    try:
        M, N = resolved_angles(tables, w0, lo, hi, tol, 16, 8, MAX_M, MAX_N)
    except (NameError, TypeError) as exc:
        raise ParameterError(f"F = {model.F} cannot be evaluated with numpy/scipy ({exc})") \
            from None
    M, N = max(M, 4 * res.p * order + 8), max(N, 4 * res.q * order + 4)
    M, N = 2 ** math.ceil(math.log2(M)), 2 ** math.ceil(math.log2(N))
    clo, chi = widened(lo, hi)

    def compare(run, check, errs):
        diffs = _differences(run, check, lo, hi)
        return diffs, [max(max(d) / (e[0] or 1) for d, e in zip(diffs, errs))] * 3

    run, errs, diffs = resolve(
        lambda grid: _run(tables, w0, res, clo, chi, *grid, order), _errors, compare,
        (17, M, N), tol, (MAX_P, MAX_M, MAX_N, MAX_SAMPLES),
        f"the numeric forced expansion of F = {model.F} to order {order} on a in "
        f"[{lo:g}, {hi:g}] did not reach tol = {tol:.0e}")
    return _result(model, order, res, lo, hi, w0, tol, run, errs, diffs, used)


def _result(model, order, res, lo, hi, w0, tol, run: _Run, errs, diffs, used):
    alg = run.alg
    A, B = [], []
    def coefficients(v):
        return (chebyshev.coefficients(v.real, axis=1)
                + 1j * chebyshev.coefficients(v.imag, axis=1))

    for An, aBn in zip(run.A, run.aB):
        A.append(SlowSeries(coefficients(An), alg.lo, alg.hi, res.p))
        B.append(SlowSeries(coefficients(aBn), alg.lo, alg.hi, res.p, over_a=True))
    A_err = tuple(max(e[1], d[0]) for e, d in zip(errs, diffs))
    B_err = tuple(max(e[1], d[1]) / lo for e, d in zip(errs, diffs))
    u_err = tuple(max(e[1], e[2], e[3]) for e in errs)
    return NumericForcedExpansion(model=model, order=order, resonance=res, a_range=(lo, hi),
                                  omega0=w0, tol=tol, resolution=(alg.P, alg.M, alg.N),
                                  A=tuple(A), B=tuple(B), A_error=A_err, B_error=B_err,
                                  u_error=u_err, parameters=used)


def forced_expansion(model: ForcedOscillator | str, order: int, values: dict | None = None, *,
                     resonance: Resonance | str | None = None, a_range=None,
                     tol: float = DEFAULT_TOL):
    """The forced expansion by the engine that applies: exact
    (:func:`~kbm.forced.derive_forced`, symbolic in the parameters) for ``F`` polynomial in
    ``x``, ``xdot``; numeric (:func:`numeric_derive_forced` at ``values``, on ``a_range``)
    otherwise.  Either result has ``model``, ``resonance``, ``order`` and
    ``slow_flow(values, order)``.

    Raises
    ------
    kbm.errors.ParameterError
        For a non-polynomial ``F`` without an ``a_range``.
    """
    if isinstance(model, str):
        model = get_forced_model(model)
    if model.is_polynomial:
        return derive_forced(model, order, resonance=resonance)
    if a_range is None:
        raise ParameterError(f"F of {model.name!r} is not polynomial in x, xdot: the numeric "
                             "forced backend computes the expansion on an amplitude interval; "
                             "give a_range=(a_min, a_max) (--a-range AMIN:AMAX)")
    vals = {k: v for k, v in (values or {}).items() if k not in ("mu", "sigma")}
    return numeric_derive_forced(model, order, a_range, vals, resonance=resonance, tol=tol)
