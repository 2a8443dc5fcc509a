"""Fourier coefficients of a cycle by quadrature along the integration, with an error estimate.

An FFT of equally spaced samples aliases the fast jumps of a relaxation cycle
(van der Pol at ``mu = 20`` loses four digits of the first-harmonic amplitude
with 1024 samples).  Here the integrals

    ``c_m = (1/T) int_0^T x(t) e^{-i m w t} dt``,  ``w = 2 pi/T``,

are extra states of the integration (``q_0' = x``, ``qc_m' = x cos(m w t)``,
``qs_m' = x sin(m w t)``), so the adaptive step control that resolves the jumps of
``x`` resolves the quadrature too.  The flow is printed from the model's sympy
acceleration and compiled (:func:`numerics.flow.jit_flow`, with ``w`` as one more
parameter); without the compiled integrator (or for a stiff cycle that the
shooting integrates with LSODA) scipy's ``solve_ivp`` integrates the same system.

The error estimate is the change of the coefficients when the integration is
repeated with a tolerance a hundred times smaller.
"""

from __future__ import annotations

import math

import numpy as np

from numerics._memo import memo
from numerics.errors import IntegrationError
from numerics.flow import Method, jit_available, jit_flow

__all__ = ["fourier_coefficients"]

def _exprs(model, n_harmonics: int):
    import sympy as sp

    from kbm.symbols import t as TIME, x as X, xdot as V

    _W = sp.Symbol("_w_fourier")
    acc = model.acceleration()
    n = 3 + 2 * (n_harmonics - 1)
    y = sp.symbols(f"q0:{n}")
    acc = acc.subs({X: y[0], V: y[1]}, simultaneous=True)
    # cos(k w t), sin(k w t) by the angle-addition recurrence from cos(w t), sin(w t): two
    # trigonometric calls per step instead of 2 (n_harmonics - 1) (the printed code shares
    # the subexpressions), rounding error ~ k eps
    c1, s1 = sp.cos(_W * TIME), sp.sin(_W * TIME)
    cos_k, sin_k = [c1], [s1]
    for _ in range(2, n_harmonics):
        c, s_ = cos_k[-1], sin_k[-1]
        cos_k.append(c * c1 - s_ * s1)
        sin_k.append(s_ * c1 + c * s1)
    ex = [y[1], acc, y[0]]
    ex += [y[0] * c for c in cos_k]
    ex += [y[0] * s_ for s_ in sin_k]
    return ex, y


@memo(maxsize=32)
def _compiled(template, n_harmonics: int, enabled: bool):
    if not enabled:
        return None
    acc = getattr(template, "acc_srepr", None)  # a template read from a model card
    if acc is not None:
        built = template.cached_flow(f"harmonics|{n_harmonics}|{acc}")
        if built is not None:
            return built
        template = template.full()
    import sympy as sp  # imported on use (issue 39)

    from kbm.symbols import t as TIME

    n = 3 + 2 * (n_harmonics - 1)
    y = sp.symbols(f"q0:{n}")
    # the expressions are a function of the acceleration and n_harmonics: printing them
    # (seconds for the recurrence's nested products) is done once per cache folder
    key = f"harmonics|{n_harmonics}|{sp.srepr(template.model.acceleration())}"
    return jit_flow(lambda: _exprs(template.model, n_harmonics)[0], TIME, y,
                    [sp.Symbol(n) for n in template.names] + [sp.Symbol("_w_fourier")],
                    key=key)


def _integrals(cm, x0: float, T: float, method: Method, rtol: float, n_harmonics: int):
    """``(int x, int x cos(m w t), int x sin(m w t))`` over one period from ``(x0, 0)``."""
    w = 2 * math.pi / T
    n = 3 + 2 * (n_harmonics - 1)
    y0 = np.zeros(n)
    y0[0] = x0
    # the error norm is a root mean square over all the states: scale the tolerance so that
    # the position and velocity are held as tightly as in a two-state integration
    tol = rtol * math.sqrt(2.0 / n)
    fl = _compiled(cm.template, n_harmonics, jit_available()) \
        if method is Method.COMPILED else None
    if fl is not None:
        res = fl(y0, T, (*cm.pvec, w), tol, tol, 1, 10**7)
        if res.status:
            raise IntegrationError(f"the quadrature of the harmonics failed: {res.message}")
        yT = res.y[-1]
    else:
        ks = np.arange(1, n_harmonics)
        acc = cm.acc

        def rhs(t, y):
            x = y[0]
            return np.concatenate(([y[1], acc(t, x, y[1]), x], x * np.cos(ks * w * t),
                                   x * np.sin(ks * w * t)))

        meth = "LSODA" if method in (Method.LSODA, Method.COMPILED, Method.AUTO) \
            else method.value
        stol = max(tol, 2.5e-14)  # scipy's floor on rtol
        from scipy.integrate import solve_ivp  # only off the compiled path (issue 39)

        with np.errstate(all="ignore"):
            sol = solve_ivp(rhs, (0.0, T), y0, method=meth, rtol=stol, atol=stol)
        if sol.status < 0:
            raise IntegrationError(f"the quadrature of the harmonics failed: {sol.message}")
        yT = sol.y[:, -1]
    if not np.all(np.isfinite(yT)):
        raise IntegrationError("the quadrature of the harmonics became non-finite")
    m = n_harmonics - 1
    return yT[2], yT[3:3 + m], yT[3 + m:3 + 2 * m]


def fourier_coefficients(cm, x0: float, T: float, method: Method, rtol: float,
                         n_harmonics: int = 16) -> tuple[np.ndarray, np.ndarray]:
    """The complex Fourier coefficients ``c_0..c_{n-1}`` of ``x(t)`` on the cycle, and their
    error estimates.

    Parameters
    ----------
    cm
        The :class:`numerics.flow.CompiledModel`.
    x0, T
        The section point (``x' = 0``) and the period of the cycle.
    method
        The integrator of the shooting (:class:`numerics.flow.Method`): the compiled
        DOP853, else scipy's ``solve_ivp`` with this method (LSODA for LSODA).
    rtol
        The integrator tolerance; the estimate comes from a second pass at
        ``rtol/100`` (not below ``1e-14``).
    n_harmonics
        How many coefficients (``m = 0..n_harmonics-1``; at least 2).

    Returns
    -------
    coefficients, errors : numpy.ndarray
        ``c_m = (1/T) int_0^T x e^{-i m w t} dt`` (complex) and ``|c_m(rtol) -
        c_m(rtol/100)|`` (float; from the cycle's ``x0`` and ``T`` as given: their
        own errors are not included).

    Raises
    ------
    numerics.errors.IntegrationError
        If the integration fails.
    """
    n_harmonics = max(2, int(n_harmonics))

    def coeffs(tol):
        q0, qc, qs = _integrals(cm, float(x0), float(T), method, tol, n_harmonics)
        return np.concatenate(([q0 + 0j], qc - 1j * qs)) / T

    c = coeffs(rtol)
    tight = max(rtol * 1e-2, 1e-14)
    err = np.abs(coeffs(tight) - c) if tight < rtol else np.full(len(c), 0.0)
    return c, err
