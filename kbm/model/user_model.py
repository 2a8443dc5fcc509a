"""A user's oscillator ``x'' + omega0^2 x = mu F`` read from the expression ``F``
(``kbm derive --rhs``, :func:`custom_model`), and the check that refuses an ``F`` whose
state variables are misnamed (:func:`check_state_names`)."""

from __future__ import annotations

import sympy as sp

from ..errors import ModelError
from .oscillator import Oscillator, _expr
from ..symbols import parse, x, xdot

__all__ = ["custom_model", "check_state_names", "STATE_LIKE_NAMES"]


def custom_model(rhs: str | sp.Expr, *, omega0: object = 1, name: str = "custom") -> Oscillator:
    """A user's oscillator ``x'' + omega0**2 x = mu F`` from the expression ``F``.

    Parameters
    ----------
    rhs
        ``F`` as a string or sympy expression in ``x``, ``xdot`` and parameters.
    omega0
        The linear natural frequency (default 1).

    Raises
    ------
    kbm.errors.ModelError
        If the expression cannot be read or uses ``mu``, ``a`` or ``psi``, or
        ``omega0`` is not a positive number (or an expression in parameters).

    Examples
    --------
    >>> custom_model("-x**3 + (1 - x**2)*xdot").F
    -x**3 + xdot*(1 - x**2)
    """
    w0 = omega0
    if isinstance(omega0, str):
        try:  # a decimal number is read exactly: "1.5" is 3/2
            w0 = sp.Rational(omega0.strip())
        except (TypeError, ValueError, ZeroDivisionError):  # "1/0" is refused by parse
            w0 = parse(omega0)
    w0 = _expr(w0)
    if w0.has(x, xdot):
        raise ModelError(f"omega0 must not depend on x or xdot, got {omega0!r}")
    if w0.is_number and not (w0.is_real and w0.is_finite and w0 > 0):
        raise ModelError(f"omega0 must be a positive number (the linear frequency), got "
                         f"{omega0!r}")
    F = parse(rhs)
    check_state_names(F, rhs)
    return Oscillator(name, F, omega0=w0,
                      description=f"user model x'' + {omega0}^2 x = mu ({rhs})")


#: names a user may mean as the state but that would be read as parameters: refused in a
#: user's F with the state variables named (``v`` is also the stage velocity of the sliders)
STATE_LIKE_NAMES = ("v", "y", "u", "dx", "xd", "xp", "dxdt", "vel", "velocity", "x_dot",
                    "xprime", "dotx", "ydot", "X", "Xdot", "xdot_", "xddot")


def check_state_names(F: sp.Expr, text: object = None) -> None:
    """Refuse a user's ``F`` (other than 0) that depends on neither ``x`` nor ``xdot``, or uses a name that
    reads as a state variable (:data:`STATE_LIKE_NAMES`), naming the state variables.

    Without this, ``"v - v**3/3"`` (Rayleigh's damping meant in the velocity) is read with
    ``v`` as a parameter: F is then a constant and the averaging answers ``A_1 = 0``
    silently.

    Raises
    ------
    kbm.errors.ModelError
    """
    shown = F if text is None else text
    bad = sorted(s.name for s in F.free_symbols if s.name in STATE_LIKE_NAMES)
    if bad:
        raise ModelError(f"F = {shown} uses {', '.join(map(repr, bad))}, which would be read as "
                         "a parameter: the state variables are x (displacement) and xdot "
                         "(velocity), and t (time) for a driven model; write e.g. "
                         "'xdot - xdot**3/3'")
    if F != 0 and not F.has(x, xdot):  # F = 0 is the harmonic oscillator, exactly
        raise ModelError(f"F = {shown} depends on neither x nor xdot, so the averaging has "
                         "nothing to act on: the state variables are x (displacement) and "
                         "xdot (velocity), e.g. '(1 - x**2)*xdot'")
