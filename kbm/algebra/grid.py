"""Series sampled on a grid: the one algebra of the numeric KBM backends of one degree of
freedom, forced or not.

A series ``f(a, psi, theta; sigma)`` is held as its values on the tensor grid of ``P``
Chebyshev points ``a_i`` of an amplitude interval (:mod:`kbm.algebra.chebyshev`), ``M``
equispaced phases ``psi_j`` and ``N`` equispaced forcing angles ``theta_l``, for each power
of the detuning ``sigma`` it holds: an array ``(d + 1, P, M, N)``, row ``s`` the coefficient
of ``sigma**s``.  The recursion is polynomial in ``sigma`` (it enters through
``D_1 = ... + sigma d/dtheta`` only), so at order ``n`` every quantity has degree
``< n`` and the truncation of products at degree ``order - 1`` is exact.  An autonomous
``F`` (:mod:`kbm.backend.one_dof`) is the case without a forcing angle: ``N = 1``, degree 0.

Products are pointwise in the grid and Cauchy products in the powers of ``sigma``;
``d/dpsi``, ``d/dtheta``, ``L0 = omega0 d/dpsi + nu0 d/dtheta``, the resonant part and the
division by ``omega0**2 - (m omega0 + k nu0)**2`` act on the discrete Fourier transform in
``(psi, theta)`` (real in ``psi``: harmonics ``m >= 0``); ``d/da`` is Chebyshev
differentiation.  Spectral coefficients below ``chop`` times the largest are dropped before
a differentiation (rounding noise above the bandwidth would be amplified), and the Nyquist
modes are dropped.

The resonant harmonics of the declared resonance ``p/q`` are ``(m, k) = (+-1 + j p, -j q)``
(:mod:`kbm.expansion.forced`; without forcing ``m = +-1``); the secular part of ``R_n``,
``P(phi) cos psi + Q(phi) sin psi`` with ``phi = psi - (q/p) theta``, gives
``A_n = -Q/(2 omega0)`` and ``B_n = -P/(2 omega0 a)``, both held as series of the slow
harmonics ``(j p, -j q)`` (without forcing: functions of ``a``, of shape ``(d + 1, P, 1, 1)``).
"""

from __future__ import annotations

import numpy as np

from . import chebyshev
from .grid_fourier import Samples
from .lazy_series import Scaled
from .smooth import SmoothBuilder, TaylorTable
from ..expansion.recursion import SlowRates, kbm_recursion
from ..model.forced import Resonance

__all__ = ["SampledSeries", "SampledAlgebra", "sampled_recursion"]


class SampledSeries(Samples):
    """Samples ``(d + 1, P, M, N)`` (rows: powers of ``sigma``); ``values is None`` is zero.

    ``cap`` is the highest power of ``sigma`` kept in products.
    """

    __slots__ = ("cap",)

    def __init__(self, values: np.ndarray | None, cap: int):
        self.values = values
        self.cap = cap

    def _new(self, values: np.ndarray | None) -> "SampledSeries":
        return SampledSeries(values, self.cap)

    def _plus(self, other: "SampledSeries") -> "SampledSeries":
        d1, d2 = self.values.shape[0], other.values.shape[0]
        if d1 == d2:
            return self._new(self.values + other.values)
        big, small = (self.values, other.values) if d1 > d2 else (other.values, self.values)
        out = big.copy()
        out[:small.shape[0]] += small
        return self._new(out)

    def __mul__(self, other: "SampledSeries") -> "SampledSeries":
        if self.values is None or other.values is None:
            return self._new(None)
        f, g = self.values, other.values
        if f.shape[0] == g.shape[0] == 1:
            return self._new(f * g)
        deg = min(f.shape[0] + g.shape[0] - 2, self.cap)
        out = np.zeros((deg + 1,) + np.broadcast_shapes(f.shape[1:], g.shape[1:]))
        for i in range(f.shape[0]):
            for j in range(min(g.shape[0], deg + 1 - i)):
                out[i + j] += f[i] * g[j]
        return self._new(out)

    def scale(self, c) -> "SampledSeries":
        """``c f`` for a number or another series."""
        if isinstance(c, SampledSeries):
            return self * c
        return self.scale_q(c)


