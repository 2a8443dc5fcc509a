"""The admissibility checks of a forced model's ``F``: periodic in ``theta``, smooth in the
state, polynomial in the forcing frequency ``nu`` (:class:`~kbm.model.forced.ForcedOscillator`
runs them; each refusal names the term and the reason), and whether the exact engine applies
(:func:`is_polynomial`)."""

from __future__ import annotations

import sympy as sp

from ..errors import NonAutonomousError, UnsupportedTermError
from ..symbols import t, x, xdot

__all__ = ["NonPeriodicError", "check_theta", "check_state", "is_polynomial",
           "polynomial_message", "theta", "nu"]

#: the forcing angle ``theta = nu t``
theta = sp.Symbol("theta")
#: the forcing frequency
nu = sp.Symbol("nu")


class NonPeriodicError(NonAutonomousError):
    """The time dependence of ``F`` is not a 2 pi-periodic function of ``theta = nu t``."""


def check_theta(F: sp.Expr, name: str) -> None:
    """Refuse time dependence that is not 2 pi-periodic in ``theta`` (the reason named)."""
    if t in F.free_symbols:
        bad = [term for term in sp.Add.make_args(sp.expand(F)) if term.has(t)]
        raise NonPeriodicError(
            f"F of model {name!r} depends on the time t itself ({bad[0]}): a forcing must be "
            "2*pi-periodic in theta = nu*t, and a term in t (t*x, exp(t)) grows or decays "
            "instead; write the drive through theta, e.g. h*cos(theta) or x*cos(2*theta)")

    def walk(e: sp.Expr) -> None:
        if not e.has(theta):
            return
        if e == theta:
            raise NonPeriodicError(
                f"F of model {name!r} has theta outside sin/cos: a term that grows with "
                "theta = nu*t is not a periodic forcing; use sin(k*theta), cos(k*theta)")
        if isinstance(e, (sp.sin, sp.cos)):
            arg = sp.expand(e.args[0])
            k = arg.coeff(theta)
            rest = sp.expand(arg - k * theta)
            if rest.has(theta) or not k.is_number:
                raise NonPeriodicError(
                    f"the term {e} of F is not a periodic forcing: the argument of sin/cos "
                    "must be k*theta + (a function of x, xdot) with an integer k")
            if not k.is_Integer:
                raise NonPeriodicError(
                    f"the term {e} of F is not 2*pi-periodic in theta (k = {k} is not an "
                    "integer); rescale the forcing frequency nu so that every frequency of the "
                    "drive is an integer multiple of nu")
            return
        if e.is_Pow and e.exp.has(theta):
            raise NonPeriodicError(
                f"the term {e} of F is not a periodic forcing: theta = nu*t may enter only "
                "through sin(k*theta + ...) and cos(k*theta + ...) with integer k")
        if e.is_Add or e.is_Mul or e.is_Pow:
            for arg in e.args:
                walk(arg)
            return
        for arg in e.args:  # another function: periodic when its arguments are
            try:
                walk(arg)
            except NonPeriodicError:
                raise NonPeriodicError(
                    f"the term {e} of F is not a periodic forcing: theta = nu*t may enter only "
                    "through sin(k*theta + ...) and cos(k*theta + ...) with integer k (exp, "
                    "powers of theta, ... are not 2*pi-periodic)") from None

    walk(F)


def check_state(F: sp.Expr, name: str) -> None:
    """``F`` must be smooth in ``x``, ``x'`` (a step or kink is refused with its smooth
    replacement) and may hold the forcing frequency ``nu`` only polynomially."""
    from .smooth_terms import non_smooth_message, non_smooth_term

    bad = non_smooth_term(F)
    if bad is not None:
        raise UnsupportedTermError(non_smooth_message(bad))
    if nu in F.free_symbols:
        for f in sp.preorder_traversal(F):
            if isinstance(f, sp.Function) and f.has(nu):
                raise UnsupportedTermError(
                    f"the term {f} of F (model {name!r}) holds the forcing frequency nu inside "
                    "a function: nu may enter F only polynomially (e.g. a stage velocity "
                    "v = nu/k), since nu = (p/q) omega0 + mu sigma is expanded in mu")
        try:
            sp.Poly(F, nu)
        except sp.PolynomialError:
            raise UnsupportedTermError(
                f"F of model {name!r} is not a polynomial in the forcing frequency nu ({F}); "
                "nu may enter F only polynomially") from None


def _non_polynomial_factor(F: sp.Expr) -> sp.Expr | None:
    """The first factor of a term of ``F`` that is not a power of ``x`` or ``xdot`` (and
    holds them), or ``None``."""
    for term in sp.Add.make_args(sp.expand(F)):
        for f in sp.Mul.make_args(term):
            if not f.has(x, xdot) or f in (x, xdot):
                continue
            if f.is_Pow and f.base in (x, xdot) and f.exp.is_Integer and f.exp > 0:
                continue
            return f
    return None


def is_polynomial(F: sp.Expr) -> bool:
    """Whether ``F`` is a polynomial in ``x`` and ``xdot`` (coefficients may hold theta):
    the case of the exact forced engine (:func:`kbm.expansion.forced.derive_forced`)."""
    return _non_polynomial_factor(F) is None


def polynomial_message(F: sp.Expr, name: str) -> str:
    """Why the exact engine refuses ``F`` and what to use instead."""
    f = _non_polynomial_factor(F)
    return (f"the term {f} of F (model {name!r}) is not polynomial in x and xdot, "
            "so the exact (rational) forced engine does not apply; use the numeric "
            "forced backend kbm.backend.forced.numeric_derive_forced(model, order, "
            "a_range, params) (on the command line: kbm response with "
            "--a-range AMIN:AMAX), which takes any smooth F such as sin(k*x + theta)")
