"""Second-order stochastic averaging: the stationary amplitude density to ``O(mu^2)``.

The noisy oscillator of :mod:`kbm.noise.stochastic`,

``x'' + omega0^2 x = mu F(x, x') + sqrt(2 D) xi(t)``,  ``D = kappa mu`` (``kappa`` fixed),

is written ``x = a cos psi``, ``x' = -a omega0 sin psi``.  Ito's formula gives the exact
(not averaged) equations

``da   = mu [-sin(psi) F/omega0 + kappa cos(psi)^2/(omega0^2 a)] dt - (sin(psi)/omega0)
sqrt(2 D) dW``,
``dpsi = [omega0 - mu cos(psi) F/(a omega0) - mu kappa sin(2 psi)/(omega0^2 a^2)] dt
- (cos(psi)/(a omega0)) sqrt(2 D) dW``,

whose stationary Fokker-Planck equation reads ``(omega0 d/dpsi - mu L_1) p = 0``: a fast
rotation ``omega0 d/dpsi`` and a slow operator ``L_1`` (drift and diffusion, both of order
``mu`` at fixed ``kappa``).  The stationary density is expanded in ``mu`` at fixed
``kappa``, ``p = P_0(a) [1 + mu G_1(a, psi) + mu^2 G_2(a, psi) + ...]/(2 pi)`` (the
multiple-scale / projection expansion of the stationary Fokker-Planck equation:
Papanicolaou and Kohler, Comm. Pure Appl. Math. 27 (1974) 641; Risken, *The
Fokker-Planck Equation*, sec. 8.3; Pavliotis and Stuart, *Multiscale Methods*, ch. 11).
Order by order

* ``omega0 dG_n/dpsi = P_0^{-1} L_1 (P_0 G_{n-1})``: the oscillating part of ``G_n``
  (``mu``-order ``n`` of the Fokker-Planck equation);
* the phase-averaged part ``q_n(a)`` of ``G_n`` from the zero total flux through every
  circle ``a = const`` at the next order (the solvability condition):
  ``(kappa/(2 omega0^2)) q_n' = <u_a g_n> - (kappa/omega0^2) (d/da + lambda) <sin^2 psi g_n>``
  with ``g_n`` the oscillating part, ``u_a`` the drift of ``a`` over ``mu`` and ``lambda =
  P_0'/P_0``; ``q_n`` is fixed up to a constant, which the normalisation takes.

``n = 0`` is the first-order (Stratonovich-Khasminskii) density ``P_0 = a exp((2 omega0^2/
kappa) int A_1)`` of :mod:`kbm.noise.stochastic`; ``q_1`` is the ``O(mu)`` correction.  **Order 2
here keeps ``q_1`` and ``q_2``**: the amplitude density is right to a relative ``O(mu^3)``
(order 1: ``O(mu)``).  When ``F(x, -x') = -F(x, x')`` (van der Pol, Rayleigh, linear
damping) reversing the phase ``psi -> -psi`` maps the expansion at ``mu`` onto the one at
``-mu``, so every odd ``q_n`` vanishes: ``q_1 = 0``, order 1 is right to ``O(mu^2)`` and
order 2 to ``O(mu^4)``; the first non-zero correction there is ``q_2``.  ``<x^2>`` also
takes the second harmonic of ``G_1`` and ``G_2`` (the phase is no longer uniform).

Everything is exact rational algebra on Fourier series in ``psi`` whose coefficients are
Laurent polynomials in ``a``, ``kappa`` and ``omega0`` (polynomial ``F`` only), done once
per model (memoised); moments are mpmath quadratures of ``P_0 (1 + mu q_1 + mu^2 q_2)``.

Checks (``tests/test_stochastic_order2.py``): linear damping with a quartic potential,
whose exact density is Boltzmann's (errors fall like ``mu`` at order 1 and ``mu^3`` at
order 2); van der Pol against long simulations.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import sympy as sp

from ..errors import ModelError, ParameterError
from ..model.builtins import Oscillator
from .stochastic import (NOISE, StochasticAveraging, amplitude_function, density_on,
                         noisy_model, quadratures, stochastic_average)
from ..symbols import a, mu, x, xdot

__all__ = ["SecondOrderAveraging", "stochastic_average_order2", "KAPPA"]

#: ``kappa = D/mu``, the temperature scale held fixed by the expansion
KAPPA = sp.Symbol("kappa", positive=True)
_z = sp.Symbol("z")  # exp(i psi)
_I = sp.I


# --- Fourier series in psi: {harmonic k: coefficient(a)} ---------------------------------
def _add(*gs) -> dict:
    out: dict = {}
    for g in gs:
        for k, c in g.items():
            out[k] = out.get(k, 0) + c
    return {k: c for k, c in ((k, sp.expand(c)) for k, c in out.items()) if c != 0}


def _mul(f: dict, g: dict) -> dict:
    out: dict = {}
    for k, c in f.items():
        for j, d in g.items():
            out[k + j] = out.get(k + j, 0) + c * d
    return {k: c for k, c in ((k, sp.expand((c))) for k, c in out.items()) if c != 0}


def _scale(g: dict, s) -> dict:
    return {k: c for k, c in ((k, sp.expand(c * s)) for k, c in g.items()) if c != 0}


def _dpsi(g: dict) -> dict:
    return {k: _I * k * c for k, c in g.items() if k != 0}


def _ipsi(g: dict) -> dict:
    """The zero-mean antiderivative in ``psi`` of a zero-mean series."""
    return {k: c / (_I * k) for k, c in g.items() if k != 0}


def _da(g: dict, lam) -> dict:
    """``P_0^{-1} d/da (P_0 g) = g' + lambda g``."""
    return {k: c for k, c in ((k, sp.expand(sp.diff(c, a) + lam * c)) for k, c in g.items())
            if c != 0}


