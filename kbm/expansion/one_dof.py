"""The Krylov-Bogoliubov-Mitropolsky expansion of one degree of freedom, to any order.

For ``x'' + omega0**2 x = mu F(x, x')`` the expansion (Bogoliubov & Mitropolsky
1961, ch. 1, sec. 2) is

``x = a cos(psi) + sum_{n>=1} mu**n u_n(a, psi)``,
``da/dt = sum_{n>=1} mu**n A_n(a)``, ``dpsi/dt = omega0 + sum_{n>=1} mu**n B_n(a)``,

with the convention that **no** ``u_n`` contains a first harmonic, so that
``a`` is exactly the amplitude of the first harmonic of ``x``: removing the first
harmonic of ``R_n`` gives ``A_n = -R_n^{sin 1}/(2 omega0)``,
``B_n = -R_n^{cos 1}/(2 omega0 a)``, and ``u_n`` follows harmonic by harmonic (the
recursion for ``R_n`` is :mod:`kbm.expansion.recursion`'s, the case ``N = 1`` without forcing).

Polynomial ``F`` is treated with exact rational arithmetic on Fourier series
with Laurent-polynomial coefficients (:mod:`kbm.algebra.poly_fourier`), any
order; ``F`` with ``sin(k x)``, ``cos(k x)`` with the Jacobi-Anger algebra of
:mod:`kbm.algebra.bessel_fourier`, order <= 2 (the Bessel sums stay symbolic; from
order 3 on they are sums over three and more indices with inner sums, not readable, and
:func:`kbm.backend.pointwise.derive_values` evaluates any order at numeric parameters instead;
:func:`kbm.backend.one_dof.numeric_derive` takes any smooth ``F``).
The recursion (:func:`kbm.expansion.recursion.one_angle_recursion`, the case ``N = 1`` of the one
recursion :func:`kbm.expansion.recursion.kbm_recursion`) sees either one only through the
:class:`~kbm.algebra.base.FourierAlgebra` protocol, and ``F`` only as the lazy
series of :mod:`kbm.algebra.lazy_series`.

:func:`derive` is the public entry; :func:`run_recursion` is the internal one
(results kept in the algebra's own types), used by the exact limit-cycle
series of :mod:`kbm.slowflow.series`.
"""

from __future__ import annotations

from dataclasses import dataclass

from typing import TYPE_CHECKING

import sympy as sp

from sympy.simplify.fu import TR8

from ..algebra.base import FourierAlgebra
from ..algebra.bessel_fourier import SymAlgebra
from ..algebra.laurent import LaurentRing
from ..algebra.lazy_series import trig_argument_message, unsupported_message
from ..algebra.poly_fourier import PolyAlgebra
from .cost import check_cost
from ..errors import NonAutonomousError, OrderError, UnsupportedTermError
from ..model.builtins import Oscillator, get_model
from ..model.oscillator import TO_ONE
from .recursion import one_angle_recursion
from .result import KBMResult
from ..symbols import a, psi, x, xdot

if TYPE_CHECKING:  # the coupled engine imports this module
    from .coupled_result import CoupledKBMResult
    from ..model.coupled import CoupledOscillators

__all__ = ["derive", "run_recursion", "RawExpansion", "MAX_ORDER_TRIG", "MAX_ORDER",
           "symbolic_order_limit"]

#: highest order kept symbolic for F with sin(k x) or cos(k x) (any order is evaluated
#: at numeric parameters by kbm.backend.pointwise.derive_values)
MAX_ORDER_TRIG = 2

#: highest order of the expansion at all: the symbolic work grows like order^5 (van der Pol,
#: one-generator dense arithmetic: order 20 in 0.3 s, 30 in 1.3 s, 40 in 6 s)
MAX_ORDER = 30

# ----------------------------------------------------------------------------- guards
def _is_polynomial(model: Oscillator) -> bool:
    """Whether the exact algebra applies: F polynomial in x, xdot with coefficients that are
    Laurent polynomials in the parameters over Q, and omega0 rational or a symbol."""
    F, w0 = _one_form(model)
    F = sp.expand(F)
    try:
        poly = sp.Poly(F, x, xdot)
    except sp.PolynomialError:
        return False
    if not (w0.is_Symbol or w0.is_Rational):
        return False
    params = sorted((F.free_symbols | w0.free_symbols) - {x, xdot}, key=lambda s: s.name)
    ring = LaurentRing([a, *params])
    for c in poly.coeffs():
        try:
            ring.from_expr(c)
        except (TypeError, sp.PolynomialError, sp.GeneratorsNeeded):
            return False
    return True


def symbolic_order_limit(model: Oscillator) -> int:
    """The highest order :func:`derive` gives for ``model``: :data:`MAX_ORDER` for
    polynomial ``F`` with rational coefficients, :data:`MAX_ORDER_TRIG` otherwise."""
    return MAX_ORDER if _is_polynomial(model) else MAX_ORDER_TRIG


