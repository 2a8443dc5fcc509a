"""The noisy Adler equation of a locked pair: the reduction, Stratonovich's slip rate and
the mean phase.

Two oscillators of a coupled system in ``1:1`` resonance (``coupled-vdp``) with the noise
``sqrt(2 D) xi_i`` on each mode, ``x_i = a_i cos(t + phi_i)``.  The averaged flow of
:func:`kbm.expansion.coupled.derive_coupled` (order 1 or 2) is in ``(a_1, a_2, gamma)``, ``gamma =
phi_2 - phi_1`` the phase difference.  The amplitudes relax to the values ``a*(gamma)``
that zero their rates at fixed ``gamma`` (adiabatic elimination: the fixed points of the
reduced equation are those of the averaged flow, so its locking edges are the averaged
edges of :func:`numerics.locking.mutual.averaged_edges`), which leaves the noisy Adler
equation

``d gamma = g(gamma) dt + sqrt(2 Q(gamma)) dW``,  ``g(gamma) = gamma-rate at a*(gamma)``,

``Q = (D/2) sum_i 1/(omega_i^2 a_i*^2)`` (the phase diffusion of each oscillator, ``D/(2
omega^2 a^2)``, :mod:`kbm.noise.stochastic`).  For ``coupled-vdp`` at order 1 ``g = mu (sigma -
(c/2)(a_1/a_2 + a_2/a_1) sin gamma)``: Adler's ``-Delta + K sin``-form with ``Delta = mu
sigma``, ``K = mu c``, derived, not assumed.

**Stratonovich's formula.**  The stationary Fokker-Planck equation of a tilted periodic
potential has the constant probability current (Stratonovich, *Topics in the Theory of
Random Noise* II, ch. 9; Risken, *The Fokker-Planck Equation*, sec. 11.2)

``J = (1 - e^{Phi(2 pi)}) / int_0^{2 pi} dx (1/Q(x)) e^{-Phi(x)} int_x^{x + 2 pi}
e^{Phi(s)} ds``,  ``Phi(x) = -int_0^x g/Q``,

the net slip rate (slips per unit time, forward minus backward); the effective frequency
difference is ``<gamma'> = 2 pi J``.  Both integrals are by quadrature.  For constant ``Q``
and ``g = Delta - K sin`` it equals the closed form ``<gamma'> = (Q/pi) sinh(pi Delta/Q)
/ |I_{i Delta/Q}(K/Q)|^2`` (the test's reference).

**The mean phase.**  ``Psi(gamma)``, ``Psi(gamma + 2 pi) = Psi(gamma) + 2 pi``, solves the
backward (Poisson) equation of the reduced generator

``g Psi' + Q Psi'' = <gamma'>``;

its periodic slope is ``Psi' = u / <u>`` with ``u(x) = int_0^{2 pi} e^{Phi(x) - Phi(x - y)}
/ Q(x - y) dy`` (``Q u' + g u = 1 - e^{Phi(2 pi)}``, constant).  By Dynkin's formula
``E Psi(gamma(T)) - E Psi(gamma(0)) = <gamma'> T`` from any start, so ``(Psi(gamma(T)) -
Psi(gamma(0)))/(2 pi T)`` counts net slips without the bias of a phase that relaxes or
moves inside a well (``Psi`` is flat there: a staircase of ``2 pi`` steps at the barrier
tops deep in locking, ``2 pi J int_0^x dy/g`` outside it at weak noise: the deterministic
phase that runs at the constant rate ``2 pi J``); and as ``Psi - gamma`` is
periodic, the count agrees with ``(gamma(T) - gamma(0))/(2 pi T)`` up to a bounded term
over ``T``.  It is the mean-return-time phase of Schwabedal and Pikovsky (*Phys. Rev.
Lett.* 110, 204102, 2013) of the one-dimensional rotator.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import sympy as sp

from kbm.errors import ParameterError

from numerics._memo import memo

__all__ = ["AdlerReduction", "adler_reduction", "stratonovich_rate", "mean_phase"]


@dataclass(frozen=True)
class AdlerReduction:
    """The reduced phase equation on a grid of ``gamma`` over one turn.

    Attributes
    ----------
    gamma : numpy.ndarray
        ``n`` points ``2 pi k/n``.
    drift, diffusion : numpy.ndarray
        ``g(gamma)`` and ``Q(gamma)``.
    amplitudes : numpy.ndarray
        ``a*(gamma)`` (``n x N``).
    detuning, tilt, coupling : float
        The detuning value; ``Delta`` and ``K`` of the first harmonic ``g ~ Delta -
        K sin(gamma - gamma_0)`` (Fourier coefficients of ``g``).
    """

    gamma: np.ndarray
    drift: np.ndarray
    diffusion: np.ndarray
    amplitudes: np.ndarray
    detuning: float
    tilt: float
    coupling: float

    @property
    def locked(self) -> bool:
        """Whether the deterministic reduced equation has a fixed point (``g`` changes
        sign)."""
        return bool(self.drift.min() < 0 < self.drift.max())


@memo(maxsize=16)
def _averaged_flow(model, fixed: tuple, order: int, detuning: str):
    """The averaged flow ``f(y, sigma, mu)`` and the amplitude rates' Jacobian (memoised:
    a derivation per model, fixed values and order)."""
    from kbm.model.coupled import amplitudes
    from kbm.expansion.coupled import derive_coupled

    res = derive_coupled(model, order, dict(fixed))
    if len(res.gammas) != 1:
        raise ParameterError(f"{model.name!r} has {len(res.gammas)} phase combinations; the "
                             "slip rate is for one locked pair (coupled-vdp)")
    state = [*amplitudes(model.dof), res.gammas[0][0]]
    exprs = [sp.sympify(r) for r in res.slow_flow()]
    args = [state, sp.Symbol(detuning), sp.Symbol("mu")]
    f = sp.lambdify(args, exprs, "numpy")
    J = sp.lambdify(args, sp.Matrix(exprs[:-1]).jacobian(state[:-1]), "numpy")
    return f, J


def _averaged(model, values: dict, order: int, detuning: str):
    fixed = tuple(sorted((k, sp.nsimplify(v, rational=True)) for k, v in values.items()
                         if k not in (detuning, "mu")))
    f, J = _averaged_flow(model, fixed, order, detuning)
    s, mu = values[detuning], values["mu"]
    return (lambda y: f(y, s, mu)), (lambda y: J(y, s, mu))


def adler_reduction(model, params: Mapping[str, object], D: float, *, order: int = 1,
                    detuning: str = "sigma", points: int = 512) -> AdlerReduction:
    """The noisy Adler equation of the pair, from the averaged flow (module docstring).

    Raises
    ------
    kbm.errors.ParameterError
        For a model without one phase combination, or amplitudes that cannot follow the
        phase difference (no positive root of the amplitude rates at some ``gamma``).
    """
    from numerics.flow.coupled_flow import bind_coupled

    model, values = bind_coupled(model, params)
    n = model.dof
    f, J = _averaged(model, values, order, detuning)
    sub = {sp.Symbol(k): v for k, v in values.items()}
    omegas = np.array([float(sp.sympify(w).subs(sub)) for w in model.frequencies()])
    grid = 2 * math.pi * np.arange(points) / points
    a = np.full(n, 2.0)
    amps = np.empty((points, n))
    drift = np.empty(points)
    for k, gm in enumerate(grid):
        for _ in range(60):
            r = np.asarray(f([*a, gm])[:-1], dtype=float)
            try:
                da = np.linalg.solve(np.asarray(J([*a, gm]), dtype=float), -r)
            except np.linalg.LinAlgError:  # a singular Jacobian: no root to follow
                a = np.full(n, math.nan)
                break
            a = a + da
            if np.max(np.abs(da)) < 1e-13 * (1 + np.max(np.abs(a))):
                break
        else:
            a = np.full(n, math.nan)
        if not (np.all(np.isfinite(a)) and np.all(a > 0)):
            raise ParameterError(f"the amplitudes of {model.name!r} do not follow the phase "
                                 f"difference at gamma = {gm:.4g} (no positive stationary "
                                 "amplitudes: amplitude death?); no phase equation: "
                                 "weaken the coupling")
        amps[k] = a
        drift[k] = float(f([*a, gm])[-1])
    Q = 0.5 * D * np.sum(1.0 / (omegas[None, :] ** 2 * amps**2), axis=1)
    c1 = 2 * np.mean(drift * np.cos(grid))
    s1 = 2 * np.mean(drift * np.sin(grid))
    return AdlerReduction(grid, drift, Q, amps, float(values[detuning]), float(np.mean(drift)),
                          float(math.hypot(c1, s1)))


#: the largest grid of :func:`stratonovich_rate`
MAX_GRID = 2**12
#: the grid of the weak-noise rule (Phi linear per cell; relative error about 1e-5)
WEAK_GRID = 2**11
#: Simpson's step times the largest |g/Q| (relative error about STEP^4/180)
STEP = 0.1
#: the largest grid of :func:`mean_phase` (its accuracy only sets how much of the motion
#: inside a well the count removes; 0.05 s a detuning)
PHASE_GRID = 2**10


def _interpolate(v: np.ndarray, n: int) -> np.ndarray:
    """The periodic samples ``v`` on a grid of ``n`` points (zero-padded spectrum)."""
    c = np.fft.rfft(v)
    out = np.zeros(n // 2 + 1, dtype=complex)
    out[:len(c)] = c
    if len(v) % 2 == 0:
        out[len(c) - 1] *= 0.5  # split the Nyquist mode between +-
    return np.fft.irfft(out, n) * (n / len(v))


def _logsumexp(a: np.ndarray, axis=None):
    top = np.max(a, axis=axis, keepdims=True)
    out = top + np.log(np.sum(np.exp(a - top), axis=axis, keepdims=True))
    return np.squeeze(out, axis=axis) if axis is not None else float(out.ravel()[0])


def stratonovich_rate(gamma: np.ndarray, drift: np.ndarray, diffusion: np.ndarray) -> float:
    """The net slip rate ``J`` of ``d gamma = g dt + sqrt(2 Q) dW`` from ``g`` and ``Q`` on a
    uniform periodic grid of an even number of points (module docstring).

    ``g/Q = m + p'`` (``m`` the mean, ``p`` periodic, its antiderivative by FFT), so
    ``Phi(s) - Phi(x) = -m (s - x) - (p(s) - p(x))`` exactly on the grid; the inner
    integral is Simpson's rule on a grid refined by Fourier interpolation until the step
    is below ``STEP/max|g/Q|``; where that would take more than :data:`MAX_GRID` points
    (weak noise), ``Phi`` is taken linear in each cell of a grid of :data:`WEAK_GRID`
    points and integrated exactly,
    which keeps the deterministic (Laplace) limit ``J -> 1/int dx/g`` outside locking.  The
    outer integral (periodic) is the trapezoidal rule; all in logarithms (no overflow deep
    in the locking region)."""
    need, r, Q, n = _refined(gamma, drift, diffusion, MAX_GRID)
    h = 2 * math.pi / n
    simpson = need <= MAX_GRID
    m, p = _split(r)
    if m == 0:
        return 0.0
    w = np.full(n + 1, 2.0)
    w[1::2] = 4.0
    w[0] = w[-1] = 1.0
    logw = np.log(w * h / 3)
    inner = np.empty(n)
    cols = np.arange(n + 1)
    for start in range(0, n, 512):
        rows = np.arange(start, min(n, start + 512))
        expo = -(p[(rows[:, None] + cols[None, :]) % n] - p[rows, None]) \
            - m * h * cols[None, :]
        if simpson:
            inner[rows] = _logsumexp(expo + logw[None, :], axis=1)
        else:  # Phi linear in each cell, integrated exactly: right in the Laplace limit too
            inner[rows] = _logsumexp(_log_cells(expo[:, :-1], expo[:, 1:], h), axis=1)
    log_den = _logsumexp(inner - np.log(Q)) + math.log(h)
    num = -math.expm1(-2 * math.pi * m)
    return float(math.copysign(math.exp(math.log(abs(num)) - log_den), num))




def _refined(gamma, drift, diffusion, most: int, weak: int = WEAK_GRID):
    """``(need, g/Q, Q, n)`` on the grid of Simpson's step :data:`STEP` (``need`` points),
    or of ``weak`` points where ``need`` exceeds ``most``; never coarser than
    the given grid of ``n`` points (even, at least 8; ``Q > 0``, else ParameterError)."""
    g, Q = np.asarray(drift, float), np.asarray(diffusion, float)
    n = len(gamma)
    if n % 2 or n < 8:
        raise ParameterError(f"the grid needs an even number of points >= 8, got {n}")
    if np.any(Q <= 0):
        raise ParameterError("the phase diffusion Q must be positive (D > 0)")
    r = g / Q
    need = 2 * math.ceil(math.pi * float(np.max(np.abs(r))) / STEP)
    fine = need if need <= most else weak
    if fine > n:
        r, Q, n = _interpolate(r, fine), _interpolate(Q, fine), fine
    return need, r, Q, n


def _split(r: np.ndarray) -> tuple[float, np.ndarray]:
    """``g/Q = m + p'`` on a periodic grid: the mean ``m`` and the periodic antiderivative
    ``p`` (by FFT)."""
    n = len(r)
    c = np.fft.rfft(r)
    k = np.arange(len(c))
    anti = np.zeros_like(c)
    anti[1:-1] = c[1:-1] / (1j * k[1:-1])
    return c[0].real / n, np.fft.irfft(anti, n)


def _log_cells(a: np.ndarray, b: np.ndarray, h: float) -> np.ndarray:
    """``log int`` over cells of width ``h`` of ``e^E`` with ``E`` linear from ``a`` to ``b``
    (exact: ``h (e^b - e^a)/(b - a)``, in logarithms)."""
    d = np.abs(b - a)
    small = d < 1e-8
    safe = np.where(small, 1.0, d)
    core = np.where(small, 0.0, np.log(-np.expm1(-safe) / safe))
    return np.maximum(a, b) + core + math.log(h)


def mean_phase(gamma: np.ndarray, drift: np.ndarray,
               diffusion: np.ndarray) -> tuple[float, np.ndarray]:
    """The mean phase ``Psi`` of ``d gamma = g dt + sqrt(2 Q) dW`` (module docstring):
    ``(start, psi)``, ``psi`` its values on ``start + 2 pi k/n``, ``k = 0..n``, rising from
    0 to ``2 pi``.

    ``start`` is where the slope ``u`` is least (the bottom of a well when locked), so that
    ``psi`` is exactly 0 and ``2 pi`` where ``u`` underflows beside it.  The grid is refined
    as in :func:`stratonovich_rate` up to :data:`PHASE_GRID` points; ``Phi`` and ``log Q``
    are linear in each cell and the inner integral is exact for that, the outer one exact
    for ``log u`` linear per cell.
    Any increasing ``Psi`` with ``Psi - gamma`` periodic keeps the net slip count unbiased
    in the stationary state; the accuracy of this one only sets how well it removes the
    motion inside a well.

    Raises
    ------
    kbm.errors.ParameterError
        For a grid of an odd number of points or fewer than 8, or ``Q <= 0``.
    """
    _, r, Q, n = _refined(gamma, drift, diffusion, PHASE_GRID, PHASE_GRID)
    h = 2 * math.pi / n
    m, p = _split(r)  # Phi(x) = -(m x + p(x) - p(0))
    logq = np.log(Q)
    log_u = np.empty(n)
    cols = np.arange(n + 1)
    for first in range(0, n, 512):
        rows = np.arange(first, min(n, first + 512))
        back = (rows[:, None] - cols[None, :]) % n  # x - y, y = h j
        # log of e^{Phi(x) - Phi(x - y)}/Q(x - y)
        expo = -(p[rows, None] - p[back]) - m * h * cols[None, :] - logq[back]
        log_u[rows] = _logsumexp(_log_cells(expo[:, :-1], expo[:, 1:], h), axis=1)
    start = int(np.argmin(log_u))
    lu = np.roll(log_u, -start)
    cells = _log_cells(lu, np.roll(lu, -1), h)
    w = np.exp(cells - _logsumexp(cells))
    total = np.cumsum(w)
    psi = np.concatenate([[0.0], 2 * math.pi * (total / total[-1])])
    return float(gamma[0] + start * h), psi
