"""The built-in forced models (names used on the command line), see :mod:`kbm.model.forced`.

``duffing-forced``  ``F = -2 zeta x' - alpha x^3 + h cos(theta)`` (Nayfeh & Mook 4.1), 1/1
``duffing-super``   the same near ``nu = omega0/3`` (superharmonic), 1/3
``mathieu``         ``F = -x cos(theta)``, ``omega0 = 1/2`` (x'' + (delta + eps cos t) x = 0
                    near delta = 1/4), 2/1
``vdp-forced``      ``F = (1 - x^2) x' + h cos(theta)`` (entrainment), 1/1
``parametric``      ``F = -2 zeta x' - alpha x^3 - h x cos(theta)``, 2/1
``duffing-super-hard``  ``F = -2 zeta x' - alpha x^3`` and the hard forcing ``K cos(theta)``,
                    1/3 (Nayfeh & Mook 4.1.2)
``duffing-sub-hard``    the same near ``nu = 3 omega0``, 3/1 (Nayfeh & Mook 4.1.3)
``mathieu-2``       ``F = -x cos(theta)``, ``omega0 = 1`` (the Mathieu tongue at delta = 1,
                    opening at order 2), 1/1
``mathieu-3``       ``F = -x cos(theta)``, ``omega0 = 3/2`` (the tongue at delta = 9/4,
                    opening at order 3), 2/3
``slider``          the self-excited slider (``sedf_comoving``) seen from its stage:
                    ``F = (1 - beta x^2)(x' + nu/k) - delta sin(k x + theta)``,
                    ``omega0 = Omega``, 1/1 (numeric backend)
``slider-cdc``      the constant-damping slider (CDC, eq. 12) seen from its stage:
                    ``F = -(x' + nu/k) - delta sin(k x + theta)``, 1/1 (numeric backend)

The sliders: the paper's eq. (3) with the self-excitation attached to the stage
(``x'' + mu (beta (X - v t)^2 - 1) X' + Delta sin(k X) + Omega^2 (X - v t) = 0``, ``k =
2 pi/lam``, ``Delta = mu delta``) written for the spring's extension ``x = X - v t``:
``x'' + Omega^2 x = mu F`` with the washboard angle ``theta = k v t``, so the forcing
frequency is ``nu = k v = 2 pi v/lam`` and the stage velocity ``v = nu/k`` enters ``F``.
Near ``nu = Omega`` the self-oscillation locks to the washboard (1/1), near
``nu = 2 Omega`` the washboard pumps it parametrically (2/1).
"""

from __future__ import annotations

from collections.abc import Mapping

import sympy as sp

from ..errors import ModelError
from ..symbols import x, xdot
from .forced import ForcedOscillator, Resonance, theta

__all__ = ["FORCED_MODELS", "get_forced_model"]

_zeta, _alpha, _h, _K = sp.symbols("zeta alpha h K")
_beta, _delta, _k, _Omega = sp.symbols("beta delta k Omega")
_nu = sp.Symbol("nu")

