"""The admissibility checks of a forced model's ``F``: periodic in ``theta``, polynomial in the
state (:class:`~kbm.forced.model.ForcedOscillator` runs them; each refusal names the term
and the reason)."""

from __future__ import annotations

import sympy as sp

from ..errors import NonAutonomousError, UnsupportedTermError
from ..symbols import t, x, xdot

__all__ = ["NonPeriodicError", "check_theta", "check_state", "theta"]

#: the forcing angle ``theta = nu t``
theta = sp.Symbol("theta")


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
            if rest.has(theta) or rest.has(x, xdot) or not k.is_number:
                raise NonPeriodicError(
                    f"the term {e} of F is not a periodic forcing: the argument of sin/cos "
                    "must be k*theta + constant with an integer k")
            if not k.is_Integer:
                raise NonPeriodicError(
                    f"the term {e} of F is not 2*pi-periodic in theta (k = {k} is not an "
                    "integer); rescale the forcing frequency nu so that every frequency of the "
                    "drive is an integer multiple of nu")
            return
        if e.is_Add or e.is_Mul or (e.is_Pow and e.exp.is_Integer and e.exp > 0):
            for arg in e.args:
                walk(arg)
            return
        raise NonPeriodicError(
            f"the term {e} of F is not a periodic forcing: theta = nu*t may enter only through "
            "sin(k*theta) and cos(k*theta) with integer k (exp, powers of theta, ... are "
            "not 2*pi-periodic)")

    walk(F)


def check_state(F: sp.Expr, name: str) -> None:
    """``F`` must be a polynomial in ``x``, ``x'`` (its coefficients may hold theta)."""
    for term in sp.Add.make_args(sp.expand(F)):
        for f in sp.Mul.make_args(term):
            if not f.has(x, xdot):
                continue
            if f in (x, xdot) or (f.is_Pow and f.base in (x, xdot) and f.exp.is_Integer
                                  and f.exp > 0):
                continue
            raise UnsupportedTermError(
                f"the term {f} of F (model {name!r}) is not supported by the forced KBM "
                "engine: F must be a polynomial in x and xdot whose coefficients are "
                "trigonometric polynomials in theta (sin(k*x), cos(k*x) are treated by the "
                "autonomous engine only); expand or approximate that term")
