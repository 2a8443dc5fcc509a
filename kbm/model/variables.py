"""The symbols of ``N`` degrees of freedom: the state ``x1..xN``, ``xdot1..xdotN`` of
:class:`~kbm.model.coupled.CoupledOscillators` and the KBM amplitudes ``a1..aN`` and phases
``psi1..psiN`` of its averaged flow, and the check that right-hand sides use them as such
(:func:`check_right_hand_sides`)."""

from __future__ import annotations

import re
from collections.abc import Sequence

import sympy as sp

from ..errors import ModelError
from ..symbols import mu, parse, t, x, xdot
from ..parameters.values import parameter_value

__all__ = ["positions", "velocities", "amplitudes", "phases", "check_right_hand_sides",
           "read_system", "read_exprs", "read_frequency", "MAX_DOF"]

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


#: most degrees of freedom a model may have (the compiled flows and shooting are 2N
#: dimensional; the symbolic averaging has its own, lower, limit)
MAX_DOF = 256
_THETA, _NU = sp.Symbol("theta"), sp.Symbol("nu")


def read_frequency(value: object, i: int | str) -> sp.Rational:
    name = i if isinstance(i, str) else f"omega{i}"
    w = parameter_value(name, value) if not isinstance(value, sp.Basic) else value
    if not (w.is_Rational and w > 0):
        raise ModelError(f"{name} must be a positive rational number (internal resonances "
                         f"are exact ratios of the frequencies), got {value!r}")
    return w


def read_exprs(values, n: int, what: str) -> tuple:
    out = tuple(parse(v) if isinstance(v, str) else sp.sympify(v) for v in values)
    if out and len(out) != n:
        raise ModelError(f"{n} right-hand sides but {len(out)} {what}; give one per degree "
                         "of freedom (0 for none)")
    return out if any(v != 0 for v in out) else ()


def read_system(name: str, F, omega0, nu0, internal, drive, hard) -> tuple:
    """The right-hand sides, frequencies, ``nu0``, resonances, drives and hard forcings of a
    system of ``N = len(F)`` degrees of freedom, read and checked
    (:class:`~kbm.model.coupled.CoupledOscillators`).

    Raises
    ------
    kbm.errors.ModelError
        Naming what to change.
    """
    from ..expansion.resonance import InternalResonance

    if isinstance(F, (str, sp.Basic)) or not isinstance(F, Sequence):
        raise ModelError("F must be a sequence of right-hand sides, one per degree of "
                         "freedom")
    F = tuple(parse(f) if isinstance(f, str) else sp.sympify(f) for f in F)
    n = len(F)
    if not 1 <= n <= MAX_DOF:
        raise ModelError(f"a coupled model has 1 to {MAX_DOF} degrees of freedom, got {n}")
    w = (omega0,) if not isinstance(omega0, Sequence) or isinstance(omega0, str) \
        else omega0
    if len(w) != n:
        raise ModelError(f"{n} right-hand sides but {len(w)} frequencies omega0: give one "
                         f"frequency per degree of freedom (e.g. --omega0 "
                         f"{','.join(['1'] * n)})")
    w = tuple(read_frequency(v, i) for i, v in enumerate(w, 1))
    forced = nu0 is not None
    nu0 = read_frequency(nu0, "nu0") if forced else None
    internal = tuple(r if isinstance(r, InternalResonance) else
                     InternalResonance.parse(r, n, forced=forced) for r in internal)
    for r in internal:
        r.check(w + ((nu0,) if forced else ()))
    drive = read_exprs(drive, n, "drives")
    state = set(positions(n)) | set(velocities(n))
    for d in drive:
        if d.free_symbols & (state | {mu}):
            raise ModelError(f"the drive {d} must depend on t and parameters only")
    hard = read_exprs(hard, n, "hard forcing amplitudes")
    if hard and not forced:
        raise ModelError("a hard forcing K_i cos(theta) needs the forcing frequency: give "
                         "nu0 (theta = nu t, nu = nu0 + mu sigma)")
    for k in hard:
        if k.free_symbols & (state | {mu, t, _THETA, _NU}):
            raise ModelError(f"the hard forcing amplitude {k} must be a constant (numbers "
                             "and parameters)")
    check_right_hand_sides(F, name, forced)
    return F, w, nu0, internal, drive, hard
