"""The KBM expansion evaluated at given amplitudes, any order, for ``F`` with sin/cos of x.

The symbolic engine keeps the Jacobi-Anger Bessel sums of ``sin(k x)``, ``cos(k x)``
to order 2 (:data:`kbm.expansion.one_dof.MAX_ORDER_TRIG`); from order 3 on they become sums
over three and more indices with inner sums in their coefficients, which would not be
readable.  :func:`derive_values` gives every order instead at numeric parameter values
and amplitudes ``a_q``: the same recursion (:func:`kbm.expansion.recursion.kbm_recursion`, with the
same :class:`~kbm.algebra.lazy_series.Builder` of ``F``) over the jets of the numeric coupled
backend with one mode (:meth:`kbm.algebra.coupled_jets.JetAlgebra.one_mode`, every amplitude
at once), where the Bessel functions are numbers (:mod:`kbm.algebra.jet_fourier`),
derivatives in ``a`` are exact (Taylor jets) and the one truncation is in the harmonics,
chosen so that the Jacobi-Anger coefficients left out, ``|J_m(k a)|``, and the Fourier
tails of every ``u_n`` are below ``tol`` relative to that order's quantities.

It also takes polynomial ``F`` (where the exact engine gives the same numbers).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.special
import sympy as sp
from sympy.simplify.fu import TR8

from ..expansion.one_dof import MAX_ORDER, _check_terms
from ..algebra.coupled_jets import JetAlgebra
from ..errors import ParameterError, ResolutionError
from ..model.builtins import Oscillator
from .sampling import (SampledExpansion, check_order, check_tol, fourier_tail, numeric_model,
                       order_scale, sampled_orders, wave_spectrum)
from ..symbols import x, xdot

__all__ = ["derive_values", "ExpansionValues", "DEFAULT_TOL"]

#: default truncation tolerance, relative to each order's quantities
DEFAULT_TOL = 1e-14
#: most phases (harmonics below M/2)
MAX_M = 2**14


@dataclass(frozen=True, eq=False)
class ExpansionValues(SampledExpansion):
    """``A_n``, ``B_n`` and the harmonics of ``u_n`` at the amplitudes ``a``.

    ``model`` and ``order`` as in :class:`~kbm.backend.sampling.SampledExpansion`.

    Attributes
    ----------
    a
        The amplitudes (1-D array).
    A, B
        Arrays ``(N + 1, len(a))``: ``A[n]``, ``B[n]`` at the amplitudes (``A[0] = 0``,
        ``B[0] = omega0``).
    u_cos, u_sin
        Arrays ``(N + 1, len(a), H + 1)``: the coefficients of ``cos(m psi)`` and
        ``sin(m psi)`` of ``u_n`` (``u_0 = a cos psi``).
    harmonics
        ``H``: the highest harmonic kept.
    tol
        The truncation tolerance asked for.
    truncation
        Per order (entry 0 is 0): the largest harmonic left out or aliased, estimated
        by the Fourier tails of ``u_n``, absolute.
    """

    a: np.ndarray
    A: np.ndarray
    B: np.ndarray
    u_cos: np.ndarray
    u_sin: np.ndarray
    harmonics: int
    tol: float
    truncation: tuple[float, ...]

    def u(self, n: int, psi) -> np.ndarray:
        """``u_n(a_q, psi)``: an array ``(len(a),) + shape(psi)``."""
        psi = np.asarray(psi, dtype=float)
        m = np.arange(self.harmonics + 1)
        ph = psi[..., None] * m
        c = self.u_cos[n].reshape((len(self.a),) + (1,) * psi.ndim + (-1,))
        s = self.u_sin[n].reshape((len(self.a),) + (1,) * psi.ndim + (-1,))
        return np.sum(c * np.cos(ph) + s * np.sin(ph), axis=-1)

    def to_json(self) -> dict:
        """Plain keys: ``a``, ``A`` and ``B`` by order, the truncation by order."""
        orders = self._orders()
        return {
            **self._json_head(float(self.B[0][0]) if len(self.a) else None,
                              "jacobi-anger values"),
            "tol": self.tol, "harmonics": self.harmonics,
            "a": [float(v) for v in self.a],
            "A": {k: [float(v) for v in self.A[n]] for n, k in enumerate(orders, 1)},
            "B": {k: [float(v) for v in self.B[n]] for n, k in enumerate(orders, 1)},
            "truncation": dict(zip(orders, self.truncation[1:])),
        }


def _amplitudes(a) -> np.ndarray:
    arr = np.atleast_1d(np.asarray(a, dtype=float))
    if arr.ndim != 1 or arr.size == 0:
        raise ParameterError("give the amplitudes a as a number or a 1-D list of numbers")
    if not np.all(np.isfinite(arr)) or np.any(arr <= 0):
        bad = arr[~np.isfinite(arr) | (arr <= 0)][0]
        raise ParameterError(f"every amplitude must be a finite number > 0 (B_n has a 1/a), "
                             f"got a = {bad:g}")
    return arr


def _trig_coefficients(F: sp.Expr) -> list[float]:
    """The ``k`` of every ``sin(k x + c)``, ``cos(k x + c)`` in ``F``."""
    return [float(sp.expand(f.args[0]).coeff(x)) for f in F.atoms(sp.sin, sp.cos)
            if f.has(x)]


def _start_phases(F: sp.Expr, a_max: float, order: int, tol: float) -> int:
    """Phases enough for the Bessel functions beyond the kept harmonics to be below tol,
    with room for the harmonics the polynomial part and the orders add."""
    H = 0
    for k in _trig_coefficients(F):
        z = abs(k) * a_max
        m = int(z) + 1
        while abs(scipy.special.jv(m, z)) >= tol and m < MAX_M // 2:
            m += 1
        H = max(H, m + order)
    poly = F.replace(lambda e: isinstance(e, (sp.sin, sp.cos)), lambda e: sp.Integer(1))
    deg = max(sp.Poly(poly, x, xdot).total_degree(), 1)
    H += (deg + 1) * order + 4
    M = 32
    while M // 2 - 1 < H:
        M *= 2
    return M


def _tails(Us: list[np.ndarray], A, B, a) -> list[tuple[float, float]]:
    """Per order: (scale, Fourier tail of u_n) with the tail the top quarter's largest."""
    return [(order_scale(An, a * Bn, Un), fourier_tail(Un, axis=-1) if Un.size else 0.0)
            for An, Bn, Un in zip(A, B, Us)]


