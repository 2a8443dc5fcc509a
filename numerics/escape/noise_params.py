"""The noise level and the small parameter of a noisy model, checked before any work, and the
exception of a model with no stationary state (split from :mod:`numerics.escape.envelope`).

Convention: ``x'' + ... = sqrt(2 D) xi(t)``, ``<xi(t) xi(t')> = delta(t - t')``.
"""

from __future__ import annotations

import math

import sympy as sp
from kbm.errors import ModelError, ParameterError

__all__ = ["NoStationaryState", "noise_level", "check_mu"]


class NoStationaryState(ModelError):
    """The noisy model has no stationary state (no damping, ``A_1 = 0``, a drift that does
    not confine the amplitude or the energy, or a potential that does not confine): raised
    before any simulation, with the reason."""


def noise_level(D: object) -> float:
    """``D`` as a float, refused when negative or not finite.

    Raises
    ------
    kbm.errors.ParameterError
    """
    try:
        val = float(D)
    except (TypeError, ValueError):
        raise ParameterError(f"D must be a number, got {D!r} (e.g. -p D=0.01)") from None
    if not math.isfinite(val) or val < 0:
        raise ParameterError(f"D = {val:g}: the noise intensity must be finite and >= 0 "
                             "(x'' + ... = sqrt(2 D) xi(t); e.g. -p D=0.01)")
    return val


def check_mu(params: dict) -> None:
    """Refuse ``mu <= 0`` (and a ``D`` that is infinite or NaN) before any work.

    ``mu`` is the small parameter of ``x'' + omega0^2 x = mu F``: ``mu < 0`` turns the
    damping into a drive (no stationary state), ``mu = 0`` leaves the noise unbalanced.

    Raises
    ------
    kbm.errors.ParameterError
    """
    for key in ("D", "mu"):
        if key not in params:
            continue
        try:
            val = float(params[key])  # "inf", "nan" included
        except (TypeError, ValueError):
            try:
                val = float(sp.sympify(params[key]))
            except (TypeError, ValueError, sp.SympifyError):
                continue  # the parser of the model says what is wrong
        if not math.isfinite(val):
            what = ("finite and >= 0 (the noise intensity of sqrt(2 D) xi)" if key == "D"
                    else "a finite number > 0")
            raise ParameterError(f"{key} = {params[key]} must be {what}; e.g. -p {key}=0.1")
        if key == "mu" and val <= 0:
            raise ParameterError(
                f"mu = {params[key]}: the small parameter must be > 0 (x'' + omega0^2 x = mu "
                "F; mu < 0 turns the damping into a drive and mu = 0 leaves the noise "
                "unbalanced: no stationary state); give mu > 0")
