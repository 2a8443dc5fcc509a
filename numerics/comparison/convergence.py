"""Convergence of KBM predictions with the small parameter: fitted log-log slopes vs theory.

For ``eps = mu`` along a geometric sequence (the other parameters fixed in the
model's *scaled* form, e.g. ``delta = Delta/mu`` fixed for sedf, so that the
expansion is a genuine power series in ``mu``), :func:`convergence_study`
compares each KBM order with the true cycle and fits the slope of
``log|error|`` against ``log eps``; :func:`predicted_orders` states the order
the theory predicts.

Predicted orders (order ``N`` = ``A_1..A_N``, ``B_1..B_N``, ``u_1..u_N`` kept)
-----------------------------------------------------------------------------
Write ``a`` for the true first-harmonic amplitude; because no ``u_n`` holds a
first harmonic, the *full* series root of ``sum_n eps**n A_n(a) = 0`` is ``a``.

- amplitude: the order-``N`` root solves ``A_1 + eps A_2 + ... + eps**(N-1) A_N = 0``;
  the first omitted term ``eps**N A_{N+1}`` moves the root by ``O(eps**N)``
  (``A_1'(a_0) != 0``, a hyperbolic cycle).  Order ``N``.
- frequency: ``omega_N - omega = eps B_1'(a) (a_N - a) - eps**(N+1) B_{N+1} + ...``:
  order ``N + 1``.
- maximum of ``x``: the amplitude error ``O(eps**N)`` enters at first order, the
  omitted ``eps**(N+1) u_{N+1}`` is smaller: order ``N``.
- third harmonic (absolute): ``eps [u_1]_3`` at ``a_N`` plus ``eps**(N+1) [u_{N+1}]_3``
  omitted: order ``N + 1``.
- Floquet exponent ``L = log m`` (fitted instead of the multiplier ``m = exp(L)``,
  whose factor ``exp(-c eps)`` bends the log-log line at moderate ``eps``): the exponent ``T A'(a*)`` is ``O(eps)`` and the full series
  gives the exact exponent; ``A'`` at the shifted root (``eps A_1'' (a_N - a)``) and the
  omitted ``eps**(N+1) A_{N+1}'`` are ``O(eps**(N+1))``: order ``N + 1``.
- dissipation over the reconstructed orbit: the order-``N`` orbit satisfies the
  equation up to a residual ``r_N = eps**(N+1) R_{N+1} + ...``, and the energy balance
  gives ``Gamma_N = int x' r_N dt``, whose leading term is ``prop. to a A_{N+1}(a)``:
  order ``N + 1`` (while the true ``Gamma`` is 0).

Time-reversal-symmetric models (``F(x, -x') = -F(x, x')``: van der Pol, Rayleigh)
satisfy ``x(t; -eps) = x(-t; eps)``: ``A_n = 0`` for even ``n``, ``B_n = 0`` for odd ``n``
and ``u_n(a, -psi) = (-1)**n u_n(a, psi)``.  Then the order-``N`` predictions
themselves are even functions of ``eps`` (amplitude, frequency, maximum) or odd
ones (third harmonic, Floquet exponent, ``Gamma``), so each error has only even
or only odd powers: the generic order is rounded *up* to that parity.  For van
der Pol: amplitude and maximum ``2, 2, 4, 4``; frequency ``2, 4, 4, 6``; third
harmonic, multiplier and ``Gamma`` ``3, 3, 5, 5`` for ``N = 1, 2, 3, 4``.

References
----------
N. N. Bogoliubov and Y. A. Mitropolsky, *Asymptotic Methods in the Theory of
Non-Linear Oscillations* (1961), ch. 1, sec. 2 (error of the N-th approximation).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import sympy as sp

from kbm.errors import ParameterError
from kbm.model.builtins import Oscillator, get_model
from kbm.output.strict_json import jsonable
from kbm.symbols import xdot as V

from numerics.comparison.comparison import Comparison, compare
from numerics.comparison.prediction import ERROR_KEYS, derived

__all__ = ["FIT_KEYS", "predicted_orders", "time_reversal_symmetric", "ConvergenceStudy",
           "convergence_study", "fit_slope", "by_pair"]

_GENERIC = {"amplitude": 0, "amplitude_max": 0, "frequency": 1, "harmonic3": 1,
            "floquet_multiplier": 1, "floquet_exponent": 1, "dissipation": 1}
#: parity in eps of each predicted quantity for a time-reversal-symmetric model
_PARITY = {"amplitude": 0, "amplitude_max": 0, "frequency": 0, "harmonic3": 1,
           "floquet_multiplier": 1, "floquet_exponent": 1, "dissipation": 1}
#: the quantities whose convergence is fitted (the multiplier ``exp(L)`` itself carries the
#: factor ``exp(-c eps)``, which bends its log-log line; its exponent ``L`` is fitted)
FIT_KEYS = ("amplitude", "amplitude_max", "frequency", "harmonic3", "floquet_exponent",
            "dissipation")


def time_reversal_symmetric(model: Oscillator | str) -> bool:
    """Whether ``F(x, -x') = -F(x, x')`` (then ``x(t; -eps) = x(-t; eps)``)."""
    m = get_model(model) if isinstance(model, str) else model
    return sp.simplify(m.F.subs(V, -V) + m.F) == 0


def predicted_orders(model: Oscillator | str, order: int) -> dict[str, int]:
    """The power of ``eps`` of each error of the order-``order`` KBM prediction.

    See the module docstring for the derivation.

    Examples
    --------
    >>> predicted_orders("vdp", 1)["frequency"], predicted_orders("vdp", 2)["frequency"]
    (2, 4)
    >>> predicted_orders("sedf", 2)["amplitude"]
    2
    """
    sym = time_reversal_symmetric(model)
    out = {}
    for key, extra in _GENERIC.items():
        p = order + extra
        if sym and p % 2 != _PARITY[key]:
            p += 1
        out[key] = p
    return out


def fit_slope(eps: Sequence[float], err: Sequence[float]) -> float:
    """Least-squares slope of ``log|err|`` against ``log eps`` (nan with fewer than 2 points)."""
    e = np.asarray(eps, dtype=float)
    r = np.abs(np.asarray(err, dtype=float))
    ok = np.isfinite(r) & (r > 0)
    if ok.sum() < 2:
        return float("nan")
    return float(np.polyfit(np.log(e[ok]), np.log(r[ok]), 1)[0])


def by_pair(table: Mapping[tuple, object]) -> dict:
    """A table keyed by pairs ``(row, quantity)`` keyed by ``"row:quantity"`` (its JSON)."""
    return {f"{r}:{k}": v for (r, k), v in table.items()}


@dataclass(frozen=True, eq=False)
class ConvergenceStudy:
    """Errors of KBM predictions along ``eps`` and their fitted slopes.

    Attributes
    ----------
    model
        Model name.
    fixed
        The parameters held fixed (scaled names).
    eps
        The values of ``mu``.
    orders
        KBM orders compared.
    errors
        ``errors[(N, key)]``: absolute errors ``|predicted - true|`` along ``eps``
        (``key`` in :data:`numerics.comparison.comparison.ERROR_KEYS`).
    slopes, predicted
        ``slopes[(N, key)]``: fitted slope; ``predicted[(N, key)]``: the theory's order.
    numeric_dissipation
        ``|Gamma|`` of the true cycle at each ``eps`` (zero to integration accuracy).
    comparisons
        The :class:`~numerics.comparison.comparison.Comparison` at each ``eps``.
    """

    model: str
    fixed: Mapping[str, object]
    eps: tuple[float, ...]
    orders: tuple[int, ...]
    errors: Mapping[tuple[int, str], np.ndarray]
    slopes: Mapping[tuple[int, str], float]
    predicted: Mapping[tuple[int, str], int]
    numeric_dissipation: np.ndarray
    comparisons: tuple[Comparison, ...]

    def table(self) -> str:
        """Fitted slope (predicted order) per KBM order and quantity."""
        keys = sorted({k for _, k in self.slopes}, key=list(ERROR_KEYS).index)
        head = f"{'N':>3}" + "".join(f"{k:>22}" for k in keys)
        lines = [f"{self.model}: fitted slope of log|error| vs log mu (predicted order); "
                 f"mu = {', '.join(f'{e:g}' for e in self.eps)}; fixed "
                 + ", ".join(f"{k}={v}" for k, v in self.fixed.items()), head]
        for N in self.orders:
            lines.append(f"{N:>3}" + "".join(
                f"{self.slopes[(N, k)]:>15.2f} ({self.predicted[(N, k)]:d})  " for k in keys))
        lines.append("max |Gamma| of the true cycles: "
                     f"{float(np.max(np.abs(self.numeric_dissipation))):.2e}")
        return "\n".join(lines)

    def to_json(self) -> dict:
        """Strict-JSON dict (nan becomes ``None``), the tables keyed ``"N:quantity"``."""
        return jsonable({"model": self.model, "fixed": {k: str(v) for k, v in self.fixed.items()},
                         "eps": self.eps, "orders": self.orders, "errors": by_pair(self.errors),
                         "slopes": by_pair(self.slopes), "predicted": by_pair(self.predicted),
                         "numeric_dissipation": self.numeric_dissipation})


def convergence_study(model: str, eps: Sequence[float], *, orders: Sequence[int] = (1, 2),
                      fixed: Mapping[str, object] | None = None,
                      keys: Sequence[str] = FIT_KEYS, **cycle_kwargs) -> ConvergenceStudy:
    """Errors of each KBM order against the true cycle for ``mu`` in ``eps``.

    Parameters
    ----------
    model
        A built-in model name.
    eps
        Values of ``mu`` (a geometric sequence gives evenly spaced log-log points).
    orders
        KBM orders ``N``.
    fixed
        The other parameters, in the model's scaled names (``delta``, not ``Delta``,
        so that they stay fixed as ``mu`` changes).
    cycle_kwargs
        Passed to :func:`numerics.limit_cycle`.

    Examples
    --------
    >>> s = convergence_study("vdp", [0.05, 0.1], orders=(1,))
    >>> round(s.slopes[(1, "frequency")])
    2
    """
    values = [float(e) for e in eps]
    bad = [e for e in values if not (math.isfinite(e) and e > 0)]
    if bad:  # -0.1,0.05,0.1 said "needs at least two distinct values", given two
        raise ParameterError("a convergence study needs values of mu > 0 (the slope of "
                             "log|error| against log mu), got "
                             f"{', '.join(f'{e:g}' for e in bad)}: leave "
                             f"{'it' if len(bad) == 1 else 'them'} out")
    if len(set(values)) < 2:
        # 0.1,0.1,0.1 printed RankWarnings and slopes fitted to one point
        raise ParameterError("a convergence study needs at least two distinct values of "
                             "mu > 0 (the slope of log|error| against log mu), got "
                             f"{', '.join(f'{e:g}' for e in values)}")
    fixed = dict(fixed or {})
    orders = tuple(sorted(int(n) for n in orders))
    res = derived(model, orders[-1])
    fns = res.functions("numpy")
    comps = []
    for e in eps:
        comps.append(compare(model, {**fixed, "mu": e}, orders=orders, result=res,
                             functions=fns, **cycle_kwargs))
    errors, slopes, predicted = {}, {}, {}
    for N in orders:
        pred = predicted_orders(model, N)
        for key in keys:
            errs = []
            for c in comps:
                p = next(q for q in c.predictions if q.order == N)
                errs.append(abs(c.error(p, key)) if p.success else np.nan)
            errors[(N, key)] = np.array(errs)
            slopes[(N, key)] = fit_slope(eps, errs)
            predicted[(N, key)] = pred[key]
    gam = np.array([abs(c.numeric.dissipation.total) for c in comps])
    return ConvergenceStudy(model=str(model), fixed=fixed, eps=tuple(float(e) for e in eps),
                            orders=orders, errors=errors, slopes=slopes, predicted=predicted,
                            numeric_dissipation=gam, comparisons=tuple(comps))
