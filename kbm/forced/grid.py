"""Two-angle series sampled on a grid: the algebra of the numeric forced KBM backend.

A series ``f(a, psi, theta; sigma)`` is held as its values on the tensor grid of ``P``
Chebyshev points ``a_i`` of an amplitude interval (:mod:`kbm.algebra.chebyshev`), ``M``
equispaced phases ``psi_j`` and ``N`` equispaced forcing angles ``theta_l``, for each power
of the detuning ``sigma`` it holds: an array ``(d + 1, P, M, N)``, row ``s`` the coefficient
of ``sigma**s``.  The recursion is polynomial in ``sigma`` (it enters through
``D_1 = ... + sigma d/dtheta`` only), so at order ``n`` every quantity has degree
``< n`` and the truncation of products at degree ``order - 1`` is exact.

Products are pointwise in the grid and Cauchy products in the powers of ``sigma``;
``d/dpsi``, ``d/dtheta``, ``L0 = omega0 d/dpsi + nu0 d/dtheta``, the resonant part and the
division by ``omega0**2 - (m omega0 + k nu0)**2`` act on the two-dimensional discrete
Fourier transform in ``(psi, theta)``; ``d/da`` is Chebyshev differentiation.  As in the
autonomous :class:`~kbm.algebra.grid_fourier.GridAlgebra`, spectral coefficients below
``chop`` times the largest are dropped before a differentiation (rounding noise above the
bandwidth would be amplified), and the Nyquist modes are dropped.

The resonant harmonics of the declared resonance ``p/q`` are ``(m, k) = (+-1 + j p, -j q)``
(:mod:`kbm.forced.engine`); the secular part of ``R_n``, ``P(phi) cos psi + Q(phi) sin psi``
with ``phi = psi - (q/p) theta``, gives ``A_n = -Q/(2 omega0)`` and
``B_n = -P/(2 omega0 a)``, both held as series of the slow harmonics ``(j p, -j q)``.
"""

from __future__ import annotations

import numpy as np

from ..algebra import chebyshev
from ..algebra.grid_fourier import Samples
from ..recursion import SlowRates
from .model import Resonance

