"""The numeric forced KBM backend: any smooth ``F(x, x', theta)``, any order, on an
amplitude interval.

For ``x'' + omega0**2 x = mu F(x, x', theta)`` with ``F`` built from any functions numpy and
scipy evaluate — the washboard force ``sin(k x + theta)`` of a slider seen from its moving
stage, ``tanh``, ``exp(-x**2) cos(theta)`` — :func:`numeric_derive_forced` runs the same
recursion as the exact engine (:func:`kbm.expansion.recursion.kbm_recursion`: same conventions,
no resonant harmonic in any ``u_n``) on *samples* (:mod:`kbm.algebra.grid`):

- ``psi`` and ``theta`` on ``M x N`` equispaced angles (derivatives, the resonant part and
  ``u_n`` by the FFT);
- ``a`` on ``P`` Chebyshev points of the interval (derivatives spectrally);
- the detuning ``sigma`` exactly, as polynomial coefficients;
- ``F(x_0 + Dx, v_0 + Dv, theta)`` by its Taylor series with the partial derivatives taken
  symbolically and compiled (:class:`kbm.algebra.smooth.TaylorTable`).

A forcing frequency in ``F`` (a stage velocity ``v = nu/k``) is expanded exactly:
``nu = nu0 + mu sigma``.  The grid is refined adaptively by the one numeric backend of one
degree of freedom (:mod:`kbm.backend.sampled`, whose case without a forcing angle is
:mod:`kbm.backend.one_dof`) until the coefficient tails of every ``A_n``, ``B_n``, ``u_n``, and
their differences from a second grid half as fine again, are below ``tol`` times the size
of that order's quantities: those are the reported error estimates.

The result holds ``A_n(a, phi, sigma)``, ``B_n(a, phi, sigma)`` as Chebyshev series in
``a`` times Fourier series in ``phi`` times polynomials in ``sigma``, and gives the slow
flow at a value of ``mu`` as a :class:`~kbm.expansion.forced_result.SlowFlow` (the steady states,
folds and response curves of :mod:`kbm.slowflow.steady` then apply unchanged).
"""

from __future__ import annotations

import math
from math import comb

import sympy as sp

from ..algebra import chebyshev
from ..algebra.smooth import TaylorTable
from ..errors import ModelError, ParameterError
from .sampling import check_order, check_tol, parse_a_range, require_values
from ..symbols import x, xdot
from ..model.forced_builtins import get_forced_model
from ..expansion.forced import derive_forced
from .sampled import SampledRun, sampled_expansion
from ..model.forced import ForcedOscillator, Resonance, nu, theta
from .forced_result import NumericForcedExpansion, SlowSeries

__all__ = ["numeric_derive_forced", "forced_expansion", "DEFAULT_TOL", "MAX_ORDER_NUMERIC"]

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


def numeric_derive_forced(model: ForcedOscillator | str, order: int, a_range,
                          params: dict | None = None, *, resonance: Resonance | str | None = None,
                          tol: float = DEFAULT_TOL) -> NumericForcedExpansion:
    """Forced KBM expansion near a resonance computed numerically, any smooth ``F``.

    Parameters
    ----------
    model
        A :class:`~kbm.model.forced.ForcedOscillator` or a built-in forced model's name
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
        A hard forcing (write it as a weak one); an ``F`` numpy cannot evaluate
        (:class:`~kbm.errors.UnsupportedTermError`).
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
    run, errs, diffs = sampled_expansion(
        tables, w0, res, lo, hi, order, tol, (16, 8), (MAX_P, MAX_M, MAX_N, MAX_SAMPLES),
        f"the numeric forced expansion of F = {model.F} to order {order} on a in "
        f"[{lo:g}, {hi:g}] did not reach tol = {tol:.0e}")
    return _result(model, order, res, lo, hi, w0, tol, run, errs, diffs, used)


def _result(model, order, res, lo, hi, w0, tol, run: SampledRun, errs, diffs, used):
    alg = run.alg

    def series(v, over_a=False):
        coef = (chebyshev.coefficients(v.real, axis=1)
                + 1j * chebyshev.coefficients(v.imag, axis=1))
        return SlowSeries(coef, alg.lo, alg.hi, res.p, over_a=over_a)

    # one tail in a for every quantity of an order: the largest of A_n, a B_n, u_n
    tails = [max(e[1:4]) for e in errs]
    return NumericForcedExpansion(
        model=model, order=order, resonance=res, a_range=(lo, hi), omega0=w0, tol=tol,
        resolution=(alg.P, alg.M, alg.N), A=tuple(series(An) for An in run.A),
        B=tuple(series(aBn, over_a=True) for aBn in run.B),
        A_error=tuple(max(t, d[0]) for t, d in zip(tails, diffs)),
        B_error=tuple(max(t, d[1]) / lo for t, d in zip(tails, diffs)),
        u_error=tuple(max(t, *e[4:]) for t, e in zip(tails, errs)), parameters=used)


def forced_expansion(model: ForcedOscillator | str, order: int, values: dict | None = None, *,
                     resonance: Resonance | str | None = None, a_range=None,
                     tol: float = DEFAULT_TOL):
    """The forced expansion by the engine that applies: exact
    (:func:`~kbm.expansion.forced.derive_forced`, symbolic in the parameters) for ``F`` polynomial
    in ``x``, ``xdot``; numeric (:func:`numeric_derive_forced` at ``values``, on ``a_range``)
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