def _series(expr) -> dict:
    """A Laurent polynomial in ``z = exp(i psi)`` as ``{k: coefficient}``."""
    out: dict = {}
    for term in sp.Add.make_args(sp.expand(expr)):
        rest = sp.Mul(*[f for f in sp.Mul.make_args(term) if not f.has(_z)])
        k = sp.Integer(0)
        for f in sp.Mul.make_args(term):
            if f == _z:
                k += 1
            elif f.is_Pow and f.base == _z:
                k += f.exp
        out[int(k)] = out.get(int(k), 0) + rest
    return {k: sp.expand(c) for k, c in out.items() if sp.expand(c) != 0}


@dataclass(frozen=True)
class _Operator:
    """The slow operator ``P_0^{-1} L_1 P_0`` on Fourier series (``mu = 1``, ``D = kappa``)."""

    w: sp.Expr
    ua: dict
    upsi: dict
    s2: dict
    sc_a: dict
    c2_a2: dict
    lam: sp.Expr

    def __call__(self, g: dict) -> dict:
        k = KAPPA / self.w**2
        drift = _add(_scale(_da(_mul(self.ua, g), self.lam), -1),
                     _scale(_dpsi(_mul(self.upsi, g)), -1))
        diff = _add(_da(_da(_mul(self.s2, g), self.lam), self.lam),
                    _scale(_da(_dpsi(_mul(self.sc_a, g)), self.lam), 2),
                    _dpsi(_dpsi(_mul(self.c2_a2, g))))
        return _add(drift, _scale(diff, k))

    def flux_q(self, g: dict) -> sp.Expr:
        """``q'`` of the phase-averaged part that balances the oscillating ``g``."""
        k = KAPPA / self.w**2
        ua_g = _mul(self.ua, g).get(0, 0)
        s2_g = _mul(self.s2, g).get(0, 0)
        rhs = ua_g - k * (sp.diff(s2_g, a) + self.lam * s2_g)
        return sp.expand(2 * self.w**2 / KAPPA * rhs)


def _operator(model: Oscillator, A1: sp.Expr) -> _Operator:
    w = model.omega0
    cos = (_z + 1 / _z) / 2
    sin = (_z - 1 / _z) / (2 * _I)
    F = _series(model.F.subs({x: a * cos, xdot: -a * w * sin}))
    S, C = _series(sin), _series(cos)
    ua = _add(_scale(_mul(S, F), -1 / w), _scale(_mul(C, C), KAPPA / (w**2 * a)))
    upsi = _add(_scale(_mul(C, F), -1 / (a * w)),
                _scale(_mul(_mul(S, C), {0: 2}), -KAPPA / (w**2 * a**2)))
    lam = sp.expand(2 * w**2 * A1 / KAPPA + 1 / a)
    return _Operator(w, ua, upsi, _mul(S, S), _scale(_mul(S, C), 1 / a),
                     _scale(_mul(C, C), 1 / a**2), lam)