FORCED_MODELS = {
    "duffing-forced": lambda: ForcedOscillator(
        "duffing-forced", -2 * _zeta * xdot - _alpha * x**3 + _h * sp.cos(theta),
        resonance=Resonance(1, 1),
        description="Duffing x'' + x = mu (-2 zeta x' - alpha x^3 + h cos nu t), "
                    "Nayfeh & Mook sec. 4.1.1 (primary resonance)"),
    "duffing-super": lambda: ForcedOscillator(
        "duffing-super", -2 * _zeta * xdot - _alpha * x**3 + _h * sp.cos(theta),
        resonance=Resonance(1, 3),
        description="Duffing x'' + x = mu (-2 zeta x' - alpha x^3 + h cos nu t) near "
                    "nu = 1/3 (superharmonic resonance; weak forcing: order >= 3)"),
    "mathieu": lambda: ForcedOscillator(
        "mathieu", -x * sp.cos(theta), omega0=sp.Rational(1, 2), resonance=Resonance(2, 1),
        description="Mathieu x'' + (1/4) x = -mu x cos(nu t), i.e. x'' + (delta + eps cos s) x "
                    "= 0 with s = nu t, delta = 1/(4 nu^2), eps = mu/nu^2"),
    "vdp-forced": lambda: ForcedOscillator(
        "vdp-forced", (1 - x**2) * xdot + _h * sp.cos(theta), resonance=Resonance(1, 1),
        description="forced van der Pol x'' - mu (1 - x^2) x' + x = mu h cos nu t "
                    "(entrainment)"),
    "duffing-super-hard": lambda: ForcedOscillator(
        "duffing-super-hard", -2 * _zeta * xdot - _alpha * x**3, resonance=Resonance(1, 3),
        hard=_K,
        description="Duffing x'' + x = mu (-2 zeta x' - alpha x^3) + K cos nu t near "
                    "nu = 1/3 (superharmonic resonance, hard excitation; Nayfeh & Mook "
                    "4.1.2)"),
    "duffing-sub-hard": lambda: ForcedOscillator(
        "duffing-sub-hard", -2 * _zeta * xdot - _alpha * x**3, resonance=Resonance(3, 1),
        hard=_K,
        description="Duffing x'' + x = mu (-2 zeta x' - alpha x^3) + K cos nu t near "
                    "nu = 3 (subharmonic resonance, hard excitation; Nayfeh & Mook 4.1.3)"),
    "parametric": lambda: ForcedOscillator(
        "parametric", -2 * _zeta * xdot - _alpha * x**3 - _h * x * sp.cos(theta),
        resonance=Resonance(2, 1),
        description="parametrically excited Duffing x'' + x = mu (-2 zeta x' - alpha x^3 "
                    "- h x cos nu t), principal parametric resonance"),
    "mathieu-2": lambda: ForcedOscillator(
        "mathieu-2", -x * sp.cos(theta), omega0=sp.Integer(1), resonance=Resonance(1, 1),
        description="Mathieu x'' + x = -mu x cos(nu t), i.e. x'' + (delta + eps cos s) x = 0 "
                    "with s = nu t, delta = 1/nu^2, eps = mu/nu^2: the second tongue "
                    "(delta = 1, width O(eps^2): order >= 2)"),
    "mathieu-3": lambda: ForcedOscillator(
        "mathieu-3", -x * sp.cos(theta), omega0=sp.Rational(3, 2), resonance=Resonance(2, 3),
        description="Mathieu x'' + (9/4) x = -mu x cos(nu t), i.e. x'' + (delta + eps cos s) x "
                    "= 0 with s = nu t, delta = 9/(4 nu^2), eps = mu/nu^2: the third tongue "
                    "(delta = 9/4, width O(eps^3): order >= 3)"),
    "slider": lambda: ForcedOscillator(
        "slider", (1 - _beta * x**2) * (xdot + _nu / _k) - _delta * sp.sin(_k * x + theta),
        omega0=_Omega, resonance=Resonance(1, 1), defaults={"Omega": 1, "beta": 1},
        description="self-excited slider seen from its stage (x = X - v t, theta = k v t, "
                    "nu = k v): x'' + Omega^2 x = mu ((1 - beta x^2)(x' + v) - delta "
                    "sin(k x + theta)), the paper's eq. 3 with the self-excitation on the "
                    "spring's extension"),
    "slider-cdc": lambda: ForcedOscillator(
        "slider-cdc", -(xdot + _nu / _k) - _delta * sp.sin(_k * x + theta),
        omega0=_Omega, resonance=Resonance(1, 1), defaults={"Omega": 1},
        description="constant-damping slider (eq. 12) seen from its stage: x'' + Omega^2 x "
                    "= mu (-(x' + v) - delta sin(k x + theta)), nu = k v"),
}


def get_forced_model(name: str, params: Mapping[str, object] | None = None) -> ForcedOscillator:
    """A built-in forced model (see the module docstring), optionally with parameters set.

    Raises
    ------
    kbm.errors.ModelError
        For an unknown name (the known ones listed).
    """
    try:
        model = FORCED_MODELS[name]()
    except KeyError:
        raise ModelError(f"unknown forced model {name!r}; the built-in forced models are "
                         f"{', '.join(FORCED_MODELS)} (or add a forcing to any model with "
                         "--forcing EXPR in theta)") from None
    return model.substitute(params) if params else model
