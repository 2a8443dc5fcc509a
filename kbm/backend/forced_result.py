"""The result of the numeric forced backend (:mod:`kbm.backend.forced`): the slow rates as
Chebyshev series in ``a`` times Fourier series in ``phi`` times polynomials in ``sigma``, and
the expansion that holds them and gives the slow flow at a value of ``mu``."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
import sympy as sp

from ..errors import ParameterError
from .sampling import IntervalExpansion
from ..model.forced import Resonance
from ..expansion.forced_result import SlowFlow, available_order

__all__ = ["SlowSeries", "NumericForcedExpansion"]


@dataclass(frozen=True, eq=False)
class SlowSeries:
    """One ``A_n`` or ``B_n``: ``sum_s sigma**s sum_j c_{s,j}(a) exp(i j p phi)``, the
    ``c_{s,j}`` Chebyshev series on ``[lo, hi]`` (the grid's interval), held as a complex
    array ``(S, D, 2 J + 1)`` (for ``B_n`` the series of ``a B_n``, smooth where ``B_n``
    has a ``1/a``, divided by ``a`` on evaluation: ``over_a``); evaluated on ``[a_min, a_max]`` of the expansion and, with
    the grid's margin, a little beyond (NaN further out)."""

    coef: np.ndarray
    lo: float
    hi: float
    p: int
    over_a: bool = False

    def __post_init__(self) -> None:
        # the coefficients of d/da, formed once (Newton and the stability ask for them at
        # every step)
        d = np.polynomial.chebyshev.chebder(self.coef, axis=1) * (2.0 / (self.hi - self.lo)) \
            if self.coef.shape[1] > 1 else np.zeros_like(self.coef)
        object.__setattr__(self, "_dcoef", d)

    @classmethod
    def combine(cls, series, weights) -> "SlowSeries":
        """``sum_i weights[i] series[i]`` (series of one expansion: the same grid)."""
        first = series[0]
        coef = sum(w * f.coef for w, f in zip(weights, series))
        return cls(coef, first.lo, first.hi, first.p, first.over_a)

    def __call__(self, a, phi, s, da: int = 0, dphi: int = 0, dsigma: int = 0) -> np.ndarray:
        """The value (or a partial derivative, ``da <= 1``) at ``(a, phi, sigma)``, arrays
        broadcast."""
        if da not in (0, 1):
            raise ValueError(f"da must be 0 or 1, got {da}")
        if self.over_a:  # the series holds a B_n: B_n = (a B_n)/a, exactly
            av = np.asarray(a, float)
            g = self._eval(a, phi, s, 0, dphi, dsigma)
            if da == 0:
                return g / av
            return (self._eval(a, phi, s, 1, dphi, dsigma) - g / av) / av
        return self._eval(a, phi, s, da, dphi, dsigma)

    def _eval(self, a, phi, s, da: int, dphi: int, dsigma: int) -> np.ndarray:
        av, ph, sv = np.broadcast_arrays(np.asarray(a, float), np.asarray(phi, float),
                                         np.asarray(s, float))
        shape = av.shape
        av, ph, sv = av.ravel(), ph.ravel(), sv.ravel()
        c = self._dcoef if da else self.coef
        t = (2.0 * av - self.lo - self.hi) / (self.hi - self.lo)
        inside = np.abs(t) <= 1.0 + 1e-12
        V = np.polynomial.chebyshev.chebvander(np.clip(t, -1, 1), c.shape[1] - 1)
        vals = np.einsum("nd,sdj->snj", V, c)
        J = (c.shape[2] - 1) // 2
        js = np.arange(-J, J + 1)
        E = np.exp(1j * self.p * ph[:, None] * js[None, :]) * (1j * self.p * js) ** dphi
        vals = np.sum(vals * E[None], axis=-1).real  # (S, n)
        out = np.zeros_like(av)
        for s_pow in range(dsigma, vals.shape[0]):
            out += vals[s_pow] * math.perm(s_pow, dsigma) * sv ** (s_pow - dsigma)
        out[~inside] = np.nan
        return out.reshape(shape)


@dataclass(frozen=True, eq=False)
class NumericForcedExpansion(IntervalExpansion):
    """The forced KBM expansion computed numerically on ``a_min <= a <= a_max``.

    ``model`` (a forced oscillator), ``order``, ``a_range``, ``omega0``, ``tol``,
    ``resolution`` (``(P, M, N)``) and the error estimates ``A_error``, ``B_error``,
    ``u_error`` (entry ``n - 1`` for order ``n``) as in
    :class:`~kbm.backend.sampling.IntervalExpansion`.

    Attributes
    ----------
    resonance
        The declared resonance ``p/q``: ``nu = (p/q) omega0 + mu sigma``.
    A, B
        ``A_1..A_N`` and ``B_1..B_N`` (so ``A[n - 1]`` is ``A_n``) as :class:`SlowSeries`:
        callables ``A[n - 1](a, phi, sigma)``.
    parameters
        The parameter values the expansion was computed with.
    """

    resonance: Resonance
    A: tuple[SlowSeries, ...]
    B: tuple[SlowSeries, ...]
    parameters: Mapping[str, float] = field(default_factory=dict)

    exact = False

    def _n(self, order: int | None) -> int:
        return available_order(order, self.order)

    def slow_flow(self, values, order: int | None = None) -> SlowFlow:
        """The slow flow ``da/dt = sum mu**n A_n``, ``dphi/dt = -mu (q/p) sigma + sum mu**n
        B_n`` at ``values["mu"]`` (any other parameter given must have the value the
        expansion was computed with), truncated at ``order``."""
        values = dict(values or {})
        if "mu" not in values:
            raise ParameterError("the slow flow needs a value of mu (e.g. values={'mu': 0.1})")
        for k, v in values.items():
            if k in self.parameters and float(sp.sympify(v)) != self.parameters[k]:
                raise ParameterError(
                    f"{k} = {v} differs from the value {self.parameters[k]:g} this expansion "
                    f"was computed with; derive it again with {k} = {v}")
        m = float(sp.sympify(values["mu"]))
        n = self._n(order)
        weights = [m ** (i + 1) for i in range(n)]
        A = SlowSeries.combine(self.A[:n], weights)  # one series per rate, summed once
        B = SlowSeries.combine(self.B[:n], weights)
        qp = self.resonance.q / self.resonance.p

        def rates(av, ph, s):
            return A(av, ph, s), B(av, ph, s) - m * qp * np.asarray(s, float)

        def jacobian(av, ph, s):
            rows = [[A(av, ph, s, da=1), A(av, ph, s, dphi=1), A(av, ph, s, dsigma=1)],
                    [B(av, ph, s, da=1), B(av, ph, s, dphi=1),
                     B(av, ph, s, dsigma=1) - m * qp]]
            return np.array([[float(np.ravel(v)[0]) for v in row] for row in rows])

        lo, hi = self.a_range
        text = (f"sum_(n<={n}) mu^n A_n(a, phi, sigma) (numeric, a in [{lo:g}, {hi:g}])",
                f"-mu*{self.resonance.q}/{self.resonance.p}*sigma + sum_(n<={n}) mu^n "
                f"B_n(a, phi, sigma) (numeric)")
        return SlowFlow.from_functions(text, self.resonance, n, rates, jacobian,
                                       domain=(self.A[0].lo, self.A[0].hi))

    def to_json(self, a, phi=0.0, s=0.0) -> dict:
        """``A_n``, ``B_n`` at the amplitudes ``a`` (one ``phi``, ``sigma``) and the error
        estimates, with plain keys."""
        a = np.atleast_1d(np.asarray(a, float))
        return {"model": self.model.name, "F": sp.sstr(self.model.F, order="lex"),
                "omega0": self.omega0, "order": self.order, "resonance": str(self.resonance),
                "method": "numeric",
                **self._interval_json(("chebyshev_points", "phases_psi", "phases_theta"), a,
                                      {"phi": float(phi), "sigma": float(s)},
                                      [f(a, phi, s) for f in self.A],
                                      [f(a, phi, s) for f in self.B])}
