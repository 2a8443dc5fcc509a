"""The noisy system of ``N`` oscillators (forced or coupled) and its compiled ensemble paths.

``x_i'' = -omega_i^2 x_i + mu F_i(x, x', theta) + sqrt(2 D) xi_i(t)`` with ``theta = nu t``
and independent white noises ``<xi_i(t) xi_j(t')> = delta_ij delta(t - t')`` (the
convention of :mod:`numerics.noise.langevin`: ``kT = D/mu`` for a damping ``mu x'``).  The
right-hand sides come from the one symbolic definition
(:meth:`kbm.model.coupled.CoupledOscillators.accelerations`): lambdified with their Jacobian for
the deterministic routes, and printed with every parameter an argument into the module of
:func:`numerics.noise.codegen.vector_module`, whose ``vector_paths`` is the scheme of
:mod:`numerics.noise._kernels` (Kloeden & Platen eq. 15.1.3, weak order 2) for ``N``
degrees of freedom.  Trajectory ``i`` draws from its own xoshiro256** stream
(:func:`numerics.noise.seeds.trajectory_states`), so a run gives the same bytes on any
executor and chunking.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import sympy as sp

from kbm.model.coupled import CoupledOscillators
from kbm.errors import ParameterError
from kbm.parameters.names import noise_intensity
from kbm.symbols import t as t_symbol

from .codegen import vector_module
from .seeds import trajectory_states

__all__ = ["NoisySystem", "bound_system", "NOISE_NEED", "CHUNK"]

#: why a noise spectrum refuses ``D = 0`` (:func:`kbm.parameters.names.noise_intensity`)
NOISE_NEED = "a noise spectrum needs noise"

#: trajectories per chunk of the executor (fixed: the arithmetic does not depend on workers)
CHUNK = 16

_THETA, _NU = sp.Symbol("theta"), sp.Symbol("nu")


@dataclass(frozen=True, eq=False)
class NoisySystem:
    """A coupled (or one-degree-of-freedom) system at bound parameter values, with noise.

    Attributes
    ----------
    model : kbm.model.coupled.CoupledOscillators
    values : dict
        Every parameter's value, ``mu`` and the detuning included.
    D : float
        The noise intensity of ``sqrt(2 D) xi`` on every mode.
    nu : float or None
        The forcing frequency (``None``: autonomous).
    omegas : numpy.ndarray
        The linear frequencies ``omega_i`` (detunings of the frequencies included).
    """

    model: CoupledOscillators
    values: Mapping[str, float]
    D: float
    nu: float | None
    omegas: np.ndarray
    _acc: tuple
    _jac: tuple

    @property
    def dof(self) -> int:
        """``N``."""
        return self.model.dof

    def acceleration(self, t: float, y: np.ndarray) -> np.ndarray:
        """``x''`` without the noise at the states ``y`` (``2N`` rows, any trailing shape)."""
        args = (t, *y)
        shape = np.shape(y[0])
        return np.array([np.broadcast_to(f(*args), shape) for f in self._acc], dtype=float)

    def field(self, t: float, y: np.ndarray) -> np.ndarray:
        """The first-order vector field ``(x', x'')`` at ``y`` (``2N`` rows)."""
        n = self.dof
        return np.concatenate([np.asarray(y[n:], dtype=float), self.acceleration(t, y)])

    def jacobian(self, t: float, y: np.ndarray) -> np.ndarray:
        """``d(x', x'')/d(x, x')`` at one state ``y`` (``2N x 2N``)."""
        n = self.dof
        J = np.zeros((2 * n, 2 * n))
        J[:n, n:] = np.eye(n)
        args = (t, *y)
        J[n:, :] = np.array([[float(f(*args)) for f in row] for row in self._jac])
        return J

    def paths(self, y0: np.ndarray, dt: float, n_steps: int, stride: int, *, seed: int,
              first: int = 0, quiet_lane: bool = False) -> np.ndarray:
        """The states (``rows x n_steps//stride x 2N``) every ``stride`` steps of trajectories
        ``first, first+1, ...`` from the rows of ``y0``, each on its own stream of ``seed``
        (a last noise-free row is added when ``quiet_lane``: the deterministic system
        under the same scheme)."""
        names = tuple(sorted(self.values)) + ((_NU.name,) if _NU.name not in self.values else ())
        exprs = tuple(sp.sympify(e).subs(_THETA, _NU * t_symbol)
                      for e in self.model.accelerations())
        module = vector_module(exprs, tuple(self.model.state), names)
        p = tuple(float(self.values[k]) if k in self.values else float(self.nu or 0.0)
                  for k in names)
        y = np.array(np.atleast_2d(np.asarray(y0, dtype=float)), dtype=float)
        m = y.shape[0]
        states = trajectory_states(seed, first, m)
        amps = np.full(m, math.sqrt(2.0 * self.D))
        if quiet_lane:
            y = np.concatenate([y, y[:1]], axis=0)
            states = np.concatenate([states, states[:1]], axis=0)
            amps = np.append(amps, 0.0)
        return module.vector_paths(p, amps, y, 0.0, float(dt), int(n_steps), int(stride),
                                   states)


def bound_system(model: CoupledOscillators, values: Mapping[str, float],
                 D: float) -> NoisySystem:
    """The noisy system of ``model`` at ``values`` (every parameter's value, ``mu``
    included: :func:`numerics.spectrum.driven_sim.noisy_system` binds them).

    Raises
    ------
    kbm.errors.ParameterError
        For ``D <= 0``, or a model whose force depends on ``t`` other than through
        ``theta`` (a pulled slider).
    """
    D = noise_intensity(D, NOISE_NEED)
    if model.drives or any(f.has(t_symbol) for f in model.rhs):
        raise ParameterError(f"{model.name!r} depends on t other than through the forcing "
                             "angle theta; the spectra here are for forced or autonomous "
                             "systems")
    nu = None
    if model.forced:
        sig = values.get(model.nu_detuning, 0.0) if model.nu_detuning else 0.0
        nu = float(model.nu0) + values["mu"] * sig
    sub = {sp.Symbol(k): v for k, v in values.items()}
    exprs = [sp.sympify(e).subs(_THETA, (nu or 0.0) * t_symbol).subs(sub).subs(_NU, nu or 0.0)
             for e in model.accelerations()]
    state = list(model.state)
    args = [t_symbol, *state]
    acc = tuple(sp.lambdify(args, e, "numpy") for e in exprs)
    jac = tuple(tuple(sp.lambdify(args, sp.diff(e, s), "numpy") for s in state) for e in exprs)
    omegas = np.array([float(sp.sympify(w).subs(sub)) for w in model.frequencies()])
    return NoisySystem(model, values, D, nu, omegas, acc, jac)
