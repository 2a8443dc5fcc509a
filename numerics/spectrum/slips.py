"""Phase slips of noisy coupled self-excited oscillators: Stratonovich's formula against counts.

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

**Simulated.**  An ensemble of the full system (:mod:`numerics.noise.coupled`); the phases
``theta_i = atan2(-x_i'/omega_i, x_i)`` unwrapped, ``gamma = theta_2 - theta_1``; the net
slips are the change of ``gamma`` over ``2 pi`` after a burn-in, and the forward and
backward slips are counted with a hysteresis of a full turn (a slip is a ``2 pi``
excursion from the last counted level).  Rates and standard errors are over trajectories.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import sympy as sp

from kbm.errors import ParameterError

from numerics._memo import memo
from numerics.noise.coupled import CHUNK
from numerics.noise.validity import averaged_error
from .driven_sim import noisy_system

__all__ = ["AdlerReduction", "adler_reduction", "stratonovich_rate", "simulate_slips",
           "slip_report"]


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
            da = np.linalg.solve(np.asarray(J([*a, gm]), dtype=float), -r)
            a = a + da
            if np.max(np.abs(da)) < 1e-13 * (1 + np.max(np.abs(a))):
                break
        else:
            a = np.full(n, math.nan)
        if not (np.all(np.isfinite(a)) and np.all(a > 0)):
            raise ParameterError(f"the amplitudes of {model.name!r} do not follow the phase "
                                 f"difference at gamma = {gm:.4g} (no positive stationary "
                                 "amplitudes: amplitude death?); no phase equation")
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
    g, Q = np.asarray(drift, float), np.asarray(diffusion, float)
    n = len(gamma)
    if n % 2 or n < 8:
        raise ParameterError(f"the grid needs an even number of points >= 8, got {n}")
    if np.any(Q <= 0):
        raise ParameterError("the phase diffusion Q must be positive (D > 0)")
    r = g / Q
    need = 2 * math.ceil(math.pi * float(np.max(np.abs(r))) / STEP)
    fine = need if need <= MAX_GRID else WEAK_GRID
    if fine > n:
        r, Q, n = _interpolate(r, fine), _interpolate(Q, fine), fine
    h = 2 * math.pi / n
    simpson = need <= MAX_GRID
    c = np.fft.rfft(r)
    m = c[0].real / n
    k = np.arange(len(c))
    anti = np.zeros_like(c)
    anti[1:-1] = c[1:-1] / (1j * k[1:-1])
    p = np.fft.irfft(anti, n)
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
            a, b = expo[:, :-1], expo[:, 1:]
            d = b - a
            small = np.abs(d) < 1e-8
            safe = np.where(small, 1.0, d)
            # log(h (e^b - e^a)/(b - a)) = max(a, b) + log(h |1 - e^{-|d|}|/|d|)
            core = np.where(small, 0.0, np.log(-np.expm1(-np.abs(safe)) / np.abs(safe)))
            inner[rows] = _logsumexp(np.maximum(a, b) + core + math.log(h), axis=1)
    log_den = _logsumexp(inner - np.log(Q)) + math.log(h)
    num = -math.expm1(-2 * math.pi * m)
    return float(math.copysign(math.exp(math.log(abs(num)) - log_den), num))


# -- simulation -------------------------------------------------------------------------
def _slip_task(task) -> list:
    model, params, D, y0, dt, n_burn, n_run, stride, seed, first, count = task
    system = noisy_system(model, params, D)
    rec = system.paths(np.tile(y0, (count, 1)), dt, n_burn + n_run, stride, seed=seed,
                       first=first)
    n, w = system.dof, system.omegas
    th = np.arctan2(-rec[:, :, n:n + 2] / w[None, None, :2], rec[:, :, 0:2])
    th = np.unwrap(th, axis=1)
    gam = th[:, :, 1] - th[:, :, 0]
    gam = gam[:, n_burn // stride:]
    out = []
    for gr in gam:
        fwd = bwd = 0
        ref = gr[0]
        for v in gr:  # hysteresis: a full turn from the last counted level
            while v >= ref + 2 * math.pi:
                fwd, ref = fwd + 1, ref + 2 * math.pi
            while v <= ref - 2 * math.pi:
                bwd, ref = bwd + 1, ref - 2 * math.pi
        out.append((float(gr[-1] - gr[0]), fwd, bwd))
    return out


def simulate_slips(model, params: Mapping[str, object], D: float, *, duration: float,
                   burn_in: float, trajectories: int = 32, seed: int = 0,
                   workers: int | None = None, store=None, progress: bool = False,
                   dt: float | None = None, shared: int = 1) -> dict:
    """Slip counts of the full noisy system (module docstring): ``{"rate", "stderr",
    "frequency", "frequency_stderr", "forward", "backward", "duration", ...}``.

    Raises
    ------
    kbm.errors.ParameterError
        For a bad time, ``D <= 0``, fewer than 2 trajectories, or a run above the step or
        memory limit (shared by ``shared`` runs of a sweep, :mod:`numerics.spectrum._cost`).
    """
    from numerics.executor import chunk, map_chunks
    from numerics.noise.budget import STEP_BUDGET
    from numerics.spectrum._cost import check_cost

    if trajectories < 2:
        raise ParameterError(f"--trajectories {trajectories}: a standard error needs at least 2")
    if not (duration > 0 and burn_in >= 0):
        raise ParameterError(f"--duration must be positive, got {duration!r}")
    params = {k: float(v) for k, v in params.items()}
    system = noisy_system(model, params, D)
    top = float(system.omegas.max())
    if dt is None:
        dt = 2 * math.pi / top / 64
    stride = max(1, int(0.5 / top / dt))  # a sample every half radian at least
    n_run = int(round(duration / dt / stride)) * stride
    n_burn = int(round(burn_in / dt / stride)) * stride
    # a chunk of CHUNK paths is recorded whole (all 2 dof coordinates) before it is reduced
    check_cost(trajectories, n_burn + n_run, 8.0 * min(int(trajectories), CHUNK)
               * 2 * system.dof * ((n_burn + n_run) // stride + 1), budget=STEP_BUDGET / shared,
               shared=shared)
    y0 = tuple([2.0] * system.dof + [0.0] * system.dof)
    groups = chunk(list(range(int(trajectories))), size=CHUNK)
    tasks = [(model, params, float(D), y0, float(dt), n_burn, n_run, stride, int(seed), g[0],
              len(g)) for g in groups]
    definition = repr(("spectrum.slips", tasks[0][:8], int(seed), int(trajectories)))
    rows = map_chunks(_slip_task, tasks, workers=workers, progress=progress,
                      desc="trajectories", unit="trajectory", sizes=[len(g) for g in groups],
                      store=store, definition=definition if store is not None else None)
    T = n_run * dt
    dg = np.array([r[0] for r in rows]) / T
    rate = dg / (2 * math.pi)
    n = len(rows)
    return {"rate": float(rate.mean()), "stderr": float(rate.std(ddof=1) / math.sqrt(n)),
            "frequency": float(dg.mean()), "frequency_stderr":
            float(dg.std(ddof=1) / math.sqrt(n)),
            "forward": float(np.mean([r[1] for r in rows]) / T),
            "backward": float(np.mean([r[2] for r in rows]) / T),
            "duration": T, "burn_in": n_burn * dt, "dt": float(dt), "trajectories": n,
            "seed": int(seed)}


def slip_report(model, params: Mapping[str, object], D: float, detunings, *, order: int = 1,
                detuning: str = "sigma", simulate: bool = True, duration: float | None = None,
                trajectories: int = 32, seed: int = 0, workers: int | None = None, store=None,
                progress: bool = False) -> list[dict]:
    """Per detuning: the averaged (Stratonovich) and simulated slip rate and frequency
    difference, ``{"detuning", "locked", "slip_rate": {averaged, simulated, stderr},
    "frequency_difference": {...}, "adler": {tilt, coupling}, ...}``.

    Each of the two also holds ``averaged_order`` and its expected error,
    ``expected_error`` and ``expected_error_source`` (the rule of
    :func:`numerics.noise.validity.averaged_error`, as ``kbm spectrum``'s line): the
    simulation's bound ``|averaged - simulated| + 2 stderr`` (``"simulation"``; ``None``
    and ``"none"`` without a simulation), at either order.  The second order's
    correction is not used as the first order's error here: the rate's error is mostly the
    reduction's (one Adler equation, amplitudes slaved, at finite ``D/mu``), which the
    next order of the averaging leaves as it is.  Measured (``coupled-vdp``, ``mu =
    0.05``, ``c = 0.3``, ``D/mu = 0.1``, 32 trajectories over 8000): ``|J_2 - J_1|`` is
    5.4e-5 and 2.8e-5 at ``sigma`` = 0.45 and 0.3, the simulated first-order gap (1.4 +-
    0.4)e-4 and (1.3 +- 0.4)e-4, three to five times more.

    The default duration is ``400/mu`` after a burn-in of ``20/mu``."""
    detunings = list(detunings)
    out = []
    for s in detunings:
        p = {**dict(params), detuning: float(s)}
        red = adler_reduction(model, p, D, order=order, detuning=detuning)
        J = stratonovich_rate(red.gamma, red.drift, red.diffusion)
        row = {"detuning": float(s), "locked": red.locked,
               "adler": {"tilt": red.tilt, "coupling": red.coupling,
                         "diffusion_mean": float(red.diffusion.mean())},
               "slip_rate": {"averaged": J, "simulated": None, "stderr": None,
                             "averaged_order": order},
               "frequency_difference": {"averaged": 2 * math.pi * J, "simulated": None,
                                        "stderr": None, "averaged_order": order}}
        if simulate:
            mu = float(p.get("mu", 0) or 0)
            if not mu > 0:
                raise ParameterError("the slip rate needs mu > 0 (-p mu=VALUE)")
            T = duration if duration is not None else 400 / mu
            sim = simulate_slips(model, p, D, duration=T, burn_in=20 / mu,
                                 trajectories=trajectories, seed=seed, workers=workers,
                                 store=store, progress=progress, shared=len(detunings))
            row["slip_rate"].update(simulated=sim["rate"], stderr=sim["stderr"])
            row["frequency_difference"].update(simulated=sim["frequency"],
                                               stderr=sim["frequency_stderr"])
            row["simulation"] = {k: sim[k] for k in ("forward", "backward", "duration",
                                                     "burn_in", "dt", "trajectories", "seed")}
        for entry in (row["slip_rate"], row["frequency_difference"]):
            entry["expected_error"], entry["expected_error_source"] = averaged_error(entry)
        out.append(row)
    return out