def derive_values(model: Oscillator | str, order: int, a, params: dict | None = None, *,
                  tol: float = DEFAULT_TOL) -> ExpansionValues:
    """KBM expansion to ``order`` evaluated at amplitudes ``a`` (numeric parameters).

    Parameters
    ----------
    model
        A model whose ``F`` is a polynomial in ``x``, ``xdot`` times ``sin``/``cos`` of
        linear functions of ``x`` (``sedf``, ``cdc``, ...), or polynomial.
    order
        Any order ``1 <= N <= 30``.
    a
        Amplitudes ``> 0``.
    params
        A value for every parameter (built-in defaults fill the rest; the paper's
        physical names ``Delta``, ``lam`` with ``mu`` are converted).
    tol
        Relative truncation tolerance of the harmonics.

    Returns
    -------
    ExpansionValues

    Raises
    ------
    kbm.errors.ParameterError
        A parameter without a value, or an amplitude that is not a finite number > 0.
    kbm.errors.UnsupportedTermError
        A term of ``F`` outside polynomials times sin/cos (the term is named).
    kbm.errors.ResolutionError
        If more than ``2**14`` phases would be needed (``k a`` too large).

    Examples
    --------
    >>> v = derive_values("cdc", 4, [1.0], {"delta": 0.5, "k": 2})
    >>> bool(abs(v.A[1][0] + 0.5) < 1e-15)         # A_1 = -a/2: the damping alone
    True
    """
    check_order(order, MAX_ORDER, None)
    tol = check_tol(tol, 1e-16)
    amps = _amplitudes(a)
    model, F, w0 = numeric_model(model, params)
    # as in kbm.expansion.one_dof: products of sines and cosines become sums
    F = sp.expand(TR8(F)) if F.has(sp.sin, sp.cos) else sp.expand(F)
    _check_terms(F)
    M = _start_phases(F, float(amps.max()), order, tol)
    while True:
        Av, Bv, Uv = sampled_orders(JetAlgebra.one_mode(w0, amps, order - 1, M), F, order)
        tails = _tails(Uv, Av, Bv, amps)
        if all(t <= tol * max(s, 1e-300) or t < 1e-300 for s, t in tails):
            break
        if 2 * M > MAX_M:
            worst = max(t / (s or 1) for s, t in tails)
            raise ResolutionError(
                f"the harmonics of the expansion of F = {F} did not fall below tol = "
                f"{tol:.0e} within {MAX_M // 2} harmonics (tail {worst:.1e}): k*a is too "
                f"large; use smaller amplitudes or a looser tol")
        M *= 2
    return _values(model, order, amps, w0, M, Av, Bv, Uv, tol, tails)


def _values(model, order, amps, w0, M, Av, Bv, Uv, tol, tails) -> ExpansionValues:
    Q, H = len(amps), M // 2 - 1
    A = np.vstack([np.zeros(Q), *Av])
    B = np.vstack([np.full(Q, w0), *Bv])
    uc = np.zeros((order + 1, Q, H + 1))
    us = np.zeros_like(uc)
    uc[0, :, 1] = amps
    for n, Un in enumerate(Uv, start=1):
        spec = wave_spectrum(Un, M)[:, :H + 1]
        uc[n], us[n] = spec.real, -spec.imag
    return ExpansionValues(model=model, order=order, a=amps, A=A, B=B, u_cos=uc, u_sin=us,
                           harmonics=H, tol=tol,
                           truncation=(0.0, *[float(t) for _, t in tails]))
