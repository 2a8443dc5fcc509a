"""What the sampled (numeric) KBM backends share: their input and their resolution measure.

- the amplitude interval ``a_min:a_max`` (:func:`parse_a_range`), the model with every
  parameter a number (:func:`numeric_model`), the order and the tolerance
  (:func:`check_order`, :func:`check_tol`);
- the coefficient tails that say whether a grid resolves a quantity: the largest Fourier
  coefficient (in an angle) and the largest Chebyshev coefficient (in the amplitude) in the
  top quarter (:func:`fourier_tail`, :func:`chebyshev_tail`);
- the resolution loops' common steps: the Chebyshev interval reaching past the one asked for
  (:func:`widened`), the second grid half as fine again that measures what the tails cannot
  (:func:`check_grid`) with the matrices that compare the two (:func:`comparison_matrices`),
  and the refusal of an ``F`` whose samples grow without bound as the
  angles are refined (:func:`check_bounded`);
- the sampled backends' common run and read-out: the recursion over a sampled
  algebra read at its amplitudes (:func:`sampled_orders`), the size of each order
  (:func:`order_scale`), the harmonics of ``u_n`` (:func:`wave_spectrum`) and their result's
  common fields (:class:`SampledExpansion`, :class:`IntervalExpansion`).

Used by the numeric backend :mod:`kbm.backend.sampled` (and its cases :mod:`kbm.backend.one_dof`,
:mod:`kbm.backend.forced`) and by :mod:`kbm.backend.pointwise`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import sympy as sp

from ..algebra import chebyshev
from ..errors import OrderError, ParameterError, UnsupportedTermError
from ..algebra.lazy_series import Builder
from ..model.builtins import Oscillator, get_model
from ..expansion.recursion import kbm_recursion
from ..model.smooth_terms import non_smooth_message, non_smooth_term
from ..symbols import x, xdot

__all__ = ["parse_a_range", "numeric_model", "require_values", "check_order", "check_tol", "fourier_tail",
           "chebyshev_tail", "widened", "check_grid", "check_bounded", "comparison_matrices", "MARGIN",
           "sampled_orders", "order_scale", "wave_spectrum", "SampledExpansion",
           "IntervalExpansion"]

#: the top fraction of the coefficients read as the tail
_TAIL = 0.25
#: how far (a fraction of its width) the Chebyshev grid reaches past each end of the interval
MARGIN = 0.1


def parse_a_range(a_range) -> tuple[float, float]:
    """``(a_min, a_max)`` from a pair or a string ``"a_min:a_max"``, checked.

    Raises
    ------
    kbm.errors.ParameterError
        Unless ``0 < a_min < a_max`` are finite numbers.
    """
    if isinstance(a_range, str):
        parts = a_range.split(":")
        if len(parts) != 2:
            raise ParameterError(f"the a-range must be 'AMIN:AMAX' (e.g. 0.1:4), got "
                                 f"{a_range!r}")
    else:
        parts = list(a_range) if isinstance(a_range, (tuple, list)) else [a_range]
        if len(parts) != 2:
            raise ParameterError(f"a_range must be a pair (a_min, a_max), got {a_range!r}")
    try:
        lo, hi = (float(p) for p in parts)
    except (TypeError, ValueError):
        raise ParameterError(f"the a-range must be two numbers, got {a_range!r}") from None
    if not (math.isfinite(lo) and math.isfinite(hi)):
        raise ParameterError(f"the a-range must be finite, got {lo:g}:{hi:g}")
    if lo <= 0:
        raise ParameterError(f"the a-range must lie in a > 0 (a = 0 is the fixed point, "
                             f"where B_n has a 1/a and the phase is undefined), got "
                             f"{lo:g}:{hi:g}; start it above 0, e.g. 0.05:{hi:g}")
    if hi <= lo:
        raise ParameterError(f"the a-range needs a_min < a_max, got {lo:g}:{hi:g}")
    return lo, hi


def numeric_model(model: Oscillator | str, params) -> tuple[Oscillator, sp.Expr, float]:
    """The model with every parameter a number, ``F`` and ``omega0`` (a float).

    Raises
    ------
    kbm.errors.ParameterError
        Naming the parameters without a value.
    kbm.errors.UnsupportedTermError
        For a non-smooth term of ``F`` (naming a smooth replacement).
    kbm.errors.NonAutonomousError
        If ``F`` depends on ``t``.
    """
    if isinstance(model, str):
        model = get_model(model)
    vals = model.resolve(params or {})
    vals.pop("mu", None)
    if vals:
        model = model.substitute(vals)
    model.require_autonomous("the KBM averaging")
    F = model.F
    bad = non_smooth_term(F)
    if bad is not None:
        raise UnsupportedTermError(non_smooth_message(bad))
    require_values(model, F, {x, xdot}, "the evaluated expansion")
    return model, F, float(model.omega0)


def require_values(model, F: sp.Expr, variables: set, backend: str) -> None:
    """Refuse a model whose ``F`` or ``omega0`` holds a symbol other than ``variables``.

    Raises
    ------
    kbm.errors.ParameterError
        Naming the parameters without a value (``backend`` says who needs them).
    """
    missing = sorted(s.name for s in (F.free_symbols | model.omega0.free_symbols) - variables)
    if missing:
        raise ParameterError(
            f"{backend} needs a value for every parameter of {model.name!r}; "
            f"missing: {', '.join(missing)} (e.g. params={{{missing[0]!r}: 1}})")


def check_order(order, limit: int, backend: str | None = "numeric backend") -> None:
    """Refuse an order that is not an integer in ``1..limit`` (:class:`OrderError`; the
    message names ``backend`` unless it is ``None``)."""
    if not isinstance(order, int) or isinstance(order, bool) or order < 1:
        raise OrderError(f"the order must be an integer >= 1, got {order!r}")
    if order > limit:
        of = f" of the {backend}" if backend else ""
        raise OrderError(f"order {order} is above the limit {limit}{of}; ask for order <= "
                         f"{limit}")


def check_tol(tol, smallest: float = 1e-15) -> float:
    """``tol`` as a float in ``[smallest, 1)`` (else :class:`ParameterError`)."""
    try:
        tol = float(tol)
    except (TypeError, ValueError):
        raise ParameterError(f"tol must be a number, got {tol!r}") from None
    if not smallest <= tol < 1:
        raise ParameterError(f"tol must be between {smallest:g} and 1 (relative), got "
                             f"{tol:g}")
    return tol


# ----------------------------------------------------------------------------- resolution
def fourier_tail(values: np.ndarray, axis: int = 1) -> float:
    """Largest |Fourier coefficient| in the top quarter of the harmonics along ``axis``."""
    n = values.shape[axis]
    spec = np.abs(np.fft.rfft(values, axis=axis)) * (2.0 / n)
    top = np.take(spec, np.arange(int((1 - _TAIL) * (n // 2)), n // 2 + 1), axis=axis)
    return float(np.max(top)) if top.size else 0.0


def chebyshev_tail(values: np.ndarray, axis: int = 0) -> float:
    """Largest |Chebyshev coefficient| in the top quarter of the degrees along ``axis``."""
    c = np.abs(chebyshev.coefficients(values, axis=axis))
    n = c.shape[axis]
    return float(np.max(np.take(c, np.arange(int((1 - _TAIL) * (n - 1)), n), axis=axis)))


def widened(lo: float, hi: float) -> tuple[float, float]:
    """The Chebyshev interval for ``[lo, hi]``: :data:`MARGIN` of its width past each end
    (at most a quarter of ``lo`` below it): the ends of a Chebyshev grid are where
    differentiation amplifies errors most."""
    return lo - min(MARGIN * (hi - lo), 0.25 * lo), hi + MARGIN * (hi - lo)


def check_grid(P: int, *angles: int) -> tuple[int, ...]:
    """The second grid, half as fine again, that measures the rounding errors the
    differentiations in ``a`` amplify: ``P + (P - 1)/2`` Chebyshev points (odd stays odd)
    and ``M + M/2`` points per angle."""
    return (P + (P - 1) // 2, *(M + M // 2 for M in angles))


def comparison_matrices(lo: float, hi: float, clo: float, chi: float, P0: int, P1: int
                        ) -> tuple[np.ndarray, np.ndarray]:
    """The barycentric interpolation matrices of two Chebyshev grids of ``[clo, chi]``
    (``P0`` and ``P1`` points) at ``2 P0 + 1`` equispaced amplitudes of ``[lo, hi]``, where
    the grid and its check grid are compared."""
    at = np.linspace(lo, hi, 2 * P0 + 1)
    return (chebyshev.barycentric_matrix(clo, chi, P0, at),
            chebyshev.barycentric_matrix(clo, chi, P1, at))


def check_bounded(F, f: np.ndarray, first: float, exhausted: bool, where: str,
                  refined: str = "") -> None:
    """Refuse an ``F`` whose samples ``f`` grow without bound as the angles are refined.

    On the last grid (``exhausted``), a largest sample ten times that of the first grid
    (``first``), or ``1e8`` times the median, is the sign of a pole of ``F`` on the orbits.

    Raises
    ------
    kbm.errors.ParameterError
        Saying ``where`` (the orbits of the a-range, or the orbit at ``a_max``).
    """
    scale = float(np.max(np.abs(f))) or 1.0
    if exhausted and (scale > 10 * first
                      or scale > 1e8 * (float(np.median(np.abs(f))) or 1.0)):
        raise ParameterError(
            f"F = {F} is not bounded {where}: its largest sampled value grows from "
            f"{first:.3g} to {scale:.3g} as the phases are refined{refined}, as at a pole of F "
            "on |x| <= a_max, |xdot| <= omega0 a_max; shrink the a-range or change F")


# ----------------------------------------------------------------------------- one angle
def sampled_orders(alg, F: sp.Expr, order: int, builder=Builder
                   ) -> tuple[list[np.ndarray], list[np.ndarray], list[np.ndarray]]:
    """:func:`~kbm.expansion.recursion.kbm_recursion` for ``x'' + omega0**2 x = mu F(x, x')`` over
    a sampled algebra of one unforced mode at given amplitudes (the jets of
    :meth:`kbm.algebra.coupled_jets.JetAlgebra.one_mode`), read there: the arrays of
    ``A_1..A_N``, ``B_1..B_N`` (amplitudes) and ``u_1..u_N`` (amplitudes x phases, zeros
    where ``u_n`` vanishes).  ``builder(alg, X, V).build(F)`` makes the lazy series of ``F``
    (:class:`~kbm.algebra.lazy_series.Builder`)."""
    def rhs(X, V):
        return [[(0, builder(alg, X[0], V[0]).build(F))]]

    (A,), (B,), (U,) = kbm_recursion(alg, rhs, order)
    return ([alg.at_amplitudes(c)[..., 0] for c in A], [alg.at_amplitudes(c)[..., 0] for c in B],
            [alg.at_amplitudes(u) for u in U])


def order_scale(A: np.ndarray, aB: np.ndarray, U: np.ndarray, floor: float = 0.0) -> float:
    """The size of one order: the largest ``|A_n|``, ``|a B_n|``, ``|u_n|`` (or ``floor``,
    that of the orders below, when larger: an order whose quantities all vanish holds
    rounding noise only)."""
    return float(max(np.max(np.abs(A)), np.max(np.abs(aB)), np.max(np.abs(U)), floor))


def wave_spectrum(U: np.ndarray, M: int) -> np.ndarray:
    """The harmonics of samples on ``M`` phases (last axis): ``c_m - i s_m`` for
    ``u = sum_m c_m cos(m psi) + s_m sin(m psi)``, ``m = 0..M/2`` (the Nyquist mode kept as
    sampled; callers drop it)."""
    spec = np.fft.rfft(U, axis=-1) * (2.0 / M)
    spec[..., 0] *= 0.5
    return spec


@dataclass(frozen=True, eq=False)
class SampledExpansion:
    """What every one-degree-of-freedom sampled expansion holds first.

    Attributes
    ----------
    model
        The oscillator (forced or not) with its parameter values substituted.
    order
        The highest order ``N``.
    """

    model: Oscillator
    order: int

    def _orders(self) -> list[str]:
        return [str(n) for n in range(1, self.order + 1)]

    def _json_head(self, omega0, method: str) -> dict:
        """The leading keys of ``to_json``: model, F, omega0, order, method."""
        return {"model": self.model.name, "F": sp.sstr(self.model.F, order="lex"),
                "omega0": omega0, "order": self.order, "method": method}


@dataclass(frozen=True, eq=False)
class IntervalExpansion(SampledExpansion):
    """A sampled expansion computed on an amplitude interval (Chebyshev grids).

    Attributes
    ----------
    a_range
        ``(a_min, a_max)``.
    omega0
        The linear frequency.
    tol
        The tolerance asked for (relative to the size of each order's quantities).
    resolution
        ``(P, M[, N])``: Chebyshev points in ``a``, phases in ``psi`` (and in ``theta``) of
        the final grid.
    A_error, B_error, u_error
        Estimated absolute errors per order (largest over the interval): the larger of the
        coefficient tails of the final grid and the difference from a second grid half as
        fine again.
    """

    a_range: tuple[float, float]
    omega0: float
    tol: float
    resolution: tuple[int, ...]
    A_error: tuple[float, ...]
    B_error: tuple[float, ...]
    u_error: tuple[float, ...]

    def _interval_json(self, grid: tuple[str, ...], a, at: dict, A, B, skip: int = 0) -> dict:
        """The keys of ``to_json`` after the head: the interval, tolerance and resolution
        (its entries named ``grid``), the amplitudes ``a``, the point ``at`` in the other
        slow variables, the columns ``A``, ``B`` of orders ``1..N`` and the error estimates
        (from entry ``skip`` on)."""
        orders = self._orders()
        return {"a_range": list(self.a_range), "tol": self.tol,
                "resolution": dict(zip(grid, self.resolution)),
                "a": [float(v) for v in a], **at,
                "A": {k: [float(v) for v in col] for k, col in zip(orders, A)},
                "B": {k: [float(v) for v in col] for k, col in zip(orders, B)},
                "error": {q: dict(zip(orders, e[skip:])) for q, e in
                          (("A", self.A_error), ("B", self.B_error), ("u", self.u_error))}}