class SampledAlgebra(SlowRates):
    """The recursion's algebra on a ``P x M x N`` grid (see the module docstring): the case
    ``N = 1`` of :class:`~kbm.algebra.base.RecursionAlgebra`, with a forcing angle when a
    resonance is declared.

    Parameters
    ----------
    omega0
        The linear frequency.
    resonance
        The declared resonance ``p/q`` (``nu0 = (p/q) omega0``), or ``None`` for an
        autonomous ``F``: no forcing angle (``N = 1``), no detuning (``cap = 0``).
    lo, hi
        The amplitude interval of the Chebyshev grid, ``0 < lo < hi``.
    P, M, N
        Chebyshev points in ``a``, phases in ``psi`` and in ``theta`` (``M``, ``N`` even, or
        ``N = 1``).
    cap
        The highest power of ``sigma`` kept (``order - 1``).
    chop
        Relative size below which spectral coefficients are dropped before a
        differentiation.
    """

    exact = False
    dof = 1

    def __init__(self, omega0: float, resonance: Resonance | None, lo: float, hi: float,
                 P: int, M: int, N: int = 1, cap: int = 0, chop: float = 1e-14):
        self.w0 = float(omega0)
        self.res = resonance
        self.detuned = resonance is not None  # nu = nu0 + mu sigma
        p, q = (resonance.p, resonance.q) if self.detuned else (1, 1)
        self.nu0 = self.w0 * p / q if self.detuned else 0.0
        self.lo, self.hi, self.P, self.M, self.N = float(lo), float(hi), int(P), int(M), int(N)
        self.cap, self.chop = int(cap), float(chop)
        self.a = chebyshev.points(lo, hi, P)
        self.psi = 2 * np.pi * np.arange(M) / M
        self.theta = 2 * np.pi * np.arange(N) / N
        m = np.arange(M // 2 + 1)
        k = np.rint(np.fft.fftfreq(N) * N).astype(int)
        mm, kk = np.meshgrid(m, k, indexing="ij")
        keep = (mm != M // 2) & ((kk != -N // 2) | (N == 1))  # the Nyquist modes dropped
        j = np.where(kk % q == 0, -kk // q, 0)
        resonant = (kk % q == 0) & (np.abs(mm - j * p) == 1)
        freq = mm * self.w0 + kk * self.nu0
        self._iL0 = np.where(keep, 1j * freq, 0.0)
        self._im = np.where(keep, 1j * mm, 0.0)
        self._ik = np.where(keep, 1j * kk, 0.0)
        div = self.w0**2 - freq.astype(float) ** 2
        ok = keep & ~resonant
        self._inv = np.where(ok, 1.0 / np.where(ok, div, 1.0), 0.0)
        # the slow harmonics j: (j p, -j q), with both resonant partners (+-1 + j p, -j q)
        # on the grid
        jmax = min((M // 2 - 2) // p, (N // 2 - 1) // q) if self.detuned else 0
        self.slow = list(range(-jmax, jmax + 1))
        self._pq = (p, q)
        self._grid = (P, M, N)

    # -- the transforms -----------------------------------------------------------------
    def _fft(self, values: np.ndarray) -> np.ndarray:
        """The discrete Fourier transform in ``(psi, theta)`` (``m >= 0``)."""
        spec = np.fft.rfft(values, axis=2)
        return np.fft.fft(spec, axis=3) if self.N > 1 else spec

    def _ifft(self, spec: np.ndarray) -> np.ndarray:
        if self.N > 1:
            spec = np.fft.ifft(spec, axis=3)
        return np.fft.irfft(spec, n=self.M, axis=2)

    def _at(self, spec: np.ndarray, m: int, k: int) -> np.ndarray:
        """The coefficient of ``exp(i (m psi + k theta))`` from the half spectrum."""
        if m >= 0:
            return spec[:, :, m, k % self.N]
        return np.conj(spec[:, :, -m, -k % self.N])

    def _series(self, values: np.ndarray | None) -> SampledSeries:
        return SampledSeries(values, self.cap)

    def _spectral(self, f: SampledSeries, mult: np.ndarray, chop: bool = True) -> SampledSeries:
        if f.values is None:
            return f
        spec = self._fft(f.values)
        if chop:
            spec[np.abs(spec) < self.chop * np.max(np.abs(spec))] = 0.0
        return self._series(self._ifft(spec * mult))

    def sample(self, values: np.ndarray) -> SampledSeries:
        """A series of degree 0 in ``sigma`` from its samples ``(P, M, N)``."""
        return self._series(np.broadcast_to(values, self._grid)[None].astype(float))

    # -- the recursion's vocabulary ---------------------------------------------------
    def zero(self) -> SampledSeries:
        return self._series(None)

    def x0(self, i: int = 0) -> SampledSeries:
        """``a cos(psi)``."""
        return self.sample(self.a[:, None, None] * np.cos(self.psi)[None, :, None])

    def L0(self, f: SampledSeries) -> SampledSeries:
        """``omega0 df/dpsi + nu0 df/dtheta``; without forcing the small coefficients are
        dropped first, as in :meth:`dpsi` (at order 20 the rounding noise that ``L0``
        passes on grows without bound over the phases; with forcing, dropping them raises
        the slider's order-3 error from 1e-13 to 4e-11)."""
        return self._spectral(f, self._iL0, chop=not self.detuned)

    def dpsi(self, f: SampledSeries, l: int = 0) -> SampledSeries:
        return self._spectral(f, self._im)

    def sigma_dtheta(self, f: SampledSeries) -> SampledSeries:
        """``sigma df/dtheta``: one power of ``sigma`` up (dropped beyond ``cap``)."""
        d = self._spectral(f, self._ik)
        return self.sigma_power(d, 1)

    def sigma_power(self, f: SampledSeries, s: int) -> SampledSeries:
        """``sigma**s f`` (truncated at ``cap``)."""
        if f.values is None or s == 0:
            return f
        if s > self.cap:
            return self.zero()
        v = np.concatenate([np.zeros((s,) + f.values.shape[1:]), f.values])[:self.cap + 1]
        return self._series(v)

    def da(self, f: SampledSeries, l: int = 0) -> SampledSeries:
        """``df/da`` by the Chebyshev coefficients (small ones dropped first)."""
        if f.values is None:
            return f
        return self._series(chebyshev.differentiate(f.values, self.lo, self.hi, 1, self.chop))

    def slow_coefficients(self, f: SampledSeries, times_a: bool = False) -> np.ndarray:
        """The coefficients of ``exp(i j p phi)`` of a slow series ``f`` (of ``a f`` with
        ``times_a``): an array ``(cap + 1, P, 2 J + 1)``, zero rows above ``f``'s degree."""
        out = np.zeros((self.cap + 1, self.P, len(self.slow)), dtype=complex)
        if f.values is None:
            return out
        v = f.values * (self.a[None, :, None, None] if times_a else 1.0)
        spec = self._fft(v) / (self.M * self.N)
        p, q = self._pq
        for i, j in enumerate(self.slow):
            out[:v.shape[0], :, i] = self._at(spec, j * p, -j * q)
        return out

    def secular(self, R: SampledSeries, i: int = 0, n: int = 0
                ) -> tuple[SampledSeries, SampledSeries]:
        """``(A_n, B_n)``: the resonant part of ``R_n`` as series of the slow harmonics."""
        if R.values is None:
            return self.zero(), self.zero()
        if not self.detuned:  # the first harmonic, by projection: functions of a
            c = R.values[..., 0] @ np.cos(self.psi) * (2.0 / self.M)
            s = R.values[..., 0] @ np.sin(self.psi) * (2.0 / self.M)
            return (self._series((-s / (2 * self.w0))[..., None, None]),
                    self._series((-c / (2 * self.w0 * self.a))[..., None, None]))
        spec = self._fft(R.values) / (self.M * self.N)
        p, q = self._pq
        sa = np.zeros_like(spec)
        sb = np.zeros_like(spec)
        for j in self.slow:
            if j * p < 0:  # held by its conjugate partner
                continue
            gp, gm = self._at(spec, 1 + j * p, -j * q), self._at(spec, -1 + j * p, -j * q)
            sa[:, :, j * p, -j * q % self.N] = -1j * (gp - gm) / (2 * self.w0)
            sb[:, :, j * p, -j * q % self.N] = -(gp + gm) / (2 * self.w0)
        scale = self.M * self.N
        av = self._ifft(sa * scale)
        bv = self._ifft(sb * scale) / self.a[None, :, None, None]
        return self._series(av), self._series(bv)

    def solve(self, R: SampledSeries, i: int = 0, n: int = 0) -> SampledSeries:
        """``u_n``: every non-resonant harmonic over ``omega0**2 - (m omega0 + k nu0)**2``."""
        return self._spectral(R, self._inv, chop=False)


def sampled_recursion(alg: SampledAlgebra, tables: dict[int, TaylorTable], order: int
                      ) -> tuple[list, list, list]:
    """:func:`~kbm.expansion.recursion.kbm_recursion` over ``alg`` for
    ``F = sum_i (mu sigma)**i F_i`` (``tables``: ``{i: TaylorTable of F_i}``, the forcing angle its
    extra argument when forced): the lists ``A_1..A_N``, ``B_1..B_N``, ``u_1..u_N`` of
    :class:`SampledSeries`."""
    extra = (np.broadcast_to(alg.theta, alg._grid),) if alg.detuned else ()

    def terms(XL, VL):
        out = []
        for i, table in tables.items():
            node = SmoothBuilder(alg, XL[0], VL[0], table, extra).build(table.F)
            if i:
                node = Scaled(alg.zero, node, lambda f, i=i: alg.sigma_power(f, i))
            out.append((i, node))
        return [out]

    (A,), (B,), (U,) = kbm_recursion(alg, terms, order)
    return A, B, U
