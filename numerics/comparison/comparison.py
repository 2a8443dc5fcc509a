"""Approximations of a limit cycle next to the true one: :func:`compare`.

For a model ``x'' + omega0^2 x = mu F(x, x')`` and parameter values,
:func:`compare` computes the true periodic orbit by shooting
(:func:`numerics.limit_cycle`) and the cycle each KBM order ``N`` predicts
(:func:`numerics.comparison.prediction.kbm_prediction`), plus any other
approximation passed in ``extra``; :class:`Comparison` holds them with their
errors, as a table and as JSON.

References
----------
N. N. Bogoliubov and Y. A. Mitropolsky, *Asymptotic Methods in the Theory of
Non-Linear Oscillations* (1961), ch. 1.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

from kbm import KBMFunctions, KBMResult
from kbm.errors import ParameterError
from kbm.parameters.bound import BoundModel, bind
from kbm.model.builtins import Oscillator

from kbm.output.strict_json import finite
from numerics.comparison.prediction import (ERROR_KEYS, Prediction, derived,
                                            kbm_prediction, numeric_value)
from numerics.cycles import LimitCycle, limit_cycle
from numerics._show import num, params_text

__all__ = ["Comparison", "compare", "ExtraPrediction"]

#: an extra approximation for :func:`compare`: ``f(bound, target_amplitude=a) -> Prediction``
ExtraPrediction = Callable[..., Prediction]


@dataclass(frozen=True, eq=False)
class Comparison:
    """Predictions of several approximations next to the true cycle.

    Attributes
    ----------
    model
        Model name.
    params
        Every parameter value used (floats, scaled names, incl. ``mu``).
    numeric
        The true cycle (:func:`numerics.limit_cycle`).
    predictions
        One :class:`Prediction` per KBM order, and those of ``extra``
        approximations (the paper's printed formulas, the energy averaging).
    """

    model: str
    params: Mapping[str, float]
    numeric: LimitCycle
    predictions: tuple[Prediction, ...]

    def __repr__(self) -> str:
        labels = ", ".join(p.label for p in self.predictions)
        return (f"Comparison({self.model}; {params_text(self.params)}: true T="
                f"{num(self.numeric.period)}, x_max={num(self.numeric.amplitude_max)}; "
                f"{labels}; .table() prints the errors)")

    def _repr_html_(self) -> str:
        from html import escape

        return f"<pre>{escape(self.table())}</pre>"

    def error(self, prediction: Prediction, key: str) -> float:
        """Signed error ``predicted - true`` of one quantity (see :data:`ERROR_KEYS`)."""
        return prediction.value(key) - numeric_value(self.numeric, key)

    def relative_error(self, prediction: Prediction, key: str) -> float:
        """``|predicted - true| / |true|``; for ``dissipation`` (true value 0) relative to
        ``Gamma_-`` of the true cycle, for the multiplier relative to ``|1 - m|``."""
        err = abs(self.error(prediction, key))
        if key == "dissipation":
            return err / abs(self.numeric.dissipation.gamma_minus or 1.0)
        if key == "floquet_multiplier":
            return err / abs(1 - numeric_value(self.numeric, key))
        return err / abs(numeric_value(self.numeric, key))

    def to_json(self) -> dict:
        """The keys of ``kbm compare --json`` (``None`` for a number that does not exist)."""
        c = self.numeric
        numeric = {"period": c.period, "frequency": c.frequency,
                   "amplitude_first_harmonic": c.amplitude_first_harmonic,
                   "amplitude_max": c.amplitude_max, "dissipation": c.dissipation.total,
                   "floquet_multiplier": numeric_value(c, "floquet_multiplier"),
                   "harmonic3": numeric_value(c, "harmonic3"),
                   "gamma_minus": c.dissipation.gamma_minus,
                   "harmonics": [float(2 * abs(h)) if m else float(abs(h))
                                 for m, h in enumerate(c.harmonics[:8])],
                   "stable": c.stable, "success": c.success, "message": c.message}
        kbm_rows, paper, others = [], None, {}
        for p in self.predictions:
            row = p.to_json()
            row["relative_error"] = {k: (self.relative_error(p, k) if p.success else None)
                                     for k in ERROR_KEYS}
            if p.source == "kbm":
                kbm_rows.append(row)
            elif p.source == "paper":
                paper = row
            else:
                others.setdefault(p.source, []).append(row)
        out = {"model": self.model, "params": dict(self.params), "numeric": numeric,
               "kbm": kbm_rows}
        if paper is not None:
            out["paper"] = paper
        out.update(others)
        return finite(out)

    def table(self) -> str:
        """A plain-text table: each quantity, the true value, and each prediction with its
        relative error."""
        c = self.numeric
        head = f"{'quantity':<20}{'numerical':>16}"
        for p in self.predictions:
            head += f"{p.label:>30}"
        lines = [f"{self.model}  " + ", ".join(f"{k}={v:.6g}" for k, v in sorted(
            self.params.items())), head]
        names = {"amplitude": "a (1st harmonic)", "amplitude_max": "max x",
                 "frequency": "frequency", "harmonic3": "3rd harmonic",
                 "floquet_multiplier": "Floquet multiplier",
                 "floquet_exponent": "T dA/da = log m", "dissipation": "Gamma"}
        for key in ERROR_KEYS:
            line = f"{names[key]:<20}{numeric_value(c, key):>16.10g}"
            for p in self.predictions:
                if not p.success or not math.isfinite(p.value(key)):
                    line += f"{'-':>30}"
                    continue
                entry = f"{p.value(key):.10g} ({self.relative_error(p, key):.1e})"
                line += f"{entry:>30}" if len(entry) <= 28 else f"  {entry}"
            lines.append(line)
        lines.append(f"{'stable':<20}{str(c.stable):>16}" + "".join(
            f"{str(p.stable) if p.success else '-':>30}" for p in self.predictions))
        lines.append("(relative errors in parentheses; Gamma relative to Gamma_- of the "
                     "true cycle, the multiplier relative to 1 - m)")
        for p in self.predictions:
            if not p.success:
                lines.append(f"{p.label}: {p.message}")
        return "\n".join(lines)


def compare(model: Oscillator | str | BoundModel, params: Mapping[str, object] | None = None, *,
            orders: Sequence[int] = (1, 2), extra: Sequence[ExtraPrediction] = (),
            cycle: LimitCycle | None = None, result: KBMResult | None = None,
            functions: KBMFunctions | None = None, **cycle_kwargs) -> Comparison:
    """KBM predictions of several orders (and other approximations) next to the true limit
    cycle.

    Parameters
    ----------
    model
        A built-in name or an :class:`~kbm.model.builtins.Oscillator` (autonomous).
    params
        Parameter values, including ``mu`` (physical names such as ``Delta`` allowed).
    orders
        KBM orders ``N`` (for ``sin(k x)`` models at most 2).
    extra
        More approximations, each a callable ``f(bound, target_amplitude=...)``
        returning a :class:`Prediction` (e.g.
        :func:`numerics.paper.paper_prediction`, the paper's eqs. (5)-(9) as
        printed); their rows come first.
    cycle
        A true cycle already computed (else :func:`numerics.limit_cycle` is called
        with ``cycle_kwargs``).
    result, functions
        A KBM derivation of order ``>= max(orders)`` and its compiled functions, to reuse
        (derived here otherwise).

    Returns
    -------
    Comparison

    Examples
    --------
    >>> c = compare("vdp", {"mu": 0.1}, orders=(1, 3))
    >>> [round(p.amplitude, 6) for p in c.predictions]
    [2.0, 2.000156]
    >>> round(c.numeric.amplitude_first_harmonic, 6)
    2.000156
    """
    bound = bind(model, params)
    orders = sorted({int(n) for n in orders})
    if not orders or orders[0] < 1:
        raise ParameterError(f"KBM orders must be >= 1, got {orders}")
    if bound.mu is None:
        raise ParameterError("compare needs a value of mu")
    if cycle is None:
        cycle = limit_cycle(bound, **cycle_kwargs)
    if result is None:
        result = derived(bound.model, orders[-1])
    fns = functions or result.functions("numpy")
    target = cycle.amplitude_first_harmonic
    preds = [fn(bound, target_amplitude=target) for fn in extra]
    preds += [kbm_prediction(result, bound, n, target_amplitude=target, functions=fns)
              for n in orders]
    return Comparison(model=bound.name, params=bound.floats, numeric=cycle,
                      predictions=tuple(preds))
