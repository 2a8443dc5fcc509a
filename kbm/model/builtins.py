"""Weakly nonlinear oscillators ``x'' + w0^2 x = eps F(x, x')``, defined once, symbolically.

Every model of the toolkit is an :class:`Oscillator`: the right-hand side ``F``
is a sympy expression in the symbols ``x``, ``xdot`` (and ``t`` for a driven,
non-autonomous model) and named parameters; the small parameter is ``mu``
(the paper's mu, epsilon in the textbooks).  The averaging in :mod:`kbm`
and the integrators in :mod:`numerics` both start from this one definition.

Built-in models (names used on the command line):

``vdp``               van der Pol, ``F = (1 - x^2) x'``
``duffing``           Duffing, ``F = -x^3``
``rayleigh``          Rayleigh, ``F = (1 - x'^2/3) x'`` (its velocity is a van der Pol variable)
``linear_damping``    ``F = -2 zeta x'``
``linear_stiffness``  ``F = -kappa x``
``sedf``              paper eq. (3), self-excited slider: ``F = -(beta x^2 - 1) x' - delta sin(k x)``
``cdc``               paper eq. (12), constant-damping slider: ``F = -x' - delta sin(k x)``
``sedf_comoving``     the SEDF with its self-excitation attached to the stage: equal to ``sedf``
                      at ``v = 0``; pulled, ``F = -(beta (x - v t)^2 - 1) x' - delta sin(k x)``

For ``sedf`` and ``cdc``, ``w0 = Omega``, ``delta = Delta/mu`` and ``k = 2 pi/lam``
(the scaled KBM form of the paper's physical parameters).  With a stage
velocity ``v != 0`` the spring pulls with ``Omega^2 (v t - x)``: the model gets
the drive ``Omega^2 v t`` (not multiplied by ``mu``) on the right-hand side,
``x'' + w0^2 x = mu F + drive(t)``, and is non-autonomous.

The paper's SEDF measures its self-excitation ``mu (beta x^2 - 1) x'`` by the
position ``x`` on the substrate, so a slider pulled over many wells meets an ever
larger damping ``mu beta x^2`` (its friction grows without bound, the paper's Fig. 6)
and has no steady sliding state.  ``sedf_comoving`` attaches the self-excitation to
the stage instead (it is measured by the spring's extension ``x - v t``, the
deflection of a tip from its support), which is invariant under
``x -> x + lam, t -> t + lam/v`` and so has friction laws
(:mod:`numerics.sliding`).

The type is :class:`kbm.model.oscillator.Oscillator`, a user's model
:func:`kbm.model.user_model.custom_model`; this module is the catalogue of built-in models that
instantiate it (all three names are importable from here).  Parameter values are read by
:mod:`kbm.parameters.values` and bound to a model once by :mod:`kbm.parameters.bound`
(:func:`kbm.parameters.bound.bind`), which builds on this module (never the other way round).

References
----------
M. D'Acunto, "Friction force for self-excited systems", eqs. (3), (4), (12).
"""

from __future__ import annotations

from collections.abc import Mapping

import sympy as sp

from ..errors import ModelError, ParameterError
from .oscillator import Oscillator
from ..symbols import mu, x, xdot
from .user_model import STATE_LIKE_NAMES, check_state_names, custom_model
from ..parameters.values import FrozenMap, parameter_value

__all__ = ["Oscillator", "FrozenMap", "MODELS", "SLIDERS", "SLIDER_DEFAULTS", "with_slider_defaults", "get_model",
           "custom_model", "check_state_names", "STATE_LIKE_NAMES", "parameter_value",
           "model_names"]


# ----------------------------------------------------------------------------- built-ins
_beta, _delta, _k, _Omega = sp.symbols("beta delta k Omega")
_zeta, _kappa, _Delta, _lam = sp.symbols("zeta kappa Delta lam")
_PHYSICAL = {"delta": _Delta / mu, "k": 2 * sp.pi / _lam}
_EXCITATION = -(_beta * x**2 - 1) * xdot  # the SEDF's, attached to the stage in sedf_comoving

