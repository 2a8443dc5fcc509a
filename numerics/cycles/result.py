"""The result of a limit-cycle computation: :class:`LimitCycle` and its :class:`Dissipation`.

Results are immutable: the arrays are read-only, the mappings frozen, and two
results compare by identity (``eq=False``: arrays have no single truth value).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from kbm.parameters.values import FrozenMap
from numerics._show import html_table, num, params_text

__all__ = ["Dissipation", "LimitCycle"]


@dataclass(frozen=True)
class Dissipation:
    """Energy gain and loss over one cycle (paper eqs. 10-11): ``total = factor*plus - minus``.

    For the SEDF (and van der Pol, ``beta = 1``) ``gamma_plus = mu int x^2 x'^2 dt``,
    ``gamma_minus = mu int x'^2 dt`` and ``total = beta gamma_plus - gamma_minus``.
    """

    total: float
    gamma_plus: float
    gamma_minus: float
    plus_factor: float = 1.0


@dataclass(frozen=True, eq=False)
class LimitCycle:
    """A periodic orbit of the full equation, with its checks.

    Attributes
    ----------
    success, message
        Whether Newton converged to a periodic orbit, and how (or why not).
    period, frequency
        ``T`` and ``2 pi/T``.
    amplitude_max
        Maximum of ``x`` on the orbit (the section point).
    amplitude_first_harmonic
        ``|(2/T) int x e^{-i w t} dt|``: what KBM's amplitude ``a`` predicts.
    harmonics
        Complex Fourier coefficients ``c_m`` of ``x(t) = sum_m c_m e^{i m w t}``,
        ``m = 0..len-1`` (time origin at the section point).
    t, x, xdot
        Samples of one period.
    floquet_multipliers
        Eigenvalues of the monodromy matrix, the trivial one (closest to 1) first.
    stable
        ``|non-trivial multiplier| < 1``.
    liouville
        ``(det Phi(T), exp(int div f dt))``: equal by Liouville's formula.
    dissipation
        :class:`Dissipation` over one period.
    energy_residual
        ``E(0) - E(T) - Gamma``: zero up to integration error.
    iterations, residual, history
        Newton iterations, final ``|P(x0) - x0|``, and the residual of each iteration.
    method
        The integrator of the shooting (``"DOP853 (compiled)"``, ``"LSODA"``, or a scipy
        method's name).
    params
        The parameter values used (floats).
    accuracy
        Estimated relative errors of ``period``, ``frequency``, ``amplitude_max`` and
        ``amplitude_first_harmonic`` (from a Newton step and a quadrature at a
        tolerance a hundred times smaller; see :mod:`numerics.cycles.finalpass`).
    digits
        ``None`` for double precision; the number of digits for :func:`limit_cycle`
        with ``digits=`` (then ``period_mp``, ``amplitude_max_mp``,
        ``amplitude_first_harmonic_mp`` hold mpmath numbers).
    """

    success: bool
    message: str
    model: str
    params: Mapping[str, float]
    period: float
    frequency: float
    amplitude_max: float
    amplitude_first_harmonic: float
    harmonics: np.ndarray
    t: np.ndarray
    x: np.ndarray
    xdot: np.ndarray
    floquet_multipliers: tuple[complex, complex]
    stable: bool
    liouville: tuple[float, float]
    dissipation: Dissipation
    energy_residual: float
    iterations: int
    residual: float
    history: tuple[float, ...]
    method: str
    digits: int | None = None
    mp: Mapping[str, object] = field(default_factory=dict)
    accuracy: Mapping[str, float] = field(default_factory=dict)

    def __post_init__(self) -> None:
        for name in ("harmonics", "t", "x", "xdot"):
            arr = np.array(getattr(self, name))
            arr.setflags(write=False)
            object.__setattr__(self, name, arr)
        object.__setattr__(self, "params", FrozenMap(self.params))
        object.__setattr__(self, "mp", FrozenMap(self.mp))
        object.__setattr__(self, "accuracy", FrozenMap(self.accuracy))

    def _rows(self) -> list[tuple[str, str]]:
        m = ", ".join(num(abs(z), 6) for z in self.floquet_multipliers)
        return [("period", num(self.period)), ("amplitude_max", num(self.amplitude_max)),
                ("first harmonic", num(self.amplitude_first_harmonic)),
                ("stability", "stable" if self.stable else "unstable"),
                ("|Floquet multipliers|", m), ("residual", num(self.residual, 2)),
                ("method", self.method)]

    def __repr__(self) -> str:
        head = f"LimitCycle({self.model}; {params_text(self.params)}"
        if not self.success:
            return f"{head}: failed: {self.message})"
        rows = dict(self._rows())
        return (f"{head}: T={rows['period']}, x_max={rows['amplitude_max']}, "
                f"{rows['stability']}, |multipliers|=({rows['|Floquet multipliers|']}))")

    def _repr_html_(self) -> str:
        title = f"limit cycle of {self.model} ({params_text(self.params)})"
        if not self.success:
            return html_table(title, [("failed", self.message)])
        return html_table(title, self._rows())

    def significant_digits(self, name: str, limit: int = 12) -> int:
        """How many significant digits of ``name`` (``"period"``, ``"amplitude_max"``, ...)
        the accuracy estimate supports (at most ``limit``, at least 1)."""
        rel = self.accuracy.get(name)
        if rel is None or not rel > 0:
            return limit
        return max(1, min(limit, int(math.floor(-math.log10(rel)))))

    def to_json(self) -> dict:
        """The keys of ``kbm cycle --json`` (numbers as strings when ``digits`` is set)."""
        def num(name, value):
            if self.digits is not None and name in self.mp:
                import mpmath
                return mpmath.nstr(self.mp[name], self.digits, strip_zeros=False)
            return float(value)

        return {
            "model": self.model,
            "params": {k: float(v) for k, v in sorted(self.params.items())},
            "success": self.success,
            "message": self.message,
            "period": num("period", self.period),
            "frequency": num("frequency", self.frequency),
            "amplitude_max": num("amplitude_max", self.amplitude_max),
            "amplitude_first_harmonic": num("amplitude_first_harmonic",
                                            self.amplitude_first_harmonic),
            "floquet_multipliers": [float(m.real) if abs(m.imag) < 1e-300 else
                                    [float(m.real), float(m.imag)]
                                    for m in self.floquet_multipliers],
            "stable": self.stable,
            "dissipation": {"total": self.dissipation.total,
                            "gamma_plus": self.dissipation.gamma_plus,
                            "gamma_minus": self.dissipation.gamma_minus},
            "energy_residual": self.energy_residual,
            "iterations": self.iterations,
            "residual": self.residual,
            "method": self.method,
            "digits": self.digits,
            "accuracy": {k: float(v) for k, v in sorted(self.accuracy.items())},
        }
