"""The small parameter of a noisy model, checked before any work (the noise intensity ``D``:
:func:`kbm.parameters.names.noise_intensity`), and the exception of a model with no
stationary state (split from :mod:`numerics.escape.envelope`).

Convention: ``x'' + ... = sqrt(2 D) xi(t)``, ``<xi(t) xi(t')> = delta(t - t')``.
"""

from __future__ import annotations

import math

import sympy as sp
from kbm.errors import ModelError, ParameterError

__all__ = ["NoStationaryState", "check_mu"]


class NoStationaryState(ModelError):
    """The noisy model has no stationary state (no damping, ``A_1 = 0``, a drift that does
    not confine the amplitude or the energy, or a potential that does not confine): raised
    before any simulation, with the reason."""


def check_mu(params: dict) -> None:
    """Refuse ``mu <= 0`` before any work (``D``: :func:`kbm.parameters.names.noise_intensity`).

    ``mu`` is the small parameter of ``x'' + omega0^2 x = mu F``: ``mu < 0`` turns the
    damping into a drive (no stationary state), ``mu = 0`` leaves the noise unbalanced.

    Raises
    ------
    kbm.errors.ParameterError
    """
    if "mu" not in params:
        return
    try:
        val = float(params["mu"])  # "inf", "nan" included
    except (TypeError, ValueError):
        try:
            val = float(sp.sympify(params["mu"]))
        except (TypeError, ValueError, sp.SympifyError):
            return  # the parser of the model says what is wrong
    if not math.isfinite(val):
        raise ParameterError(f"mu = {params['mu']} must be a finite number > 0; e.g. -p mu=0.1")
    if val <= 0:
        raise ParameterError(
            f"mu = {params['mu']}: the small parameter must be > 0 (x'' + omega0^2 x = mu "
            "F; mu < 0 turns the damping into a drive and mu = 0 leaves the noise "
            "unbalanced: no stationary state); give mu > 0")
