"""The result of the forced KBM recursion: the slow flow in ``(a, phi)`` and the corrections."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from fractions import Fraction

import numpy as np
import sympy as sp

from ..errors import OrderError, ParameterError
from ..symbols import a, mu, psi
from ..parameters.values import parameter_value
from ..model.forced import LAMBDA, ForcedOscillator, Resonance, phi, sigma

__all__ = ["ForcedKBMResult", "SlowFlow"]


def available_order(order: int | None, top: int) -> int:
    """``order`` (default ``top``) checked to lie in ``1..top``."""
    n = top if order is None else order
    if not (isinstance(n, int) and 1 <= n <= top):
        raise OrderError(f"order {order!r} is not available: this expansion goes to "
                         f"order {top}")
    return n


@dataclass(frozen=True)
class ForcedKBMResult:
    """``x = a cos(psi) + sum mu**n u_n(a, psi, theta)`` with the autonomous slow flow
    ``da/dt = sum mu**n A_n(a, phi)``, ``dphi/dt = -mu (q/p) sigma + sum mu**n B_n(a, phi)``,
    ``psi = (q/p) theta + phi``, ``theta = nu t``, ``nu = (p/q) omega0 + mu sigma``.

    Without a resonance (:attr:`resonance` ``None``, fixed ``nu``) the ``A_n``, ``B_n`` do
    not depend on ``phi`` and ``dpsi/dt = omega0 + sum mu**n B_n(a)``.

    Attributes
    ----------
    model
        The forced oscillator, parameters substituted.
    order
        ``N``.
    resonance, nu_ratio
        The declared resonance (or ``None``) and ``nu0/omega0``.
    A, B, u
        ``A_1..A_N`` and ``B_1..B_N`` (so ``A[n - 1]`` is ``A_n``), sympy expressions in
        ``a``, ``phi``, the parameters and ``sigma``; ``u_1..u_N`` in ``a``, ``psi``,
        ``theta``.
    """

    model: ForcedOscillator
    order: int
    resonance: Resonance | None
    nu_ratio: Fraction
    A: tuple[sp.Expr, ...]
    B: tuple[sp.Expr, ...]
    u: tuple[sp.Expr, ...]
    exact: bool = True

    def _n(self, order: int | None) -> int:
        return available_order(order, self.order)

    def amplitude_rate(self, order: int | None = None) -> sp.Expr:
        """``da/dt = sum_{n<=order} mu**n A_n``."""
        return sp.Add(*[mu**(n + 1) * self.A[n] for n in range(self._n(order))])

    def phase_rate(self, order: int | None = None) -> sp.Expr:
        """``dphi/dt`` (resonant) or ``dpsi/dt`` (non-resonant) to ``order``."""
        s = sp.Add(*[mu**(n + 1) * self.B[n] for n in range(self._n(order))])
        if self.resonance is None:
            return self.model.omega0 + s
        return s - mu * sp.Rational(self.resonance.q, self.resonance.p) * sigma

    def displacement(self, order: int | None = None) -> sp.Expr:
        """``x = a cos(psi) + sum mu**n u_n`` (in ``a``, ``psi``, ``theta``)."""
        return a * sp.cos(psi) + sp.Add(*[mu**(n + 1) * self.u[n]
                                          for n in range(self._n(order))])

    def latex(self, order: int | None = None) -> str:
        """The slow flow as two LaTeX equations (``aligned``)."""
        lhs = r"\dot\varphi" if self.resonance else r"\dot\psi"
        return (r"\begin{aligned}\dot a &= " + sp.latex(self.amplitude_rate(order))
                + r" \\ " + lhs + " &= " + sp.latex(self.phase_rate(order))
                + r"\end{aligned}")

    def slow_flow(self, values: Mapping[str, object] | None = None,
                  order: int | None = None) -> "SlowFlow":
        """The slow flow at numerical parameter values (``mu`` required), as numpy functions
        of ``(a, phi, sigma)``; see :class:`SlowFlow`."""
        values = dict(values or {})
        if "mu" not in values:
            raise ParameterError("the slow flow needs a value of mu (e.g. values={'mu': 0.1})")
        n = self._n(order)
        known = {sp.Symbol(k): parameter_value(k, v) for k, v in values.items()
                 if k != "sigma"}
        da, dphi = self.amplitude_rate(n), self.phase_rate(n)
        if self.model.hard != 0:  # Lambda = K/(omega0^2 - nu^2) at nu = nu0 + mu sigma
            r = self.nu_ratio
            freq = sp.Rational(r.numerator, r.denominator) * self.model.omega0 \
                + (mu * sigma if self.resonance is not None else 0)
            lam = self.model.hard_response(freq)
            da, dphi = da.subs(LAMBDA, lam), dphi.subs(LAMBDA, lam)
        da, dphi = da.subs(known), dphi.subs(known)
        rest = (da.free_symbols | dphi.free_symbols) - {a, phi, sigma}
        if rest:
            names = sorted(s.name for s in rest)
            raise ParameterError(f"the slow flow needs values of {', '.join(names)} "
                                 f"(values={{'{names[0]}': ...}})")
        return SlowFlow.build(da, dphi, self.resonance, n)

    def to_json(self) -> dict:
        """The coefficients as strings (read back with :func:`kbm.symbols.parse`)."""
        return {"model": self.model.name, "order": self.order,
                "resonance": str(self.resonance) if self.resonance else None,
                "A": [str(e) for e in self.A], "B": [str(e) for e in self.B]}


@dataclass(frozen=True)
class SlowFlow:
    """The truncated slow flow at fixed parameters: numpy functions of ``(a, phi, sigma)``.

    ``rates(a, phi, s)`` returns ``(da/dt, dphi/dt)``; ``jacobian(a, phi, s)`` the 2x3
    matrix of their derivatives with respect to ``(a, phi, sigma)``.  ``exprs`` keeps the
    two sympy expressions (for a numeric expansion, :meth:`from_functions`, two strings
    that say what they are); ``domain`` is the amplitude interval on which the rates are
    defined (``None``: every ``a > 0``; outside it they are NaN).
    """

    exprs: tuple
    resonance: Resonance | None
    order: int
    _rates: Callable
    _jac: Callable
    domain: tuple[float, float] | None = None

    @classmethod
    def from_functions(cls, text: tuple[str, str], res: Resonance | None, order: int,
                       rates: Callable, jacobian: Callable,
                       domain: tuple[float, float] | None = None) -> "SlowFlow":
        """A slow flow given by vectorised functions (the numeric forced backend,
        :mod:`kbm.backend.forced`): ``rates(a, phi, sigma) -> (da/dt, dphi/dt)`` and
        ``jacobian(a, phi, sigma) -> 2x3 array``."""
        return cls(tuple(text), res, order, rates, jacobian, domain)

    @classmethod
    def build(cls, da: sp.Expr, dphi: sp.Expr, res: Resonance | None, order: int) -> "SlowFlow":
        """Lambdify the rates and their Jacobian once."""
        J = [[sp.diff(e, v) for v in (a, phi, sigma)] for e in (da, dphi)]
        f = sp.lambdify((a, phi, sigma), [da, dphi], modules="numpy", cse=True)
        j = sp.lambdify((a, phi, sigma), J, modules="numpy", cse=True)
        return cls((da, dphi), res, order, f, j)

    def rates(self, av, ph, s):
        """``(da/dt, dphi/dt)`` (arrays broadcast)."""
        r = self._rates(av, ph, s)
        shape = np.broadcast(np.asarray(av), np.asarray(ph), np.asarray(s)).shape
        return np.broadcast_to(r[0], shape), np.broadcast_to(r[1], shape)

    def jacobian(self, av: float, ph: float, s: float) -> np.ndarray:
        """The 2x3 matrix ``d(da/dt, dphi/dt)/d(a, phi, sigma)``."""
        return np.array(self._jac(float(av), float(ph), float(s)), dtype=float)
