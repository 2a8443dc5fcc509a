"""The KBM expansion of a periodically forced oscillator, near a resonance, to any order.

For ``x'' + omega0**2 x = mu F(x, x', theta)``, ``theta = nu t``,
``nu = nu0 + mu sigma`` with ``nu0 = (p/q) omega0`` (:class:`~kbm.model.forced.Resonance`):

``x = a cos(psi) + sum_{n>=1} mu**n u_n(a, psi, theta)``,
``da/dt = sum mu**n A_n(a, psi, theta)``, ``dpsi/dt = omega0 + sum mu**n B_n(a, psi, theta)``,

where ``A_n``, ``B_n`` hold only the *slow* harmonics ``cos(j (p psi - q theta))``,
``sin(...)`` — functions of the resonant phase ``phi = psi - (q/p) theta``, since
``p psi - q theta = p phi`` — and no ``u_n`` holds a *resonant* harmonic
``(m, k) = (+-1 + j p, -j q)`` (those of frequency ``+-omega0`` at ``nu = nu0``), so that
``a`` is exactly the amplitude of the response's component at the frequency
``(q/p) nu``.  ``L0 = omega0 d/dpsi + nu0 d/dtheta`` annihilates the slow harmonics and
``D_1`` holds ``sigma d/dtheta`` (the recursion for ``R_n`` is :mod:`kbm.expansion.recursion`'s).
The resonant part ``P(p phi) cos(psi) + Q(p phi) sin(psi)`` of ``R_n`` gives
``A_n = -Q/(2 omega0)``, ``B_n = -P/(2 omega0 a)`` and every other harmonic is divided by
``omega0**2 - (m omega0 + k nu0)**2`` (never zero).  The slow flow is autonomous:
``da/dt = sum mu**n A_n(a, phi)``, ``dphi/dt = -mu (q/p) sigma + sum mu**n B_n(a, phi)``.

Without a declared resonance (``nu`` given, not near one) the same recursion keeps only
``(m, k) = (1, 0)`` secular; a harmonic whose divisor is small (within ``tolerance`` of a
resonance) is refused with the resonance named (:class:`SmallDivisorError`).

The engine is the coupled one at ``N = 1`` with a forcing angle: the one recursion
(:func:`kbm.expansion.recursion.kbm_recursion`) over the exact algebra of
:mod:`kbm.expansion.coupled` (:class:`~kbm.algebra.forced.ForcedAlgebra`, a
:class:`~kbm.algebra.coupled.CoupledAlgebra`): Fourier series in ``(psi, theta)``
(:mod:`kbm.algebra.multi_angle`) with Laurent-polynomial coefficients over Q in ``a``, the
parameters and ``sigma``, on the slow lattice of the declared resonance.

References
----------
N. N. Bogoliubov and Y. A. Mitropolsky, *Asymptotic Methods in the Theory of Non-Linear
Oscillations* (1961), ch. 3 (resonance case).  A. H. Nayfeh and D. T. Mook, *Nonlinear
Oscillations* (1979), sec. 4.1.
"""

from __future__ import annotations

from fractions import Fraction

import sympy as sp

from ..algebra.coupled import coupled_rhs
from ..algebra.multi_angle import MultiAngle
from ..errors import OrderError, ParameterError, UnsupportedTermError
from .recursion import kbm_recursion
from ..symbols import a, mu, psi, x, xdot
from ..parameters.values import parameter_value
from ..model.forced_builtins import get_forced_model
from ..model.forced_checks import polynomial_message
from ..model.oscillator import TO_GENERAL
from ..model.forced import ForcedOscillator, Resonance, phi, sigma, theta
from ..model.forced import nu as nu_symbol
from ..algebra.forced import ForcedAlgebra, SmallDivisorError
from .forced_result import ForcedKBMResult
from .resonance import InternalResonance, SlowLattice

__all__ = ["derive_forced", "SmallDivisorError", "MAX_ORDER"]

#: highest order of the forced expansion (cost grows quickly with the harmonics of theta)
MAX_ORDER = 12


def _slow_expr(f: MultiAngle) -> sp.Expr:
    """A slow series (harmonics ``(j p, -j q)``, i.e. of ``j p phi``) in ``a`` and ``phi``."""
    parts = []
    for kind, table in (("cos", f.cos), ("sin", f.sin)):
        fn = sp.cos if kind == "cos" else sp.sin
        for (m, _k), c in sorted(table.items()):
            parts.append(c.as_primitive_expr() * (fn(m * phi) if m else 1))
    return sp.Add(*parts)