#: the built-in models by name, each built on first use
MODELS = {
    "vdp": lambda: Oscillator(
        "vdp", (1 - x**2) * xdot,
        description="van der Pol oscillator x'' - mu (1 - x^2) x' + x = 0"),
    "duffing": lambda: Oscillator(
        "duffing", -x**3, description="Duffing oscillator x'' + x + mu x^3 = 0"),
    "rayleigh": lambda: Oscillator(
        "rayleigh", (1 - xdot**2 / 3) * xdot,
        description="Rayleigh oscillator x'' - mu (1 - x'^2/3) x' + x = 0"),
    "linear_damping": lambda: Oscillator(
        "linear_damping", -2 * _zeta * xdot,
        description="linearly damped oscillator x'' + 2 mu zeta x' + x = 0 (exact)"),
    "linear_stiffness": lambda: Oscillator(
        "linear_stiffness", -_kappa * x,
        description="stiffness perturbation x'' + (1 + mu kappa) x = 0 (exact)"),
    "sedf": lambda: Oscillator(
        "sedf", -(_beta * x**2 - 1) * xdot - _delta * sp.sin(_k * x), omega0=_Omega,
        description="self-excited slider on a periodic potential, paper eq. (3) with v = 0: "
                    "x'' + mu (beta x^2 - 1) x' + Delta sin(2 pi x/lam) + Omega^2 x = 0",
        physical=_PHYSICAL, defaults={"Omega": 1}, gain_factor=_beta),
    "cdc": lambda: Oscillator(
        "cdc", -xdot - _delta * sp.sin(_k * x), omega0=_Omega,
        description="constant-damping slider, paper eq. (12) with v = 0: "
                    "x'' + mu x' + Delta sin(2 pi x/lam) + Omega^2 x = 0",
        physical=_PHYSICAL, defaults={"Omega": 1}),
    "sedf_comoving": lambda: Oscillator(
        "sedf_comoving", _EXCITATION - _delta * sp.sin(_k * x), omega0=_Omega,
        description="self-excited slider with the self-excitation attached to the stage, with "
                    "v = 0: x'' + mu (beta (x - v t)^2 - 1) x' + Delta sin(2 pi x/lam) "
                    "+ Omega^2 (x - v t) = 0",
        physical=_PHYSICAL, defaults={"Omega": 1}, gain_factor=_beta,
        stage_relative=_EXCITATION),
}


#: the built-in models that have a stage (their spring can be pulled at a velocity v)
SLIDERS = ("sedf", "cdc", "sedf_comoving")
#: the values of a slider's stage that ``kbm noise``, ``kbm escape`` and ``kbm spectrum``
#: take when they are not given (the paper's Omega = 1 and lam = 1)
SLIDER_DEFAULTS = {"Omega": "1", "lam": "1"}


def with_slider_defaults(model, params: Mapping) -> dict:
    """``params`` with :data:`SLIDER_DEFAULTS` where not given, for a built-in slider
    (:data:`SLIDERS`, by name; any other model's ``params`` unchanged), no ``lam`` where the
    wavenumber ``k = 2 pi/lam`` is given.

    Examples
    --------
    >>> with_slider_defaults("sedf", {"mu": "0.1", "k": "6.283"})
    {'mu': '0.1', 'k': '6.283', 'Omega': '1'}
    >>> with_slider_defaults("vdp", {"mu": "0.1"})
    {'mu': '0.1'}
    """
    out = dict(params)
    if isinstance(model, str) and model in SLIDERS:
        for name, value in SLIDER_DEFAULTS.items():
            if not (name == "lam" and "k" in out):
                out.setdefault(name, value)
    return out


def _drive_variant(model: Oscillator, v: object) -> Oscillator:
    if model.name not in SLIDERS:
        raise ParameterError(f"unknown parameter 'v' for model {model.name!r}; only the "
                             f"sliders {' and '.join(SLIDERS)} have a stage velocity")
    return model.with_stage_velocity(v)


def model_names() -> tuple[str, ...]:
    """Names of the built-in models."""
    return tuple(MODELS)


def get_model(name: str, params: Mapping[str, object] | None = None) -> Oscillator:
    """A built-in model, optionally with some parameters set.

    Parameters
    ----------
    name
        One of :func:`model_names`.
    params
        Parameter values by name; physical names (``Delta``, ``lam``) are
        converted to the scaled ones (``delta = Delta/mu``, ``k = 2 pi/lam``),
        which needs ``mu``.  A stage velocity ``v`` other than 0 (sedf, cdc)
        adds the spring drive ``Omega^2 v t`` and makes the model
        non-autonomous: the averaging refuses it, the integrators accept it.

    Raises
    ------
    kbm.errors.ModelError
        For an unknown model name.
    kbm.errors.ParameterError
        For an unknown parameter or a bad value.

    Examples
    --------
    >>> get_model("sedf", {"beta": 1, "Delta": "3/20", "mu": "1/10", "lam": 1}).F
    xdot*(1 - x**2) - 3*sin(2*pi*x)/2
    """
    try:
        model = MODELS[name]()
    except KeyError:
        raise ModelError(f"unknown model {name!r}; the built-in models are "
                         f"{', '.join(MODELS)} (or give your own F with custom_model)") from None
    params = dict(params or {})
    v = params.pop("v", None)
    if v is not None:
        model = _drive_variant(model, v)
    if params:
        model = model.substitute(params)
    return model
