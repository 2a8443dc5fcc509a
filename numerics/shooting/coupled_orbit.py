"""Periodic orbits of ``N`` coupled oscillators by shooting, with all ``2N`` Floquet multipliers.

The unknowns are the state ``y0`` on the section ``xdot_1 = 0`` (``x_1`` at a maximum) and
the period ``T``; the residual ``y(T) - y0`` (``2N`` equations for ``2N - 1 + 1``
unknowns) and its Jacobian ``[Phi(T) - I without the column of xdot_1, f(y(T))]`` come
from one integration of the extended system (:mod:`numerics.flow.coupled_flow`).  The start is
the state after a transient (a stable cycle attracts it) or a state given.  The shooting
is :func:`numerics.shooting.orbit.shoot` (autonomous, or at the drive's period for
:func:`forced_response`), accepted by the standard of :mod:`numerics.shooting.acceptance`:
past a fold, where only a minimum of the residual is left, it is refused
with that minimum in the message.  The multipliers are the eigenvalues of ``Phi(T)``;
Liouville's formula
``det Phi(T) = exp(int_0^T tr J dt)`` is the independent check printed with them.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from kbm.model.coupled import CoupledOscillators
from kbm.errors import ParameterError
from kbm.output.strict_json import complex_json
from numerics.errors import ConvergenceError, NoCycleError
from numerics.shooting.acceptance import trivial_ok
from numerics.shooting.orbit import multipliers, shoot
from numerics.flow.coupled_flow import CoupledFlow, coupled_flow

__all__ = ["CoupledCycle", "coupled_cycle", "section_start", "ForcedCoupledResponse",
           "forced_response"]


@dataclass(frozen=True, eq=False)
class CoupledCycle:
    """A periodic orbit of a coupled system.

    Attributes
    ----------
    model, params
        The system's name and every parameter's value (``mu`` included).
    period, frequency
        ``T`` and ``2 pi/T``.
    state
        The orbit's state at the section ``xdot_1 = 0``, ``x_1`` maximal.
    amplitudes
        First-harmonic amplitude ``|(2/T) int x_i e^{-i w t} dt|`` of each ``x_i``:
        what KBM's ``a_i`` predicts.
    phases
        Phase of each ``x_i``'s first harmonic minus that of ``x_1`` (radians, in
        ``(-pi, pi]``): 0 in phase, ``pi`` anti-phase.
    floquet_multipliers
        The ``2N`` eigenvalues of the monodromy matrix, the trivial one (closest to 1)
        first, the others by decreasing modulus.
    stable
        Every non-trivial multiplier inside the unit circle.
    liouville
        ``(det Phi(T), exp(int tr J dt))``.
    iterations, residual
        Newton's iterations and the final ``max |y(T) - y0|``.
    """

    model: str
    params: Mapping[str, float]
    period: float
    state: np.ndarray
    amplitudes: np.ndarray
    phases: np.ndarray
    floquet_multipliers: np.ndarray
    stable: bool
    liouville: tuple[float, float]
    iterations: int
    residual: float
    message: str

    @property
    def frequency(self) -> float:
        return 2 * math.pi / self.period

    def to_json(self) -> dict:
        """JSON-ready: a real multiplier is a number, a complex one ``[re, im]``."""
        return {
            "model": self.model, "params": dict(self.params), "success": True,
            "message": self.message, "period": self.period, "frequency": self.frequency,
            "state": [float(v) for v in self.state],
            "amplitudes": [float(v) for v in self.amplitudes],
            "phases": [float(v) for v in self.phases],
            "floquet_multipliers": [complex_json(z) for z in self.floquet_multipliers],
            "floquet_moduli": [float(abs(z)) for z in self.floquet_multipliers],
            "stable": self.stable,
            "liouville": {"det_monodromy": self.liouville[0],
                          "exp_divergence_integral": self.liouville[1]},
            "iterations": self.iterations, "residual": self.residual,
        }


def section_start(fl: CoupledFlow, y: np.ndarray, t_window: float, samples: int = 4000
                  ) -> tuple[np.ndarray, float]:
    """From the state ``y``: the first crossing of ``xdot_1 = 0`` downwards (``x_1`` at a
    maximum), refined by Newton on the flow, and the time to the next such crossing.

    Raises
    ------
    numerics.errors.NoCycleError
        If ``x_1`` has fewer than two maxima in ``t_window`` (the motion is at rest or
        too slow).
    """
    n = fl.dof
    ys = fl.states(y, t_window, samples)
    v1 = ys[:, n]
    idx = np.nonzero((v1[:-1] > 0) & (v1[1:] <= 0))[0]
    dt = t_window / samples
    if len(idx) < 2 or np.ptp(ys[:, 0]) < 1e-8:
        raise NoCycleError(f"no oscillation to shoot from: x1 has {len(idx)} maxima in "
                           f"t = {t_window:.4g} after the transient (range of x1 "
                           f"{np.ptp(ys[:, 0]):.3g}); the system settles to rest or "
                           "moves too slowly")

    def refine(k: int) -> tuple[np.ndarray, float]:
        yk, tk = ys[k].copy(), k * dt
        for _ in range(8):  # Newton in time on xdot_1(t) = 0
            f = fl.rhs(yk)
            step = -yk[n] / f[n]
            if abs(step) < 1e-14:
                break
            # back in time: a linear extrapolation (a fraction of the output spacing)
            yk = fl.states(yk, step, 1)[-1] if step > 0 else yk + step * f
            tk += step
        return yk, tk

    y0, t0 = refine(idx[0])
    _, t1 = refine(idx[1])
    return y0, t1 - t0


def _start_state(n: int, start) -> np.ndarray:
    """The state to start from: ``start``, or all ``x_i = 1`` at rest."""
    y = np.ones(2 * n) if start is None else np.asarray(start, dtype=float).copy()
    if y.shape != (2 * n,) or not np.all(np.isfinite(y)):
        raise ConvergenceError(f"the start must be {2 * n} finite numbers (x1..x{n}, "
                               f"xdot1..xdot{n}), got {start!r}")
    if start is None:
        y[n:] = 0.0
    return y


def _settling_time(fl: CoupledFlow) -> float:
    """The transient's default: ``20/mu`` within ``[100, 4000]`` (an attracting orbit draws
    the motion in at the rate ``mu``)."""
    return min(max(100.0, 20.0 / max(abs(fl.values["mu"]), 1e-12)), 4000.0)


def _shoot(fl: CoupledFlow, y0, T: float, section: int | None, rtol: float, max_iter: int,
           **kw):
    """:func:`numerics.shooting.orbit.shoot` on the coupled flow; ``(y0, T, iterations,
    Phi, divergence integral, residual)`` of the accepted orbit."""
    def monodromy(y, T):
        yT, Phi, _ = fl.monodromy(y, T, rtol=rtol)
        return yT, Phi, None

    def at_rest(z, R, state):
        # Newton on an equilibrium: phi_T(y) = y for every T and the field vanishes, so the
        # shooting matrix is singular and its correction is round-off; returned as it is
        # for the caller's check (coupled_cycle names it an equilibrium)
        if section is None:
            return False
        y = np.insert(np.asarray(z[:-1], dtype=float), section, 0.0)
        return float(np.max(np.abs(fl.rhs(y)))) <= 1e-9 * max(1.0, float(np.max(np.abs(y))))

    y0, T, it, _, _ = shoot(monodromy, y0, T, section=section, rtol=rtol, max_iter=max_iter,
                            rhs=lambda yT, T: fl.rhs(yT), degenerate=at_rest, **kw)
    yT, Phi, div = fl.monodromy(y0, T, rtol=rtol)
    return y0, T, it, Phi, div, float(np.max(np.abs(yT - y0)))


def coupled_cycle(model: CoupledOscillators | str, params: Mapping[str, object] | None = None,
                  *, start: np.ndarray | None = None, transient: float | None = None,
                  period: float | None = None, rtol: float = 1e-11, max_iter: int = 30
                  ) -> CoupledCycle:
    """A periodic orbit of ``x_i'' + omega_i**2 x_i = mu F_i``, its ``2N`` multipliers.

    Parameters
    ----------
    model
        A :class:`~kbm.model.coupled.CoupledOscillators` or a built-in name.
    params
        Parameter values, ``mu`` included (defaults fill the others).
    start
        A state ``(x_1..x_N, xdot_1..xdot_N)`` to start from (default all ``x_i = 1``).
    transient
        Time integrated from ``start`` before shooting (default ``20/mu`` within
        ``[100, 4000]``: a stable cycle attracts at the rate ``mu``); 0 to shoot from
        ``start`` itself (with ``period``, an unstable cycle).
    period
        A guess of the period (default: the return time of ``x_1``'s maximum).
    rtol
        Integrator tolerance.

    Raises
    ------
    numerics.errors.ConvergenceError
        If Newton does not converge (the residuals are in the message): after a transient
        this usually means the motion is quasi-periodic, not locked.
    numerics.errors.NoCycleError
        If the motion comes to rest.
    """
    fl = coupled_flow(model, params)
    if fl.nu is not None:
        raise ParameterError(f"{fl.model.name!r} is forced (theta = nu t): its periodic "
                             "responses have the forcing's period and are found by "
                             "forced_response")
    if not fl.model.autonomous(fl.values):
        raise ParameterError(f"{fl.model.name!r} depends on t at these parameters (a stage "
                             "that pulls, v != 0): it has no periodic orbit to shoot for; "
                             "its friction law is kbm friction")
    n = fl.dof
    y = _start_state(n, start)
    wmin = min(float(w) for w in fl.model.omegas)
    t_tr = _settling_time(fl) if transient is None else float(transient)
    if t_tr > 0:
        y = fl.states(y, t_tr, 1, rtol=1e-9, atol=1e-11)[-1]
    y0, T = section_start(fl, y, 6 * 2 * math.pi / wmin)
    try:
        y0, T, it, Phi, div, residual = _shoot(
            fl, y0, T if period is None else float(period), n, rtol, max_iter,
            damp=lambda z, dz: min(1.0, 0.3 * z[-1] / max(abs(dz[-1]), 1e-300)),
            what=f"of {fl.model.name}")
    except ConvergenceError as exc:
        raise ConvergenceError(
            f"{exc}; from the state after t = {t_tr:g}: the motion there is probably "
            "quasi-periodic (the oscillators not locked), or the parameters are past a fold "
            "of the locked cycle: compare kbm lock, or give another start") from None
    mults, rest = multipliers(Phi)
    spread = float(np.max(np.ptp(fl.states(y0, T, 64, rtol=rtol)[:, :n], axis=0)))
    if spread < 1e-6 * max(1.0, float(np.max(np.abs(y0)))) or not trivial_ok(mults[:1]):
        raise ConvergenceError(
            f"Newton converged to an equilibrium, not a cycle, of {fl.model.name} (the state "
            f"varies by {spread:.2e} over T = {T:.6g}; the multiplier nearest 1 is "
            f"{abs(mults[0]):.6g}); start nearer the cycle (--start), or let a transient "
            "bring the motion to it")
    ys = fl.states(y0, T, 512, rtol=rtol)[:-1]
    c1 = np.fft.rfft(ys[:, :n], axis=0)[1] / 512 * 2
    amps = np.abs(c1)
    ph = np.angle(c1 * np.conj(c1[0]))
    det = float(np.linalg.det(Phi))
    stable = bool(np.all(np.abs(rest) < 1.0))
    msg = (f"converged in {it} Newton iterations (DOP853 (compiled), rtol {rtol:g}); "
           f"|y(T) - y0| = {residual:.2e}; trivial multiplier {mults[0].real:.12f}; "
           f"det Phi = {det:.10g} against exp(int tr J) = {math.exp(div):.10g} (Liouville)")
    return CoupledCycle(fl.model.name, dict(fl.values), float(T), y0.copy(), amps, ph, mults,
                        stable, (det, math.exp(div)), it, residual, msg)


@dataclass(frozen=True, eq=False)
class ForcedCoupledResponse:
    """A periodic response of a forced coupled system, of period ``T = m 2 pi/nu``.

    ``amplitudes[i]`` is the amplitude of ``x_i``'s component at the frequency nearest
    ``omega_i`` among the multiples of ``nu/m`` (what KBM's ``a_i`` predicts); the
    multipliers are the ``2N`` eigenvalues of ``Phi(T)``.
    """

    model: str
    params: Mapping[str, float]
    nu: float
    period: float
    multiple: int
    state: np.ndarray
    amplitudes: np.ndarray
    floquet_multipliers: np.ndarray
    stable: bool
    liouville: tuple[float, float]
    iterations: int
    residual: float

    def to_json(self) -> dict:
        return {"model": self.model, "params": dict(self.params), "nu": self.nu,
                "period": self.period, "multiple": self.multiple,
                "state": [float(v) for v in self.state],
                "amplitudes": [float(v) for v in self.amplitudes],
                "floquet_multipliers": [complex_json(z) for z in self.floquet_multipliers],
                "stable": self.stable,
                "liouville": {"det_monodromy": self.liouville[0],
                              "exp_divergence_integral": self.liouville[1]},
                "iterations": self.iterations, "residual": self.residual}


def forced_response(model: CoupledOscillators | str, params: Mapping[str, object] | None = None,
                    *, start: np.ndarray | None = None, transient_periods: int | None = None,
                    rtol: float = 1e-11, max_iter: int = 30) -> ForcedCoupledResponse:
    """A periodic response of ``x_i'' + omega_i**2 x_i = mu F_i(x, x', nu t)`` by shooting at
    the fixed period ``T = m 2 pi/nu``, ``m`` the least common denominator of the ratios
    ``omega_i/nu0`` (``m = 2`` when a mode answers at ``nu/2``).

    The start is the state after ``transient_periods`` periods (default: a time ``20/mu``)
    from ``start`` (default all ``x_i = 1``); the multipliers are those of the monodromy.

    Raises
    ------
    numerics.errors.ConvergenceError
        If Newton does not converge (the residuals are in the message).
    kbm.errors.ParameterError
        For a system without forcing.
    """
    fl = coupled_flow(model, params)
    if fl.nu is None:
        raise ParameterError(f"{fl.model.name!r} has no forcing; its periodic orbits are "
                             "found by coupled_cycle")
    n, nu = fl.dof, fl.nu
    ratios = fl.model.forcing_ratios
    m = fl.model.response_periods
    T = m * 2 * math.pi / nu
    y = _start_state(n, start)
    k = transient_periods if transient_periods is not None else int(_settling_time(fl) / T) + 1
    if k > 0:
        y = fl.states(y, k * T, k, rtol=1e-9, atol=1e-11)[-1]
    try:
        y, _, it, Phi, div, residual = _shoot(
            fl, y, T, None, rtol, max_iter, diverge=max_iter + 1,
            what=f"of period {m} x 2 pi/nu of {fl.model.name}")
    except ConvergenceError as exc:
        raise ConvergenceError(f"{exc} (a multiplier at 1 makes the matrix singular: a fold "
                               f"at nu = {nu:.10g}, or a free phase)") from None
    mults, _ = multipliers(Phi, autonomous=False)
    samples = 256 * m
    ys = fl.states(y, T, samples, rtol=rtol)[:-1]
    spec = np.fft.rfft(ys[:, :n], axis=0) / samples * 2
    amps = np.array([abs(spec[int(round(float(r) * m)), i]) for i, r in enumerate(ratios)])
    return ForcedCoupledResponse(fl.model.name, dict(fl.values), nu, T, m, y.copy(), amps,
                                 mults, bool(np.all(np.abs(mults) < 1.0)),
                                 (float(np.linalg.det(Phi)), math.exp(div)), it, residual)
