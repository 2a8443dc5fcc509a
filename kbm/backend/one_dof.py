"""The numeric KBM backend: any smooth ``F``, any order, on an amplitude interval.

For ``x'' + omega0**2 x = mu F(x, x')`` with ``F`` built from any functions numpy and
scipy evaluate (``tanh(xdot/eps)``, ``exp(-x**2)``, ``1/(1 + x**2)``, a Stribeck
curve, ...) :func:`numeric_derive` runs the same recursion as :func:`kbm.derive`
(:func:`kbm.expansion.recursion.kbm_recursion`: same conventions, no first harmonic in any
``u_n``, ``A_n = -R_n^{sin 1}/(2 omega0)``, ``B_n = -R_n^{cos 1}/(2 omega0 a)``) on
*samples*: ``psi`` on ``M`` equispaced phases, ``a`` on ``P`` Chebyshev points of the
interval, ``F(x_0 + Dx, v_0 + Dv)`` by its Taylor series with the partial derivatives of
``F`` compiled (:mod:`kbm.algebra.smooth`; ``F`` itself is only ever *evaluated*).  It is
the case without a forcing angle of the one numeric backend of one degree of freedom
(:mod:`kbm.backend.sampled`), which refines ``P`` and ``M`` until the coefficient tails of
every ``A_n``, ``B_n``, ``u_n``, and their differences from a second grid half as fine
again, are below ``tol`` times the size of that order's quantities; those are the reported
error estimates.

The result holds callables ``A[n](a)``, ``B[n](a)``, ``u[n](a, psi)`` (vectorised,
defined on the interval only) and their error estimates.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..algebra.smooth import TaylorTable
from .sampled import SampledRun, sampled_expansion
from ..model.builtins import Oscillator
from .functions import AmplitudeFunction, ConstantFunction, WaveFunction
from .sampling import (IntervalExpansion, check_order, check_tol, numeric_model, parse_a_range,
                       wave_spectrum)

__all__ = ["numeric_derive", "NumericExpansion", "DEFAULT_TOL", "MAX_ORDER_NUMERIC"]

#: default tolerance, relative to the size of each order's quantities on the interval
DEFAULT_TOL = 1e-10
#: highest order of the numeric backend (partial derivatives of F up to order - 1)
MAX_ORDER_NUMERIC = 20
#: grid budget: Chebyshev points, phases, and their product
MAX_P, MAX_M, MAX_SAMPLES = 257, 2**15, 2**21


@dataclass(frozen=True, eq=False)
class NumericExpansion(IntervalExpansion):
    """The KBM expansion computed numerically on ``a_min <= a <= a_max``.

    ``model``, ``order``, ``a_range``, ``omega0``, ``tol``, ``resolution`` (``(P, M)``) and
    the error estimates ``A_error``, ``B_error``, ``u_error`` (indexed by order ``0..N``,
    entry 0 is 0) as in :class:`~kbm.backend.sampling.IntervalExpansion`.

    Attributes
    ----------
    A, B, u
        Callables indexed by order ``0..N``: ``A[n](a)``, ``B[n](a)``, ``u[n](a, psi)``
        (numpy broadcasting); ``A[0] = 0``, ``B[0] = omega0``, ``u[0] = a cos(psi)``.
    """

    A: tuple
    B: tuple
    u: tuple

    def table(self, a) -> dict:
        """``{"a": a, "A": [A_1(a), ...], "B": [B_1(a), ...]}`` as float arrays."""
        a = np.asarray(a, dtype=float)
        return {"a": a, "A": [self.A[n](a) for n in range(1, self.order + 1)],
                "B": [self.B[n](a) for n in range(1, self.order + 1)]}

    def to_json(self, a) -> dict:
        """The tables at the amplitudes ``a`` and the error estimates, with plain keys."""
        tab = self.table(a)
        return {**self._json_head(self.omega0, "numeric"),
                **self._interval_json(("chebyshev_points", "phases"), tab["a"], {}, tab["A"],
                                      tab["B"], skip=1)}


def numeric_derive(model: Oscillator | str, order: int, a_range, params: dict | None = None,
                   *, tol: float = DEFAULT_TOL) -> NumericExpansion:
    """KBM expansion of ``x'' + omega0**2 x = mu F(x, x')`` computed numerically, any smooth F.

    Parameters
    ----------
    model
        An :class:`~kbm.model.builtins.Oscillator`, a built-in model name, or a model from
        :func:`kbm.custom_model` (e.g. ``custom_model("-tanh(xdot/0.05)")``).
    order
        Highest order ``N`` (``1 <= N <=`` :data:`MAX_ORDER_NUMERIC`).
    a_range
        ``(a_min, a_max)`` or ``"a_min:a_max"`` with ``0 < a_min < a_max``: the
        amplitudes on which ``A_n``, ``B_n``, ``u_n`` are computed.
    params
        A value for every parameter of the model (built-in defaults fill the rest).
    tol
        Target error relative to the size of each order's quantities on the interval
        (or of a lower order's, when larger).

    Returns
    -------
    NumericExpansion
        Callables ``A[n]``, ``B[n]``, ``u[n]`` and their error estimates.

    Raises
    ------
    kbm.errors.ParameterError
        For a bad a-range or tol, a missing parameter value, or ``F`` not finite on
        the orbits of the a-range.
    kbm.errors.UnsupportedTermError
        For a non-smooth ``F`` (``sign``, ``Abs``, ...; the smooth replacement is named).
    kbm.errors.ResolutionError
        If the grid budget does not reach ``tol`` (the numbers are in the message).

    Examples
    --------
    >>> from kbm import custom_model
    >>> res = numeric_derive(custom_model("(1 - x**2)*xdot"), 2, (0.5, 3))
    >>> round(res.A[1](2.0), 12) + 0.0, round(res.B[2](2.0), 12)
    (0.0, -0.0625)
    """
    check_order(order, MAX_ORDER_NUMERIC)
    lo, hi = parse_a_range(a_range)
    tol = check_tol(tol)
    model, F, w0 = numeric_model(model, params)
    run, errs, diffs = sampled_expansion(
        {0: TaylorTable(F)}, w0, None, lo, hi, order, tol, (32, 1), (MAX_P, MAX_M, MAX_SAMPLES),
        f"the numeric expansion of F = {F} to order {order} on a in [{lo:g}, {hi:g}] "
        f"did not reach tol = {tol:.0e}")
    return _result(model, order, lo, hi, w0, tol, run, errs, diffs)


def _result(model, order, lo, hi, w0, tol, run: SampledRun, errs, diffs) -> NumericExpansion:
    M, domain = run.alg.M, (lo, hi, run.alg.lo, run.alg.hi)
    A = [ConstantFunction("A_0", 0.0)]
    B = [ConstantFunction("B_0", w0)]
    U = [ConstantFunction("u_0", 0.0, wave=True)]
    for n in range(1, order + 1):
        A.append(AmplitudeFunction(f"A_{n}", *domain, run.A[n - 1][0, :, 0].copy()))
        B.append(AmplitudeFunction(f"B_{n}", *domain, run.B[n - 1][0, :, 0].copy()))
        spec = wave_spectrum(run.U[n - 1][0, :, :, 0], M)
        spec[:, -1] = 0.0
        U.append(WaveFunction(f"u_{n}", *domain, spec.real.copy(), -spec.imag.copy()))
    # errs: (scale, tail A_n, tail B_n, tail u_n in a, in psi); diffs: (A_n, B_n, u_n)
    A_err = [0.0] + [max(e[1], d[0]) for e, d in zip(errs, diffs)]
    B_err = [0.0] + [max(e[2], d[1]) for e, d in zip(errs, diffs)]
    u_err = [0.0] + [max(e[3], e[4], d[2]) for e, d in zip(errs, diffs)]
    return NumericExpansion(model=model, order=order, a_range=(lo, hi), omega0=w0, tol=tol,
                            resolution=(run.alg.P, run.alg.M), A=tuple(A), B=tuple(B), u=tuple(U),
                            A_error=tuple(A_err), B_error=tuple(B_err), u_error=tuple(u_err))