@dataclass(frozen=True)
class SecondOrderAveraging:
    """The stationary amplitude density through ``O(mu^2)`` at fixed ``kappa = D/mu``.

    Attributes
    ----------
    first : kbm.noise.stochastic.StochasticAveraging
        The first-order averaging (``P_0``).
    q : tuple of sympy.Expr
        ``(q_1, q_2)``: the phase-averaged corrections, functions of ``a`` and
        :data:`KAPPA`, normalised later (``P = P_0 (1 + mu q_1 + mu^2 q_2)/Z``).
    h2 : tuple of sympy.Expr
        ``(c_1, c_2)``: twice the ``cos 2 psi`` coefficient of ``G_1``, ``G_2`` (``<x^2> =
        <a^2 (H_0/2 + H_2/4)>`` with ``H_2 = mu c_1 + mu^2 c_2``).
    """

    first: StochasticAveraging
    q: tuple
    h2: tuple

    def __repr__(self) -> str:
        return f"SecondOrderAveraging({self.first.model.name}: q_1 = {self.q[0]}, q_2 = ...)"

    def _functions(self, params: Mapping[str, object]):
        vals = self.first._values(params)
        m = vals.get(mu)
        if m is None or not m > 0:
            raise ParameterError(f"mu = {m} must be > 0 for the second-order averaging "
                                 "(it expands in mu at fixed D/mu)")
        sub = dict(vals)
        sub[KAPPA] = vals[NOISE] / m
        logp = self.first._log_density_of(params)
        exprs = [sp.sympify(1 + mu * self.q[0] + mu**2 * self.q[1]).subs(sub),
                 sp.sympify(mu * self.h2[0] + mu**2 * self.h2[1]).subs(sub)]
        h0, h2 = (amplitude_function(e, self.first.model.name) for e in exprs)
        return logp, h0, h2

    def _integrals(self, params, weights) -> list:
        f, h0, h2 = self._functions(params)
        return quadratures(f, [lambda s, g=g: g(s, h0, h2) for g in weights])

    def moment(self, k: int, params: Mapping[str, object]) -> float:
        """``<a^k>`` through ``O(mu^2)`` (mpmath quadrature, 30 digits).

        Parameters
        ----------
        k : int
        params : mapping
            ``mu > 0``, ``D > 0`` and the model's parameters.
        """
        z, m = self._integrals(params, [lambda s, h0, h2: h0(s),
                                        lambda s, h0, h2: s**k * h0(s)])
        return float(m / z)

    def x2(self, params: Mapping[str, object]) -> float:
        """``<x^2> = <a^2 cos^2 psi>`` through ``O(mu^2)`` (the phase is not uniform)."""
        z, m = self._integrals(params, [lambda s, h0, h2: h0(s),
                                        lambda s, h0, h2: s**2 * (h0(s) / 2 + h2(s) / 4)])
        return float(m / z)

    def density(self, grid, params: Mapping[str, object]):
        """The normalised amplitude density ``P_0 (1 + mu q_1 + mu^2 q_2)/Z`` on ``grid``."""
        f, h0, _ = self._functions(params)
        return density_on(grid, f, h0)


_CACHE: dict = {}


def stochastic_average_order2(model: Oscillator | str,
                              params: Mapping[str, object] | None = None
                              ) -> SecondOrderAveraging:
    """Second-order stochastic averaging of ``x'' + omega0^2 x = mu F + sqrt(2 D) xi``.

    Parameters
    ----------
    model : str or kbm.model.builtins.Oscillator
        An autonomous model with ``F`` polynomial in ``x, x'``.
    params : mapping, optional
        Model parameters substituted before the algebra (``mu`` and ``D`` stay symbolic).

    Raises
    ------
    kbm.errors.ModelError
        ``F`` not polynomial, or no stationary first-order density.

    Examples
    --------
    >>> so = stochastic_average_order2("vdp")
    >>> so.q[0]
    0
    >>> round(so.moment(2, {"mu": 0.3, "D": 0.15}), 5)
    4.20456
    """
    m, fixed = noisy_model(model, params, "the second-order stochastic averaging")
    key = (m.name, str(m.F), str(m.omega0), tuple(sorted((k, str(v)) for k, v in fixed.items())))
    if key in _CACHE:
        return _CACHE[key]
    first = stochastic_average(m, fixed)
    if first.log_density is None:
        raise ModelError(f"no stationary amplitude density for {m.name!r}: {first.reason}")
    F = first.model.F
    try:
        sp.Poly(sp.expand(F), x, xdot)
    except sp.PolynomialError:
        raise ModelError(f"the second-order averaging needs F polynomial in x, x'; "
                         f"{m.name!r} has F = {F} (use the first order)") from None
    A1 = sp.expand((first.drift_a - NOISE / (2 * first.model.omega0**2 * a)) / mu)
    L = _operator(first.model, A1)
    G: dict = {0: sp.Integer(1)}
    qs, hs = [], []
    for _ in (1, 2):
        g = _scale(_ipsi(L(G)), 1 / L.w)
        q = sp.integrate(L.flux_q(g), a)
        if q.has(sp.Integral):
            raise ModelError(f"the second-order correction of {m.name!r} has no closed form")
        qs.append(sp.expand(q))
        hs.append(sp.expand(g.get(2, 0) + g.get(-2, 0)))
        G = _add(g, {0: q}) if q != 0 else g
    out = SecondOrderAveraging(first, tuple(qs), tuple(hs))
    _CACHE[key] = out
    return out
