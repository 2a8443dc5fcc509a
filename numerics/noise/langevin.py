"""A compiled Langevin integrator for any model of the toolkit, driven sliders included.

The noisy model is the paper's eq. (1) with unit mass,

``x'' + omega0^2 x = mu F(x, x'[, t]) + drive(t) + sqrt(2 D) xi(t)``,
``<xi(t) xi(t')> = delta(t - t')``,

so that for linear damping ``mu`` the temperature is ``kT = D/mu``
(fluctuation-dissipation; Risken, *The Fokker-Planck Equation*, section 10.1) and
``D = 0`` is the deterministic model.  The model's expressions (:mod:`kbm` defines
them once) are printed into a small module with every parameter an argument (the
stage velocity ``v`` of the sliders too, so one compilation serves a whole friction
map) and the kernels of :mod:`numerics.noise._kernels`; numba compiles it, and the
machine code is cached on disk under the SHA-256 of the source
(:func:`numerics.flow.numba_cache.cache_dir`; the printing and compiling:
:mod:`numerics.noise.codegen`).  The scheme is Kloeden and Platen's explicit
order-2.0 weak scheme for additive noise, eq. (15.1.3); its weak order is measured
in ``tests/test_langevin.py``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import sympy as sp

from kbm.parameters.bound import BoundModel, bind
from kbm.parameters.names import noise_intensity
from kbm.errors import ParameterError
from kbm.model.builtins import SLIDERS, Oscillator
from kbm.parameters.values import parameter_value

from .codegen import _STAGE_V, _compiled, _scheme, _symbolic, python_accel
from .seeds import trajectory_states

__all__ = ["LangevinSystem", "langevin_system", "split_noise", "natural_step", "HEATING_TOLERANCE"]

#: the relative error of the temperature that the default step allows (:func:`natural_step`)
HEATING_TOLERANCE = 1e-3


def split_noise(params: Mapping[str, object] | None,
                need: str | None = None) -> tuple[dict, float]:
    """``(params without D, D)`` from a parameter mapping that holds ``D``; ``need``: why
    ``D = 0`` is refused (``None``: it is accepted, the deterministic model).

    Raises
    ------
    kbm.errors.ParameterError
        When ``D`` is missing or not a number ``>= 0``, or is 0 and ``need`` is given.
    """
    params = dict(params or {})
    if "D" not in params:
        raise ParameterError("give the noise intensity: -p D=VALUE (x'' + ... = sqrt(2 D) xi, "
                             "D >= 0)")
    return params, noise_intensity(params.pop("D"), need)


@dataclass(frozen=True)
class LangevinSystem:
    """A model at bound parameter values with noise ``sqrt(2 D) xi``, compiled.

    Attributes
    ----------
    bound : kbm.parameters.bound.BoundModel
        The model and its parameter values (``mu`` included).
    D : float
        The noise intensity.
    names : tuple of str
        The compiled module's parameter order.
    p : tuple of float
        The parameter values in that order.
    omega0 : float
        The linear frequency (``a^2 = x^2 + (x'/omega0)^2``).
    """

    bound: BoundModel
    D: float
    names: tuple
    p: tuple
    omega0: float
    symbolic: Oscillator
    scheme: str = "kp"

    def __repr__(self) -> str:
        vals = ", ".join(f"{n}={v:g}" for n, v in zip(self.names, self.p))
        return f"LangevinSystem({self.bound.name}, D={self.D:g}, {vals})"

    @property
    def sigma(self) -> float:
        """The noise amplitude ``sqrt(2 D)``."""
        return math.sqrt(2.0 * self.D)

    @property
    def kernels(self):
        """The compiled module (:mod:`numerics.noise._kernels` on this model)."""
        return _compiled(self.symbolic, self.names, self.scheme)

    def _p(self) -> tuple:
        return tuple(float(v) for v in self.p)  # a tuple: the values live in registers

    def final_states(self, y0, t_end: float, dt: float, *, seed: int = 0,
                     first: int = 0) -> np.ndarray:
        """States at ``t_end`` of trajectories ``first, first+1, ...`` from the rows of ``y0``.

        Parameters
        ----------
        y0 : array_like, shape (m, 2)
        t_end, dt : float
            ``t_end`` must be a whole number of steps ``dt``.
        seed : int
            Root seed; trajectory ``first + i`` uses its own spawned ``SeedSequence``.
        """
        n = steps_of(t_end, dt)
        y0 = np.ascontiguousarray(np.atleast_2d(np.asarray(y0, float)))
        states = trajectory_states(seed, first, y0.shape[0])
        return self.kernels.final_states(self._p(), self.sigma, y0, 0.0, float(dt), n, states)

    def path(self, y0, t_end: float, dt: float, *, stride: int = 1, seed: int = 0,
             index: int = 0) -> tuple[np.ndarray, np.ndarray]:
        """``(t, y)`` of trajectory ``index`` sampled every ``stride`` steps."""
        n = steps_of(t_end, dt)
        states = trajectory_states(seed, index, 1)[0]
        y = self.kernels.sample_path(self._p(), self.sigma, np.asarray(y0, float), 0.0,
                                     float(dt), n, int(stride), states)
        return np.arange(y.shape[0]) * stride * float(dt), y


def steps_of(t_end: float, dt: float) -> int:
    """``t_end/dt`` as a whole number of steps.

    Raises
    ------
    kbm.errors.ParameterError
        When ``dt`` or ``t_end`` is not positive and finite, or ``t_end/dt`` is not a
        whole number (to 1e-9).
    """
    for name, val in (("t_end", t_end), ("dt", dt)):
        if not (isinstance(val, (int, float)) and math.isfinite(val) and val > 0):
            raise ParameterError(f"{name} must be a positive number, got {val!r}")
    n = round(t_end / dt)
    if n < 1 or abs(n * dt - t_end) > 1e-9 * t_end:
        raise ParameterError(f"t_end = {t_end} is not a whole number of steps dt = {dt}")
    return int(n)


def langevin_system(model: Oscillator | str, params: Mapping[str, object] | None = None,
                    D: object | None = None, scheme: str = "kp") -> LangevinSystem:
    """The compiled noisy model ``x'' = f(t, x, x') + sqrt(2 D) xi``.

    Parameters
    ----------
    model : str or kbm.model.builtins.Oscillator
        A built-in name (a slider's stage velocity ``v`` is a parameter) or a model.
    params : mapping
        Parameter values, ``mu`` included; ``D`` among them when not given apart.
    D : float, optional
        The noise intensity (``>= 0``).
    scheme : {"kp", "baoab", "auto"}
        ``"kp"``: Kloeden-Platen's weak order-2 scheme (any model, two force evaluations
        per step); ``"baoab"``: BAOAB with the friction part solved exactly (weak order 2,
        one force evaluation per step; models with ``x''`` affine in ``x'`` only);
        ``"auto"``: BAOAB where it applies, else Kloeden-Platen.

    Raises
    ------
    kbm.errors.ParameterError
        A missing or bad value (``D < 0``, NaN), or a parameter named ``D`` in the model.
    kbm.errors.ModelError
        A model with a term that cannot be compiled.
    """
    params = dict(params or {})
    if D is None:
        params, D = split_noise(params)
    else:
        D = noise_intensity(D)
        params.pop("D", None)
    at_rest = (isinstance(model, str) and model in SLIDERS
               and float(parameter_value("v", params.get("v", 0))) == 0)
    sym = _symbolic(model, at_rest)
    if "D" in sym.parameters:
        raise ParameterError(f"model {sym.name!r} has a parameter named D, the noise intensity's "
                             "name; rename it")
    bm = bind(model, params).require(what="a Langevin simulation")
    names = tuple(sorted(set(sym.parameters) | {"mu"}))
    floats = bm.floats
    if _STAGE_V.name in names and _STAGE_V.name not in floats:
        floats["v"] = float(parameter_value("v", params.get("v", 0)))
    missing = [n for n in names if n not in floats]
    if missing:
        raise ParameterError(f"model {sym.name!r} needs values for {', '.join(missing)} for a "
                             "Langevin simulation")
    p = tuple(float(floats[n]) for n in names)
    w0 = float(sp.sympify(sym.omega0).subs({sp.Symbol(n): v for n, v in zip(names, p)}))
    return LangevinSystem(bm, float(D), names, p, w0, sym, _scheme(sym, scheme))


def natural_step(system: LangevinSystem, *, per_period: int = 50,
                 tolerance: float = HEATING_TOLERANCE) -> float:
    """The default time step: the smaller of the fastest linear period over ``per_period``
    and the step whose numerical heating stays below ``tolerance`` of the temperature.

    The scheme's deterministic part (Heun) multiplies the energy of an oscillation of
    frequency ``w`` by ``|1 + z + z^2/2|^2 = 1 + (w h)^4/4`` per step (``z = i w h``): a
    heating rate ``(w h)^4/(4 h)`` against the damping rate ``|mu|``, so the stationary
    temperature is off by about ``(w h)^4/(4 h |mu|)``.  With ``mu = 0.01`` and the CDC's well
    frequency 4.45 (Delta = 3) the period/40 step gave a 22 % hotter slider and escape
    rates 2.5 times too high at ``E_b/kT = 8``; hence ``h = (4 |mu| tolerance/w^4)^(1/3)``
    when it is smaller.
    """
    p = system._p()
    accel = python_accel(system.symbolic, system.names)  # the compiled accel's source, uncompiled
    eps = 1e-6
    stiff = -(accel(0.0, eps, 0.0, p) - accel(0.0, -eps, 0.0, p)) / (2 * eps)
    w = max(system.omega0, math.sqrt(max(stiff, 0.0)))
    h = 2 * math.pi / w / per_period
    mu = abs(system.bound.mu or 0.0)
    if mu > 0:
        h = min(h, (4 * mu * tolerance / w**4) ** (1 / 3))
    return h
