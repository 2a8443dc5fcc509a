"""The symbols of ``N`` degrees of freedom: the state ``x1..xN``, ``xdot1..xdotN`` of
:class:`~kbm.coupled.model.CoupledOscillators` and the KBM amplitudes ``a1..aN`` and phases
``psi1..psiN`` of its averaged flow, and the check that right-hand sides use them as such
(:func:`check_right_hand_sides`)."""

from __future__ import annotations

import re

import sympy as sp

from ..errors import ModelError
from ..symbols import mu, t, x, xdot

__all__ = ["positions", "velocities", "amplitudes", "phases", "check_right_hand_sides"]

_STATE_NAME = re.compile(r"^(x|xdot)\d+$")
_RESERVED = re.compile(r"^(a|psi|gamma)\d+$")


def positions(n: int) -> tuple[sp.Symbol, ...]:
    """``x1, ..., xn``."""
    return tuple(sp.Symbol(f"x{i}") for i in range(1, n + 1))


def velocities(n: int) -> tuple[sp.Symbol, ...]:
    """``xdot1, ..., xdotn``."""
    return tuple(sp.Symbol(f"xdot{i}") for i in range(1, n + 1))


def amplitudes(n: int) -> tuple[sp.Symbol, ...]:
    """``a1, ..., an`` (the KBM amplitudes)."""
    return tuple(sp.Symbol(f"a{i}") for i in range(1, n + 1))


def phases(n: int) -> tuple[sp.Symbol, ...]:
    """``psi1, ..., psin`` (the KBM phases)."""
    return tuple(sp.Symbol(f"psi{i}") for i in range(1, n + 1))


def check_right_hand_sides(F: tuple[sp.Expr, ...], name: str, forced: bool) -> None:
    """Refuse right-hand sides ``F_i`` of a system of ``N = len(F)`` degrees of freedom that
    use a state variable beyond ``N`` (or the single-oscillator ``x``, ``xdot``), ``mu``, a
    name reserved for the KBM amplitudes and phases, or the forcing angle ``theta`` and
    frequency ``nu`` without a forcing.

    Raises
    ------
    kbm.errors.ModelError
        Naming the right-hand side, the symbol and what to change.
    """
    n = len(F)
    state = set(positions(n)) | set(velocities(n))
    theta = sp.Symbol("theta")
    for i, f in enumerate(F, 1):
        if theta in f.free_symbols and not forced:
            raise ModelError(f"F{i} holds the forcing angle theta but the model has no "
                             "forcing frequency: give nu0 (theta = nu t, nu = nu0 + mu "
                             "sigma)")
        if mu in f.free_symbols:
            raise ModelError(f"F{i} of {name!r} contains the small parameter mu; write "
                             "each equation as x_i'' + omega_i^2 x_i = mu*F_i with F_i free "
                             "of mu")
        for s in f.free_symbols - state:
            if s in (x, xdot) or _STATE_NAME.match(s.name):
                raise ModelError(
                    f"F{i} = {f} uses {s.name!r}, which is not a state variable of a "
                    f"system of {n} degrees of freedom: the state is "
                    f"{', '.join(map(str, positions(n)))} and "
                    f"{', '.join(map(str, velocities(n)))}")
            if s == theta or s == t:
                continue
            if s.name == "nu":
                if not forced:
                    raise ModelError(f"F{i} holds the forcing frequency nu but the model "
                                     "has no forcing: give nu0 (nu = nu0 + mu sigma)")
                continue  # the forcing frequency (the sliders' stage velocity nu/k)
            if s.name in ("a", "psi") or _RESERVED.match(s.name):
                raise ModelError(f"the symbol {s.name!r} in F{i} is reserved for the "
                                 "amplitudes, phases and time; rename that parameter")