def _check_terms(F: sp.Expr) -> None:
    """Name the first unsupported term before any algebra is done."""
    def walk(e):
        if not e.has(x, xdot):
            return
        if e in (x, xdot):
            return
        if e.is_Add or e.is_Mul:
            for arg in e.args:
                walk(arg)
            return
        if e.is_Pow:
            if e.exp.is_Integer and e.exp > 0:
                walk(e.base)
                return
            raise UnsupportedTermError(unsupported_message(e))
        if isinstance(e, (sp.sin, sp.cos)):
            arg = sp.expand(e.args[0])
            if arg.has(xdot) or not arg.is_polynomial(x) or sp.Poly(arg, x).degree() != 1:
                raise UnsupportedTermError(trig_argument_message(e))
            return
        raise UnsupportedTermError(unsupported_message(e))
    walk(F)


# ----------------------------------------------------------------------------- the expansion
def derive(model: "Oscillator | CoupledOscillators | str", order: int,
           params: dict | None = None) -> "KBMResult | CoupledKBMResult":
    """KBM expansion of ``x'' + omega0**2 x = mu F(x, x')`` to order ``order``.

    Parameters
    ----------
    model
        An :class:`~kbm.model.builtins.Oscillator` or the name of a built-in model; a coupled
        system (:class:`~kbm.model.coupled.CoupledOscillators` or a coupled built-in's name) is
        the same family with ``dof = N``: :func:`kbm.expansion.coupled.derive_coupled` expands it
        and its :class:`~kbm.expansion.coupled_result.CoupledKBMResult` is returned (for ``N = 1``
        with ``sin``/``cos`` of the position above the first order, this engine's lattice sums,
        in the general form).
    order
        Highest power ``N`` of ``mu`` kept in ``da/dt``, ``dpsi/dt`` and ``x``
        (``A_1..A_N``, ``B_1..B_N``, ``u_1..u_N``).  Any ``N >= 1`` for
        polynomial ``F``; ``N <= 2`` when ``F`` contains ``sin(k x)`` or ``cos(k x)``
        (any order at numeric parameter values: :func:`kbm.derive_values`).
    params
        Parameter values substituted before the derivation (exact: ``"0.1"``
        is read as ``1/10``).

    Returns
    -------
    KBMResult
        ``A``, ``B``, ``u``: tuples indexed by order, with ``A[0] = 0``,
        ``B[0] = omega0``, ``u[0] = a cos(psi)``.

    Raises
    ------
    kbm.errors.OrderError
        If ``order < 1`` (or > 2 for trigonometric ``F``).
    kbm.errors.UnsupportedTermError
        If ``F`` has a term that is not a polynomial in ``x``, ``xdot`` times
        ``sin``/``cos`` of a linear function of ``x`` (the term is named).
    kbm.errors.NonAutonomousError
        If the model depends on ``t`` (e.g. a slider with stage velocity ``v != 0``).

    References
    ----------
    N. N. Bogoliubov and Y. A. Mitropolsky, *Asymptotic Methods in the Theory of
    Non-Linear Oscillations*, Gordon and Breach (1961), ch. 1.

    Examples
    --------
    >>> res = derive("vdp", 2)
    >>> res.A[1]
    -a*(a**2 - 4)/8
    >>> res.B[2]
    -7*a**4/256 + a**2/8 - 1/8
    """
    system = _coupled_member(model)
    if system:  # N degrees of freedom (or a forcing): the general engine
        from ..model.coupled_builtins import get_coupled_model
        from .coupled import derive_coupled

        model = get_coupled_model(model) if isinstance(model, str) else model
        if not _bessel_case(model, order):
            return derive_coupled(model, order, params)
        # N = 1, sin/cos of x above order 1: this engine's lattice sums, on the same instance
    raw = run_recursion(model, order, params)
    alg = raw.algebra
    res = KBMResult(
        model=raw.model, order=order,
        A=(sp.Integer(0), *[alg.coef_expr(c) for c in raw.A]),
        B=(raw.model.omegas[0], *[alg.coef_expr(c) for c in raw.B]),
        u=(a * sp.cos(psi), *[alg.series_expr(f) for f in raw.u]),
        exact=raw.exact,
    )
    if system:
        from .coupled_result import CoupledKBMResult

        return CoupledKBMResult.from_one_degree(model, res)
    return res


def _bessel_case(model, order: int) -> bool:
    """Whether the system ``model`` has one degree of freedom, no forcing and ``sin``/``cos``
    of its position, and ``order > 1`` (which the general engine does not take and this one
    does, on the same instance through its general accessors)."""
    from ..algebra.coupled_bessel import trig_of_state

    m = model
    if order <= 1 or m.dof != 1 or m.forced or m.hards:
        return False
    terms = sp.Add.make_args(sp.expand(m.rhs[0]))
    return any(trig_of_state(term, set(m.state)) for term in terms)


