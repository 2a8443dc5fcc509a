"""Noise spectra about the stable steady states of forced oscillators: averaged, Floquet, simulated.

The system (one or ``N`` degrees of freedom, :mod:`numerics.noise.coupled`) is

``x_i'' + omega_i^2 x_i = mu F_i(x, x', nu t) + sqrt(2 D) xi_i(t)``,

driven near a resonance, ``nu = nu0 + mu sigma``; mode ``i`` answers at ``Omega_i =
(omega_i/nu0) nu``.  About a stable periodic response ``x_p(t)`` the fluctuation
``dx = x - x_p`` is, to first order in the noise, a cyclostationary Gaussian process; its
time-averaged one-sided power spectral density ``S(w)`` (angular frequency, ``int_0^inf S
dw = <dx^2>``) is computed two ways.

**Averaged (first order).**  In the rotating frame ``x_i = u_i cos(Omega_i t) - v_i
sin(Omega_i t)``, ``x_i' = -omega_i (u_i sin + v_i cos)`` (van der Pol's variables, KBM's
``x = a cos(psi)``, ``x' = -a omega_i sin(psi)`` with ``u + i v = a e^{i phi}``) the
first-order averaged flow ``U' = f(U)`` is the time average of the equations over the
response period, the mismatch ``Omega_i - omega_i = O(mu)`` a rotation of ``(u_i, v_i)``
(the same slow flow as :func:`kbm.expansion.forced.derive_forced` at order 1, in Cartesian form);
the noise enters as ``du_i = ... - (sin(Omega_i t)/omega_i) sqrt(2 D) dW_i`` and ``dv_i = ... -
(cos/omega_i) sqrt(2D) dW_i``, whose average covariance is ``Q = (D/omega_i^2) I`` (Stratonovich, *Topics in the Theory of Random Noise* II, ch. 9).  About a
stable fixed point with Jacobian ``J`` the fluctuations are an Ornstein-Uhlenbeck process
with the matrix spectrum ``S_U(w) = (1/2 pi) (i w - J)^-1 Q (i w - J)^-H``.  The lab frame
``dx_i = Re[dz_i e^{i Omega_i t}]``, ``z = u + i v``, gives

``S(w) = (1/2) [S_z(w - Omega) + S_z(-w - Omega)]``,  ``S_z = c^T S_U conj(c)``,

with ``c`` picking ``u_i + i v_i``: a peak near ``Omega`` whose two sidebands at ``Omega +-
Im(lambda)`` (``lambda`` the eigenvalues of ``J``) have different heights, since ``J`` is
not normal (the asymmetry near the jump of the driven Duffing; Dykman & Krivoglaz, Sov.
Phys. JETP 50 (1979) 30).

**Floquet (exact linearisation).**  The full SDE linearised about the periodic orbit is
``d dy = A(t) dy dt + B dW`` with ``A`` periodic.  Its periodic covariance ``P(t)`` solves
``P' = A P + P A^T + B B^T``; from ``P(T) = M P(0) M^T + W`` (``M`` the monodromy) ``P(0)``
is the solution of a discrete Lyapunov equation.  The time-averaged correlation
``C(tau) = <Phi(t + tau, t) P(t)>_t`` has the one-sided transform ``G(w) = int_0^inf C
e^{-i w tau}``, which is the period average of the periodic solution of ``Y' = (A - i w) Y +
P(t) e`` (``Y(0) = (I - e^{-i w T} M)^-1 Y_p(T)``), so ``S(w) = (2/pi) Re G_xx(w)``.  The
orbit, ``Phi``, ``P`` and ``Y`` for every ``w`` are integrated together by the classical
Runge-Kutta method over one period.

The simulated PSD and the report are in :mod:`numerics.spectrum.driven_sim`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.integrate
import scipy.linalg

from kbm.errors import ParameterError

from numerics.errors import ConvergenceError
from numerics.noise.coupled import NoisySystem

__all__ = ["SteadyState", "AveragedFlow", "Orbit", "averaged_flow", "stable_states",
           "averaged_spectrum", "periodic_orbit", "floquet_spectrum", "detuning_name"]


@dataclass(frozen=True)
class SteadyState:
    """A fixed point of the averaged rotating-frame flow.

    Attributes
    ----------
    U : numpy.ndarray
        ``(u_1..u_N, v_1..v_N)``.
    jacobian : numpy.ndarray
        ``df/dU`` there.
    eigenvalues : numpy.ndarray
        Its eigenvalues (sorted by imaginary part).
    stable : bool
        Every real part below ``-1e-9 (1 + max |lambda|)``.
    """

    U: np.ndarray
    jacobian: np.ndarray
    eigenvalues: np.ndarray
    stable: bool

    def amplitudes(self) -> np.ndarray:
        """``a_i = |u_i + i v_i|``."""
        n = len(self.U) // 2
        return np.hypot(self.U[:n], self.U[n:])


class AveragedFlow:
    """The first-order averaged flow in van der Pol's rotating-frame variables.

    Parameters
    ----------
    system : NoisySystem
        A forced system (``nu`` set).
    samples : int
        Quadrature points per forcing period of the average (trapezoidal rule: exact for
        trigonometric polynomials of lower degree).
    """

    def __init__(self, system: NoisySystem, samples: int = 128):
        m = system.model
        if not m.forced:
            raise ParameterError(f"{m.name!r} is not forced: a response spectrum needs a "
                                 "drive (the slip rate is for autonomous coupled systems)")
        if any(k != 0 for k in m.hards):
            raise ParameterError(f"{m.name!r} has a hard (order-one) forcing: its rotating-"
                                 "frame average is not first order; use a soft forcing")
        self.system = system
        self.ratios = np.array([float(r) for r in m.forcing_ratios])
        self.Omega = self.ratios * system.nu
        self.omega0 = np.array([float(w) for w in m.omegas])
        self.period = 2 * math.pi * m.response_periods / system.nu
        k = samples * m.response_periods * max(1, int(math.ceil(self.ratios.max())))
        self.t = self.period * np.arange(k) / k
        self._c = np.cos(np.outer(self.Omega, self.t))
        self._s = np.sin(np.outer(self.Omega, self.t))

    @property
    def dof(self) -> int:
        """``N``."""
        return self.system.dof

    def rates(self, U: np.ndarray) -> np.ndarray:
        """``dU/dt`` of the averaged flow."""
        n = self.dof
        u, v = U[:n, None], U[n:, None]
        w0 = self.omega0[:, None]
        x = u * self._c - v * self._s
        xd = -w0 * (u * self._s + v * self._c)
        g = self.system.acceleration(self.t, np.concatenate([x, xd])) + w0**2 * x
        shift = self.Omega - self.omega0
        du = np.mean(-g * self._s, axis=1) / self.omega0 + shift * U[n:]
        dv = np.mean(-g * self._c, axis=1) / self.omega0 - shift * U[:n]
        return np.concatenate([du, dv])

    def jacobian(self, U: np.ndarray) -> np.ndarray:
        """``df/dU`` by central differences."""
        m = len(U)
        J = np.empty((m, m))
        for k in range(m):
            h = 1e-6 * (1 + abs(U[k]))
            e = np.zeros(m)
            e[k] = h
            J[:, k] = (self.rates(U + e) - self.rates(U - e)) / (2 * h)
        return J

    def noise_covariance(self) -> np.ndarray:
        """``Q = diag(D/omega_i^2)`` for ``(u, v)``: the averaged noise of the rotating
        frame."""
        q = self.system.D / self.omega0**2
        return np.diag(np.concatenate([q, q]))

    def state(self, U: np.ndarray) -> SteadyState:
        """The :class:`SteadyState` at the fixed point ``U`` (Jacobian, eigenvalues)."""
        J = self.jacobian(U)
        ev = np.linalg.eigvals(J)
        ev = ev[np.lexsort((ev.real, ev.imag))]
        stable = bool(np.max(ev.real) < -1e-9 * (1 + np.max(np.abs(ev))))
        return SteadyState(np.asarray(U, dtype=float), J, ev, stable)


def averaged_flow(system: NoisySystem, samples: int = 128) -> AveragedFlow:
    """The first-order averaged flow of a forced system (:class:`AveragedFlow`)."""
    return AveragedFlow(system, samples)


def _newton(flow: AveragedFlow, U: np.ndarray, bound: float) -> np.ndarray | None:
    for _ in range(40):
        r = flow.rates(U)
        try:
            dU = np.linalg.solve(flow.jacobian(U), -r)
        except np.linalg.LinAlgError:
            return None
        U = U + dU
        if not np.all(np.isfinite(U)) or np.max(np.abs(U)) > 10 * bound:
            return None
        if np.max(np.abs(dU)) < 1e-12 * (1 + np.max(np.abs(U))):
            return U if np.max(np.abs(flow.rates(U))) < 1e-10 else None
    return None


def stable_states(flow: AveragedFlow, amplitudes: tuple[float, float] = (0.02, 5.0), *,
                  seeds: int = 96) -> list[SteadyState]:
    """Every stable fixed point of the averaged flow reached by Newton's method from a grid
    of seeds (one degree of freedom: amplitudes x phases; more: a fixed pseudo-random set
    in the box), sorted by the first mode's amplitude.

    Raises
    ------
    kbm.errors.ParameterError
        For a bad amplitude window.
    """
    lo, hi = amplitudes
    if not 0 <= lo < hi:
        raise ParameterError(f"the amplitude window must satisfy 0 <= a_min < a_max, got "
                             f"({lo}, {hi})")
    n = flow.dof
    if n == 1:
        na = max(4, seeds // 8)
        A, P = np.meshgrid(np.linspace(lo, hi, na), np.linspace(0, 2 * math.pi, 8,
                                                                  endpoint=False))
        starts = np.column_stack([(A * np.cos(P)).ravel(), (A * np.sin(P)).ravel()])
    else:
        rng = np.random.default_rng(0)
        starts = rng.uniform(-hi, hi, size=(seeds, 2 * n))
    found: list[SteadyState] = []
    for U0 in starts:
        U = _newton(flow, U0, hi)
        if U is None or any(np.max(np.abs(U - s.U)) < 1e-7 * (1 + hi) for s in found):
            continue
        found.append(flow.state(U))
    out = [s for s in found if s.stable]
    return sorted(out, key=lambda s: float(s.amplitudes()[0]))


def averaged_spectrum(flow: AveragedFlow, state: SteadyState, omega, mode: int = 0
                      ) -> np.ndarray:
    """The one-sided PSD of ``x_mode`` about ``state`` from the averaged flow (see the
    module docstring), at the angular frequencies ``omega``."""
    omega = np.asarray(omega, dtype=float)
    n = flow.dof
    m = 2 * n
    J, Q = state.jacobian, flow.noise_covariance()
    c = np.zeros(m, dtype=complex)
    c[mode], c[n + mode] = 1.0, 1.0j
    W = flow.Omega[mode]

    def s_z(w):
        H = np.linalg.inv(1j * w[:, None, None] * np.eye(m) - J[None])
        S = H @ Q @ np.conj(np.swapaxes(H, 1, 2)) / (2 * math.pi)
        return np.real(np.einsum("i,kij,j->k", c, S, np.conj(c)))

    return 0.5 * (s_z(omega - W) + s_z(-omega - W))


@dataclass(frozen=True)
class Orbit:
    """A periodic response of the full system: ``y(0)``, period, Floquet multipliers."""

    y0: np.ndarray
    period: float
    multipliers: np.ndarray

    @property
    def stable(self) -> bool:
        return bool(np.max(np.abs(self.multipliers)) < 1)


def _extended(system: NoisySystem, y0, T, rtol=1e-11):
    n2 = 2 * system.dof

    def rhs(t, z):
        y = z[:n2]
        Phi = z[n2:].reshape(n2, n2)
        return np.concatenate([system.field(t, y), (system.jacobian(t, y) @ Phi).ravel()])

    z0 = np.concatenate([np.asarray(y0, dtype=float), np.eye(n2).ravel()])
    sol = scipy.integrate.solve_ivp(rhs, (0.0, T), z0, method="DOP853", rtol=rtol,
                                    atol=rtol * 1e-2)
    z = sol.y[:, -1]
    return z[:n2], z[n2:].reshape(n2, n2)


def periodic_orbit(flow: AveragedFlow, state: SteadyState, tol: float = 1e-10) -> Orbit:
    """The true periodic response near the averaged ``state`` (shooting over the response
    period from ``x_i = u_i``, ``x_i' = -Omega_i v_i`` at ``t = 0``).

    Raises
    ------
    numerics.errors.ConvergenceError
        When Newton's method does not converge (the residual in the message).
    """
    system, n = flow.system, flow.dof
    y = np.concatenate([state.U[:n], -flow.omega0 * state.U[n:]])
    T = flow.period
    res = math.inf
    for _ in range(40):
        yT, Phi = _extended(system, y, T)
        r = yT - y
        res = float(np.max(np.abs(r)))
        dy = np.linalg.solve(Phi - np.eye(2 * n), -r)
        # damped: a step longer than a fifth of the state is cut back (the averaged guess is
        # O(mu) off, and the shooting matrix is nearly singular close to a fold)
        cap = 0.2 * (1 + np.max(np.abs(y)))
        y = y + dy * min(1.0, cap / max(np.max(np.abs(dy)), 1e-300))
        if np.max(np.abs(dy)) < tol * (1 + np.max(np.abs(y))):
            yT, Phi = _extended(system, y, T)
            return Orbit(y, T, np.linalg.eigvals(Phi))
    raise ConvergenceError(f"no periodic response of {system.model.name} near the averaged "
                           f"state {np.round(state.U, 6).tolist()} (residual {res:.3g})")


def floquet_spectrum(system: NoisySystem, orbit: Orbit, omega, mode: int = 0,
                     steps: int = 1024) -> tuple[np.ndarray, float]:
    """The one-sided time-averaged PSD of ``x_mode`` of the SDE linearised about ``orbit``
    (the module docstring), and the period-averaged variance ``<dx^2>``.

    ``steps`` Runge-Kutta steps per period (global error ``O((T/steps)^4)``)."""
    omega = np.asarray(omega, dtype=float)
    n2 = 2 * system.dof
    k = mode
    B = np.zeros((n2, n2))
    B[system.dof:, system.dof:] = 2 * system.D * np.eye(system.dof)
    T = orbit.period
    h = T / steps

    def run(P0, with_y: bool):
        y = np.array(orbit.y0, dtype=float)
        Phi = np.eye(n2)
        P = np.array(P0, dtype=float)
        nw = len(omega)
        Y = np.zeros((nw, n2), dtype=complex)
        IY = np.zeros((nw, n2), dtype=complex)
        IK = np.zeros((nw, n2, n2), dtype=complex)
        Pbar = np.zeros((n2, n2))

        def d(t, y, Phi, P, Y):
            A = system.jacobian(t, y)
            out = [system.field(t, y), A @ Phi, A @ P + P @ A.T + B]
            if with_y:
                out += [Y @ A.T - 1j * omega[:, None] * Y + P[:, k][None, :],
                        Y, np.exp(-1j * omega * t)[:, None, None] * Phi[None], P]
            return out

        for j in range(steps):
            t = j * h
            s = (y, Phi, P, Y) if with_y else (y, Phi, P, None)
            k1 = d(t, *s)
            k2 = d(t + h / 2, *[a + h / 2 * b for a, b in zip(s[:3], k1[:3])],
                   s[3] + h / 2 * k1[3] if with_y else None)
            k3 = d(t + h / 2, *[a + h / 2 * b for a, b in zip(s[:3], k2[:3])],
                   s[3] + h / 2 * k2[3] if with_y else None)
            k4 = d(t + h, *[a + h * b for a, b in zip(s[:3], k3[:3])],
                   s[3] + h * k3[3] if with_y else None)
            inc = [(a + 2 * b + 2 * c + e) * (h / 6) for a, b, c, e in zip(k1, k2, k3, k4)]
            y, Phi, P = y + inc[0], Phi + inc[1], P + inc[2]
            if with_y:
                Y, IY, IK, Pbar = Y + inc[3], IY + inc[4], IK + inc[5], Pbar + inc[6]
        return Phi, P, Y, IY, IK, Pbar

    M, W, *_ = run(np.zeros((n2, n2)), False)
    P0 = scipy.linalg.solve_discrete_lyapunov(M, W)
    P0 = 0.5 * (P0 + P0.T)
    _, _, Y, IY, IK, Pbar = run(P0, True)
    lhs = np.eye(n2)[None] - np.exp(-1j * omega * T)[:, None, None] * M[None]
    Y0 = np.linalg.solve(lhs, Y[..., None])[..., 0]
    Ybar = (np.einsum("wij,wj->wi", IK, Y0) + IY) / T
    return 2 / math.pi * np.real(Ybar[:, k]), float(Pbar[k, k] / T)


def detuning_name(model) -> str:
    """The forcing detuning's name of a forced model (``sigma`` for the built-ins).

    Raises
    ------
    kbm.errors.ParameterError
        For a model without a forcing detuning.
    """
    from kbm.model.coupled_builtins import get_coupled_model

    m = get_coupled_model(model) if isinstance(model, str) else model
    if not m.forced or not m.nu_detuning:
        raise ParameterError(f"{m.name!r} has no forcing detuning: a response spectrum needs "
                             "a forced model with nu = nu0 + mu sigma")
    return m.nu_detuning