def derive_forced(model: ForcedOscillator | str, order: int, params: dict | None = None, *,
                  resonance: Resonance | str | None = None, nu: object = None,
                  tolerance: float = 0.05) -> ForcedKBMResult:
    """KBM expansion of ``x'' + omega0**2 x = mu F(x, x', nu t)`` near a resonance, order ``N``.

    Parameters
    ----------
    model
        A :class:`~kbm.model.forced.ForcedOscillator` or a built-in forced model's name.
    order
        Highest power of ``mu`` kept (``A_1..A_N``, ``B_1..B_N``, ``u_1..u_N``).
    params
        Exact parameter values substituted first (``"0.1"`` is ``1/10``).
    resonance
        The declared resonance ``p/q`` (``nu = (p/q) omega0 + mu sigma``); default the
        model's own.
    nu
        Instead of a resonance: a fixed forcing frequency (a number; ``omega0`` numeric),
        for the non-resonant expansion; refused with the resonance named when a harmonic
        comes within ``tolerance`` (relative to ``omega0``) of resonance.

    Returns
    -------
    ForcedKBMResult
        The slow flow ``da/dt = sum mu**n A_n(a, phi)``, ``dphi/dt = -mu (q/p) sigma +
        sum mu**n B_n(a, phi)`` and the corrections ``u_n(a, psi, theta)``.

    Notes
    -----
    A hard forcing (``model.hard = K``: ``x'' + omega0**2 x = mu F + K cos(nu t)``) is
    averaged for ``y = x - Lambda cos(theta)``, ``Lambda = K/(omega0**2 - nu**2)`` (the
    symbol ``Lambda`` in the result; :meth:`ForcedKBMResult.slow_flow` puts its value in).

    Raises
    ------
    kbm.errors.OrderError
        If ``order`` is not an integer in ``1..MAX_ORDER``.
    kbm.errors.ParameterError
        For both a resonance and ``nu``, a bad ``nu``, or a hard forcing at ``nu = omega0``.
    SmallDivisorError
        Non-resonant expansion near an undeclared resonance (the resonance named).

    Examples
    --------
    >>> r = derive_forced("duffing-forced", 1)
    >>> r.A[0]
    -a*zeta - h*sin(phi)/2
    >>> r.B[0]
    3*a**2*alpha/8 - h*cos(phi)/(2*a)
    """
    if isinstance(model, str):
        model = get_forced_model(model)
    if params:
        model = model.substitute(params)
    if not model.is_polynomial:
        raise UnsupportedTermError(polynomial_message(model.F, model.name))
    if not isinstance(order, int) or isinstance(order, bool) or not 1 <= order <= MAX_ORDER:
        raise OrderError(f"the order must be an integer from 1 to {MAX_ORDER}, got {order!r}")
    if nu is not None and resonance is not None:
        raise ParameterError("give either a resonance p/q (with the detuning sigma) or a fixed "
                             "forcing frequency nu, not both")
    if nu is not None:
        if not model.omega0.is_Rational:
            raise ParameterError(f"a fixed forcing frequency needs a numeric omega0, got "
                                 f"{model.omega0}; give its value")
        nu_val = parameter_value("nu", nu)  # read safely and exactly ("0.34" is 17/50)
        if not (nu_val.is_Rational and nu_val > 0):
            raise ParameterError(f"nu must be a positive number, got {nu!r}")
        ratio = Fraction(str(nu_val / model.omega0))
        res = None
    else:
        res = Resonance.parse(resonance) if resonance is not None else model.resonance
        ratio = res.ratio
    if model.hard != 0 and ratio == 1:
        raise ParameterError(f"the hard forcing K cos(theta) of {model.name!r} is resonant at "
                             "nu = omega0 (Lambda = K/(omega0^2 - nu^2) is infinite): at the "
                             "primary resonance write it as a weak forcing mu*h*cos(theta)")
    freq = sp.Rational(ratio.numerator, ratio.denominator) * model.omega0 \
        + (mu * sigma if res is not None else 0)
    Fmu = sp.Poly(sp.expand(model.shifted(freq).subs(nu_symbol, freq)), mu)
    F = [sp.expand(Fmu.coeff_monomial(mu**k)) for k in range(Fmu.degree() + 1)]
    syms = set().union(*[f.free_symbols for f in F]) | model.omega0.free_symbols
    gens = sorted(syms - {x, xdot, theta, sigma, mu}, key=lambda s: s.name)
    internal = (InternalResonance(1, 2, res.q, res.p, forcing=True),) if res else ()
    # the coupled algebra of N = 1 with the forcing angle; the declared resonance is exact,
    # so no other harmonic nears it (tolerance 0), a fixed nu checks its small divisors
    alg = ForcedAlgebra(model, SlowLattice(2, internal), gens + ([sigma] if res else []),
                        0 if res else tolerance, ratio=ratio,
                        nu0=sp.Rational(ratio.numerator, ratio.denominator) * model.omega0,
                        detuning=sigma if res else None, amplitude_symbols=(a,))
    rhs = coupled_rhs(alg, [[f.xreplace(TO_GENERAL) for f in F]])
    (A,), (B,), (U,) = kbm_recursion(alg, rhs, order)
    return ForcedKBMResult(
        model=model, order=order, resonance=res, nu_ratio=ratio,
        A=tuple(_slow_expr(f) for f in A),
        B=tuple(_slow_expr(f) for f in B),
        u=tuple(f.as_expr((psi, theta)) for f in U))
