"""The full noisy system of ``N`` oscillators, its vector field and an ensemble integrator.

``x_i'' = -omega_i^2 x_i + mu F_i(x, x', theta) + sqrt(2 D) xi_i(t)`` with ``theta = nu t``
and independent white noises ``<xi_i(t) xi_j(t')> = delta_ij delta(t - t')`` (the
convention of :mod:`numerics.noise`: ``kT = D/mu`` for a damping ``mu x'``).  The
right-hand sides come from the one symbolic definition
(:meth:`kbm.coupled.CoupledOscillators.accelerations`), lambdified with their Jacobian.

The paths are advanced by the stochastic Heun scheme for additive noise (Kloeden & Platen,
*Numerical Solution of SDEs*, eq. 15.1.3, weak order 2) with Gaussian increments, all the
trajectories of a chunk by one compiled kernel (numba; the model printed into it with
its values).  Trajectory ``i`` draws its increments from its own
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

__all__ = ["NoisySystem", "noisy_system", "generators", "heun_paths", "BLOCK", "CHUNK"]

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
    if model.drives or any(f.has(t_symbol) for f in model.rhs):
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
             .subs(sp.Symbol("nu"), nu or 0.0) for e in model.accelerations()]
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


def _source(system: NoisySystem) -> str:
    """``acc(t, y, out)``: ``x''`` without the noise at the state ``y`` written into ``out``
    (printed from the model's expressions, common subexpressions shared)."""
    from sympy.printing.pycode import pycode

    n = system.dof
    state = list(system.model.state)
    ys = sp.symbols(f"y_0:{2 * n}")
    sub = dict(zip(state, ys))
    exprs = [sp.sympify(f).subs({sp.Symbol("theta"): (system.nu or 0.0) * t_symbol})
             .subs({sp.Symbol(k): v for k, v in system.values.items()})
             .subs(sp.Symbol("nu"), system.nu or 0.0).subs(sub)
             for f in system.model.accelerations()]
    reps, reduced = sp.cse(exprs)
    lines = ["def acc(t, y, out):"]
    lines += [f"    y_{i} = y[{i}]" for i in range(2 * n)]
    lines += [f"    {a} = {pycode(b)}" for a, b in reps]
    lines += [f"    out[{i}] = {pycode(e)}" for i, e in enumerate(reduced)]
    return "\n".join(lines).replace("math.", "_m_") + "\n"


_KERNELS: dict = {}


def _kernel(system: NoisySystem):
    """The compiled Heun stepper of ``system`` (memoised on the printed source)."""
    import math as _math

    from numba import njit

    src = _source(system)
    if src in _KERNELS:
        return _KERNELS[src]
    env = {f"_m_{k}": getattr(_math, k) for k in dir(_math) if not k.startswith("_")}
    exec(compile(src, "<kbm spectrum model>", "exec"), env)
    acc = njit(env["acc"])
    n = system.dof

    @njit
    def advance(y, t0, k0, dt, dw, stride, rec):
        """Heun steps ``k0 .. k0 + len(dw) - 1`` of every row of ``y`` (updated); the state
        after global step ``k`` with ``(k + 1) % stride == 0`` goes to ``rec[(k + 1) //
        stride - 1 - k0 // stride]`` when that index is in range."""
        m = y.shape[0]
        a0 = np.empty(n)
        a1 = np.empty(n)
        yb = np.empty(2 * n)
        base = k0 // stride
        for r in range(m):
            yr = y[r]
            for k in range(dw.shape[0]):
                t = t0 + (k0 + k) * dt
                acc(t, yr, a0)
                for i in range(n):
                    yb[i] = yr[i] + dt * yr[n + i]
                    yb[n + i] = yr[n + i] + dt * a0[i] + dw[k, i, r]
                acc(t + dt, yb, a1)
                for i in range(n):
                    yr[i] = yr[i] + 0.5 * dt * (yr[n + i] + yb[n + i])
                    yr[n + i] = yr[n + i] + 0.5 * dt * (a0[i] + a1[i]) + dw[k, i, r]
                g = k0 + k + 1
                if g % stride == 0:
                    j = g // stride - 1 - base
                    if 0 <= j < rec.shape[1]:
                        for i in range(2 * n):
                            rec[r, j, i] = yr[i]
        return y

    _KERNELS[src] = advance
    return advance


def heun_paths(system: NoisySystem, y0: np.ndarray, dt: float, n_steps: int, stride: int,
               rngs: list, *, quiet_lane: bool = False, t0: float = 0.0) -> np.ndarray:
    """The states (``rows x n_steps//stride x 2N``) every ``stride`` Heun steps of the rows of
    ``y0`` driven by the generators ``rngs`` (one per row; a last noise-free row is added
    when ``quiet_lane``: the deterministic system under the same scheme).

    The increments are drawn in blocks of :data:`BLOCK` steps per trajectory, so a path
    depends on its own generator only."""
    advance = _kernel(system)
    n = system.dof
    m = len(rngs)
    y = np.array(np.atleast_2d(np.asarray(y0, dtype=float)), dtype=float)
    if quiet_lane:
        y = np.concatenate([y, y[:1]], axis=0)
    rows = y.shape[0]
    amp = math.sqrt(2.0 * system.D * dt)
    n_rec = n_steps // stride
    rec = np.empty((rows, n_rec, 2 * n))
    for start in range(0, n_steps, BLOCK):
        size = min(BLOCK, n_steps - start)
        dw = np.zeros((size, n, rows))
        for r, g in enumerate(rngs):
            dw[:, :, r] = amp * g.standard_normal((size, n))
        first = start // stride
        last = (start + size) // stride
        part = np.empty((rows, last - first, 2 * n))
        advance(y, float(t0), start, float(dt), dw, int(stride), part)
        rec[:, first:last] = part
    return rec