def _one_form(model) -> tuple[sp.Expr, sp.Expr]:
    """``(F(x, xdot), omega0)`` of an ``N = 1`` instance of the one type, from its general
    accessors ``rhs``, ``omegas`` (an :class:`Oscillator` keeps its ``F`` as written)."""
    F = model.F if isinstance(model, Oscillator) else model.rhs[0].xreplace(TO_ONE)
    return F, model.omegas[0]


def _coupled_member(model) -> bool:
    """Whether ``model`` is a coupled system (an instance of the one type built as a system,
    not one of its named cases of one degree of freedom, or the name of a coupled
    built-in): :func:`derive` then runs the general engine."""

    from ..model.builtins import MODELS
    from ..model.oscillator import Oscillator

    if isinstance(model, Oscillator) or (isinstance(model, str) and model in MODELS):
        return False  # one degree of freedom: the coupled catalogue (0.3 s) is not imported
    from ..model.coupled_builtins import is_coupled_name
    from ..model.coupled import CoupledOscillators

    return is_coupled_name(model) or (isinstance(model, CoupledOscillators)
                                      and model.case == "system")


@dataclass(frozen=True)
class RawExpansion:
    """The KBM recursion's output before display: coefficients in the algebra's own types.

    Attributes
    ----------
    model
        The ``N = 1`` instance (an :class:`Oscillator`, or a system of one degree of
        freedom read through its general accessors), parameters substituted.
    order
        The order ``N`` of the recursion.
    algebra
        The :class:`~kbm.algebra.base.FourierAlgebra` that ran it.
    A, B
        ``A_1..A_N`` and ``B_1..B_N`` (so ``A[n - 1]`` is ``A_n``), coefficients of
        ``algebra``: for the exact algebra :class:`~kbm.algebra.laurent.Laurent`
        polynomials in ``a`` and the parameters.
    u
        ``u_1..u_N`` (series of ``algebra``); ``u_N`` is left out when the
        recursion was run with ``last_u=False``.
    """

    model: Oscillator
    order: int
    algebra: FourierAlgebra
    A: tuple
    B: tuple
    u: tuple

    @property
    def exact(self) -> bool:
        """Whether the coefficients are exact rational algebra (polynomial ``F``)."""
        return self.algebra.exact


def run_recursion(model: Oscillator | str, order: int, params: dict | None = None, *,
                  last_u: bool = True) -> RawExpansion:
    """Validate the input, choose the algebra and run the recursion to ``order``.

    The arguments and errors are those of :func:`derive`; ``last_u=False`` skips
    the last (most costly) ``u_N`` when only the rates are needed.
    """
    if isinstance(model, str):
        model = get_model(model)
    if params:
        model = model.substitute(params)
    if not isinstance(order, int) or isinstance(order, bool) or order < 1:
        raise OrderError(f"the order must be an integer >= 1, got {order!r}")
    if order > MAX_ORDER:
        raise OrderError(f"order {order} is above the limit {MAX_ORDER} of the symbolic "
                         f"expansion (its cost grows like order^5: order 30 takes ~1.3 s for "
                         f"van der Pol); ask for order <= {MAX_ORDER}")
    if isinstance(model, Oscillator):
        model.require_autonomous("the KBM averaging")
    elif not model.is_autonomous:  # a system's drive of t
        raise NonAutonomousError(
            f"the KBM averaging needs an autonomous model, but {model.name!r} depends on t "
            "explicitly; set the stage velocity v = 0 or drop the time-dependent term")
    F, _ = _one_form(model)
    check_cost(F, order)
    # products of sines and cosines become sums (sin(x) cos(x) = sin(2x)/2): one Bessel
    # sum per term instead of nested ones
    F = sp.expand(TR8(F)) if F.has(sp.sin, sp.cos) else sp.expand(F)
    _check_terms(F)
    polynomial = _is_polynomial(model)
    if not polynomial and order > MAX_ORDER_TRIG:
        raise OrderError(
            f"order {order} is not available symbolically for {model.name!r}: with sin(k x) or "
            f"cos(k x) in F (or coefficients that are not rational, such as pi) the Bessel sums "
            f"stay symbolic to order {MAX_ORDER_TRIG} (order 3 would need sums over three "
            f"indices); every order is evaluated at numeric parameters and amplitudes by "
            f"derive_values(model, order, a, params) (on the command line: --a-range "
            f"AMIN:AMAX with --param values)")
    alg: FourierAlgebra = PolyAlgebra(model) if polynomial else SymAlgebra(model)
    A, B, U = one_angle_recursion(alg, F, order, last_u)
    return RawExpansion(model=model, order=order, algebra=alg, A=tuple(A), B=tuple(B),
                        u=tuple(U))
