"""The full noisy system of ``N`` oscillators, its vector field and an ensemble integrator.

``x_i'' = -omega_i^2 x_i + mu F_i(x, x', theta) + sqrt(2 D) xi_i(t)`` with ``theta = nu t``
and independent white noises ``<xi_i(t) xi_j(t')> = delta_ij delta(t - t')`` (the
convention of :mod:`numerics.noise`: ``kT = D/mu`` for a damping ``mu x'``).  The
right-hand sides come from the one symbolic definition
(:meth:`kbm.coupled.CoupledOscillators.accelerations`), lambdified with their Jacobian.

The paths are advanced by the stochastic Heun scheme for additive noise (Kloeden & Platen,
*Numerical Solution of SDEs*, eq. 15.1.3, weak order 2) with Gaussian increments, all the
trajectories of a chunk at once.  Trajectory ``i`` draws its increments from its own
``SeedSequence(seed, spawn_key=(*stream, i))`` in blocks of :data:`BLOCK` steps, and the
chunks are cut by the data (:data:`CHUNK` trajectories), so a run gives the same bytes on any
executor and worker count.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import sympy as sp

from kbm.coupled import CoupledOscillators
from kbm.errors import ParameterError
from kbm.symbols import t as t_symbol

__all__ = ["NoisySystem", "noisy_system", "generators", "BLOCK", "CHUNK"]

#: steps of noise drawn at a time per trajectory (fixed: the streams do not depend on chunks)
BLOCK = 2048
#: trajectories per chunk of the executor (fixed: the arithmetic does not depend on workers)
CHUNK = 16


@dataclass(frozen=True, eq=False)
class NoisySystem:
    """A coupled (or one-degree-of-freedom) system at bound parameter values, with noise.

    Attributes
    ----------
    model : kbm.coupled.CoupledOscillators
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


def noisy_system(model: CoupledOscillators | str, params: Mapping[str, object],
                 D: float) -> NoisySystem:
    """The bound noisy system (:func:`numerics.coupled.flow.bind_coupled` binds the values).

    Raises
    ------
    kbm.errors.ParameterError
        For an unknown name or a missing value, ``D <= 0``, or a model whose force depends
        on ``t`` other than through ``theta`` (a pulled slider).
    """
    from numerics.coupled.flow import bind_coupled

    D = float(D)
    if not (math.isfinite(D) and D > 0):
        raise ParameterError(f"D = {D:g}: a noise spectrum needs noise, give D > 0 "
                             "(x'' + ... = sqrt(2 D) xi)")
    model, values = bind_coupled(model, params)
    if model.drive or any(f.has(t_symbol) for f in model.F):
        raise ParameterError(f"{model.name!r} depends on t other than through the forcing "
                             "angle theta; the spectra here are for forced or autonomous "
                             "systems")
    n = model.dof
    nu = None
    if model.forced:
        sig = values.get(model.nu_detuning, 0.0) if model.nu_detuning else 0.0
        nu = float(model.nu0) + values["mu"] * sig
    sub = {sp.Symbol(k): v for k, v in values.items()}
    theta = sp.Symbol("theta")
    exprs = [sp.sympify(e).subs(theta, (nu or 0.0) * t_symbol).subs(sub)
             for e in model.accelerations()]
    state = list(model.state)
    args = [t_symbol, *state]
    acc = tuple(sp.lambdify(args, e, "numpy") for e in exprs)
    jac = tuple(tuple(sp.lambdify(args, sp.diff(e, s), "numpy") for s in state) for e in exprs)
    omegas = np.array([float(sp.sympify(w).subs(sub)) for w in model.frequencies()])
    return NoisySystem(model, values, D, nu, omegas, acc, jac)


def generators(seed: int, first: int, count: int, stream: tuple = ()) -> list:
    """One :class:`numpy.random.Generator` per trajectory ``first .. first+count-1``
    (``SeedSequence(seed, spawn_key=(*stream, i))``, numpy's spawning rule)."""
    return [np.random.Generator(np.random.PCG64(np.random.SeedSequence(
        seed, spawn_key=(*stream, first + j)))) for j in range(count)]


def heun_run(system: NoisySystem, y0: np.ndarray, dt: float, n_steps: int, rngs: list,
             observe, *, t0: float = 0.0, quiet_lane: bool = False):
    """Advance the rows of ``y0`` (``m x 2N``) by ``n_steps`` Heun steps; after each step
    ``observe(k, t, y)`` is called with the states (``2N x m``, plus a last noise-free
    column when ``quiet_lane``).

    The noise free lane (the deterministic system under the same scheme) lets a caller
    subtract the scheme's own periodic response from the noisy paths.
    """
    n = system.dof
    m = len(rngs)
    y = np.array(np.asarray(y0, dtype=float).T, dtype=float)  # 2N x (m [+1])
    if quiet_lane:
        y = np.concatenate([y, y[:, :1]], axis=1)
    amp = math.sqrt(2.0 * system.D * dt)
    t = t0
    noise = np.zeros((n, y.shape[1]))
    for start in range(0, n_steps, BLOCK):
        size = min(BLOCK, n_steps - start)
        draws = np.stack([g.standard_normal((size, n)) for g in rngs], axis=2)  # size x n x m
        for k in range(size):
            noise[:, :m] = amp * draws[k]
            f0 = system.field(t, y)
            ybar = y + dt * f0
            ybar[n:] += noise
            f1 = system.field(t + dt, ybar)
            y = y + 0.5 * dt * (f0 + f1)
            y[n:] += noise
            t = t0 + (start + k + 1) * dt
            observe(start + k, t, y)
    return y