__all__ = ["SampledSeries", "SampledAlgebra"]


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
    """The forced recursion's algebra on a ``P x M x N`` grid (see the module docstring): the
    case ``N = 1`` with a forcing angle of :class:`~kbm.algebra.base.RecursionAlgebra`.

    Parameters
    ----------
    omega0
        The linear frequency.
    ratio
        ``nu0/omega0 = p/q`` of the declared resonance.
    resonance
        The declared resonance.
    lo, hi
        The amplitude interval of the Chebyshev grid, ``0 < lo < hi``.
    P, M, N
        Chebyshev points in ``a``, phases in ``psi`` and in ``theta`` (``M``, ``N`` even).
    cap
        The highest power of ``sigma`` kept (``order - 1``).
    chop
        Relative size below which spectral coefficients are dropped before a
        differentiation.
    """

    exact = False
    dof = 1
    detuned = True  # a declared resonance: nu = nu0 + mu sigma

    def __init__(self, omega0: float, resonance: Resonance, lo: float, hi: float, P: int,
                 M: int, N: int, cap: int, chop: float = 1e-14):
        self.w0 = float(omega0)
        self.res = resonance
        self.nu0 = self.w0 * resonance.p / resonance.q
        self.lo, self.hi, self.P, self.M, self.N = float(lo), float(hi), int(P), int(M), int(N)
        self.cap, self.chop = int(cap), float(chop)
        self.a = chebyshev.points(lo, hi, P)
        self.psi = 2 * np.pi * np.arange(M) / M
        self.theta = 2 * np.pi * np.arange(N) / N
        m = np.rint(np.fft.fftfreq(M) * M).astype(int)
        k = np.rint(np.fft.fftfreq(N) * N).astype(int)
        self.m, self.k = m, k
        mm, kk = np.meshgrid(m, k, indexing="ij")
        nyquist = (mm == -M // 2) | (kk == -N // 2)
        self._keep = ~nyquist
        p, q = resonance.p, resonance.q
        j = np.where(kk % q == 0, -kk // q, 0)
        self._resonant = (kk % q == 0) & (np.abs(mm - j * p) == 1)
        freq = mm * self.w0 + kk * self.nu0
        self._iL0 = np.where(self._keep, 1j * freq, 0.0)
        self._im = np.where(self._keep, 1j * mm, 0.0)
        self._ik = np.where(self._keep, 1j * kk, 0.0)
        div = self.w0**2 - freq.astype(float) ** 2
        ok = self._keep & ~self._resonant
        self._inv = np.where(ok, 1.0 / np.where(ok, div, 1.0), 0.0)
        # the slow harmonics (j p, -j q) with both resonant partners (+-1 + j p, -j q) on
        # the grid: index triples into the spectrum
        slow = []
        jmax = min((M // 2 - 2) // p, (N // 2 - 1) // q)
        for jj in range(-jmax, jmax + 1):
            slow.append((jj, (jj * p) % M, (1 + jj * p) % M, (-1 + jj * p) % M, (-jj * q) % N))
        self.slow = slow
        self._grid = (P, M, N)

    # -- helpers ----------------------------------------------------------------------
    def _series(self, values: np.ndarray | None) -> SampledSeries:
        return SampledSeries(values, self.cap)

    def _spectral(self, f: SampledSeries, mult: np.ndarray, chop: bool = True) -> SampledSeries:
        if f.values is None:
            return f
        spec = np.fft.fft2(f.values, axes=(2, 3))
        if chop:
            spec[np.abs(spec) < self.chop * np.max(np.abs(spec))] = 0.0
        return self._series(np.fft.ifft2(spec * mult, axes=(2, 3)).real)

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
        return self._spectral(f, self._iL0, chop=False)

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
        v = np.concatenate([np.zeros((s,) + self._grid), f.values])[:self.cap + 1]
        return self._series(v)

    def da(self, f: SampledSeries, l: int = 0) -> SampledSeries:
        """``df/da`` by the Chebyshev coefficients (small ones dropped first)."""
        if f.values is None:
            return f
        return self._series(chebyshev.differentiate(f.values, self.lo, self.hi, 1, self.chop))

    def _spectrum(self, values: np.ndarray) -> np.ndarray:
        """The normalised two-dimensional Fourier coefficients in ``(psi, theta)``."""
        return np.fft.fft2(values, axes=(2, 3)) / (self.M * self.N)

    def slow_coefficients(self, f: SampledSeries, times_a: bool = False) -> np.ndarray:
        """The coefficients of ``exp(i j p phi)`` of a slow series ``f`` (of ``a f`` with
        ``times_a``): an array ``(cap + 1, P, 2 J + 1)``, zero rows above ``f``'s degree."""
        out = np.zeros((self.cap + 1, self.P, len(self.slow)), dtype=complex)
        if f.values is None:
            return out
        v = f.values * (self.a[None, :, None, None] if times_a else 1.0)
        spec = self._spectrum(v)
        for i, (_j, islow, _ip, _im, ik) in enumerate(self.slow):
            out[:v.shape[0], :, i] = spec[:, :, islow, ik]
        return out

    def slow_spectrum(self, R: SampledSeries) -> tuple[np.ndarray, np.ndarray]:
        """``(A, a B)`` of the resonant part of ``R`` as coefficients of ``exp(i j p phi)``:
        arrays ``(d + 1, P, 2 J + 1)`` (``j = -J..J``)."""
        spec = self._spectrum(R.values)
        Aj, Bj = [], []
        for _j, _s, ip, im, ik in self.slow:
            gp, gm = spec[:, :, ip, ik], spec[:, :, im, ik]
            Aj.append(-1j * (gp - gm) / (2 * self.w0))
            Bj.append(-(gp + gm) / (2 * self.w0))
        return np.stack(Aj, axis=-1), np.stack(Bj, axis=-1)

    def secular(self, R: SampledSeries, i: int = 0, n: int = 0
                ) -> tuple[SampledSeries, SampledSeries]:
        """``(A_n, B_n)``: the resonant part of ``R_n`` as series of the slow harmonics."""
        if R.values is None:
            return self.zero(), self.zero()
        A, aB = self.slow_spectrum(R)
        d = R.values.shape[0]
        sa = np.zeros((d, self.P, self.M, self.N), dtype=complex)
        sb = np.zeros_like(sa)
        for i, (_j, islow, _ip, _im, ik) in enumerate(self.slow):
            sa[:, :, islow, ik] = A[..., i]
            sb[:, :, islow, ik] = aB[..., i]
        scale = self.M * self.N
        av = np.fft.ifft2(sa * scale, axes=(2, 3)).real
        bv = np.fft.ifft2(sb * scale, axes=(2, 3)).real / self.a[None, :, None, None]
        return self._series(av), self._series(bv)

    def solve(self, R: SampledSeries, i: int, n: int) -> SampledSeries:
        """``u_n``: every non-resonant harmonic over ``omega0**2 - (m omega0 + k nu0)**2``."""
        return self._spectral(R, self._inv, chop=False)
