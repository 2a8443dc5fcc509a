"""The sampled multi-angle algebra of the coupled recursion: Taylor jets on a torus grid.

A quantity of the recursion at the amplitudes ``a*`` is a **jet**: its Taylor coefficients in
``Da = a - a*`` up to a degree, each a function on the ``M^D`` grid of the torus of the fast
angles (``D = N``, one more for the forcing angle ``theta``).  :class:`JetAlgebra` answers
the one recursion (:func:`kbm.expansion.recursion.kbm_recursion`, the
:class:`~kbm.algebra.base.RecursionAlgebra` protocol) on them:

- products are pointwise on the grid and Cauchy products of the Taylor coefficients;
- ``d/da_l`` shifts the coefficients (a jet of degree ``r`` gives one of degree ``r - 1``:
  every jet carries the degree up to which it is known);
- ``d/dpsi_l``, ``L0 = sum omega_l d/dpsi_l``, the resonant part of ``R_{i,n}`` and the
  division by ``omega_i^2 - (h . omega)^2`` act on the ``D``-dimensional FFT of each
  coefficient, with the slow lattice of the declared resonances as in the exact engine
  (:func:`kbm.expansion.resonance.resonant_harmonic`: the same harmonics are resonant, the
  same undeclared ones refused).

The driver, which makes ``F`` along the jets and refines the grid, is :mod:`kbm.backend.jets`.

One unforced mode (``N = 1``) is a case: :meth:`JetAlgebra.one_mode` holds a batch of
amplitudes ``a_q`` at once (a leading axis of the samples) and expands ``sin(k x)``,
``cos(k x)`` by their Jacobi-Anger series with exact Bessel jets
(:mod:`kbm.algebra.jet_fourier`); that is :func:`kbm.derive_values`.
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from functools import lru_cache
from typing import NamedTuple

import numpy as np
import sympy as sp

from .grid_fourier import Samples
from .jet_fourier import jacobi_anger_jets
from ..errors import ModelError, UnsupportedTermError
from .coupled import AngleCalculus
from ..model.coupled import CoupledOscillators
from ..expansion.resonance import SlowLattice, UndeclaredResonanceError, resonant_harmonic

__all__ = ["JetAlgebra", "JetSeries", "PRESENT"]


class _Modes(NamedTuple):
    """What the algebra reads of a coupled model (for one unforced mode:
    :meth:`JetAlgebra.one_mode`)."""

    dof: int
    forced: bool
    omegas: tuple
    nu0: object
    internal: tuple

#: a harmonic's Fourier coefficient below this fraction of the largest counts as absent
#: (rounding) when an undeclared resonant harmonic is looked for
PRESENT = 1e-11


def _multi_indices(n: int, degree: int) -> list[tuple[int, ...]]:
    """The multi-indices of ``n`` variables with ``|alpha| <= degree``, by degree."""
    out = []
    for total in range(degree + 1):
        for alpha in itertools.product(range(total + 1), repeat=n):
            if sum(alpha) == total:
                out.append(alpha)
    return out


class JetSeries(Samples):
    """Taylor coefficients ``(C, M, .., M)`` in the amplitudes, known to degree ``deg``
    (``values is None``: zero, known to every degree)."""

    __slots__ = ("alg", "deg")

    def __init__(self, alg: "JetAlgebra", values: np.ndarray | None, deg: int):
        self.alg, self.values, self.deg = alg, values, deg

    def _new(self, values, deg=None) -> "JetSeries":
        return JetSeries(self.alg, values, self.deg if deg is None else deg)

    def _plus(self, other: "JetSeries") -> "JetSeries":
        return self._new(self.values + other.values, min(self.deg, other.deg))

    def __mul__(self, other: "JetSeries") -> "JetSeries":
        if self.values is None or other.values is None:
            return self._new(None, self.alg.top)
        deg = min(self.deg, other.deg, self.alg.top)
        f, g = self.values, other.values
        out = np.zeros_like(f)
        for p, q, r in self.alg.pairs[deg]:
            out[r] += f[p] * g[q]
        return self._new(out, deg)

    def scale(self, c) -> "JetSeries":
        """``c f`` for a number or another jet."""
        if isinstance(c, JetSeries):
            return self * c
        return self.scale_q(c)

    def diff(self, l: int) -> "JetSeries":
        """``d/da_l``: the coefficients shifted, one degree less."""
        if self.values is None:
            return self
        if self.deg < 1:
            raise ModelError("internal error of the jet recursion: an amplitude derivative "
                             "of a jet known to degree 0")
        out = np.zeros_like(self.values)
        for src, dst, factor in self.alg.shifts[l]:
            if self.alg.degree[dst] < self.deg:
                out[dst] = factor * self.values[src]
        return self._new(out, self.deg - 1)

    def d_angle(self, l: int) -> "JetSeries":
        """``d/dpsi_l`` (``l = D - 1``: ``d/dtheta`` of a forced system)."""
        return self.alg.spectral(self, self.alg.ik[l])

    def value(self) -> np.ndarray:
        """The grid function at ``a*`` (the coefficient of ``Da**0``; with a batch of points
        its leading axis)."""
        if self.values is None:
            return np.zeros(self.alg.shape)
        return self.values[0]


class JetAlgebra(AngleCalculus):
    """The recursion's algebra at the amplitudes ``a*`` on an ``M^D`` torus grid (the sampled
    multi-angle :class:`~kbm.algebra.base.RecursionAlgebra`).

    Parameters
    ----------
    model
        The coupled model (values substituted; frequencies exact); only its ``dof``,
        ``forced``, ``omegas``, ``nu0`` and ``internal`` are read (:meth:`one_mode` gives
        just those).
    lattice
        The slow lattice of the declared resonances.
    point
        The amplitudes ``a*`` (positive): ``N`` numbers, or ``N`` rows of ``Q`` points
        computed at once (the samples then have a leading batch axis of length ``Q``).
    nodes
        Grid points per angle ``M`` (even).
    top
        The jets' degree (the order of the recursion).
    sigma
        The forcing detuning's value (``nu = nu0 + mu sigma``), or ``None``.
    tolerance
        As the exact engine's: a harmonic within this fraction of ``omega_i`` that is not
        declared resonant is refused when ``R_{i,n}`` holds it.
    parameters
        ``(symbols, values)`` of the parameters of ``F`` (arguments of its compiled
        derivatives).
    """

    def __init__(self, model: CoupledOscillators, lattice: SlowLattice, point: Sequence[float],
                 nodes: int, top: int, sigma: float | None, tolerance: float,
                 parameters: tuple = ((), ())):
        self.model, self.lattice, self.tol = model, lattice, tolerance
        self.parameters = parameters
        self.dof = N = model.dof
        self.forced = model.forced
        self.n = D = N + (1 if self.forced else 0)
        self.omega = tuple(model.omegas) + ((model.nu0,) if self.forced else ())
        self.w = np.array([float(v) for v in self.omega])
        self.point = np.asarray(point, dtype=float)
        self.M, self.top = int(nodes), int(top)
        self.sig = sigma
        self.detuned = sigma is not None
        self.batch = self.point.shape[1:]
        self.shape = self.batch + (self.M,) * D
        self.axes = tuple(range(-D, 0))  # the angles: the last D axes of the samples
        # a*_l, broadcast against the grid
        self._amp = [np.reshape(self.point[l], self.batch + (1,) * D) for l in range(N)]
        # the multi-indices of the amplitudes and the tables of products and derivatives
        self.index = _multi_indices(N, self.top)
        self.degree = [sum(a) for a in self.index]
        pos = {a: k for k, a in enumerate(self.index)}
        self.pairs = {}
        for d in range(self.top + 1):
            self.pairs[d] = [(pos[a], pos[b], pos[tuple(x + y for x, y in zip(a, b))])
                             for a in self.index for b in self.index
                             if sum(a) + sum(b) <= d]
        self.shifts = []
        for l in range(N):
            row = []
            for a in self.index:
                up = tuple(v + (1 if k == l else 0) for k, v in enumerate(a))
                if up in pos:
                    row.append((pos[up], pos[a], float(up[l])))
            self.shifts.append(row)
        self.pos = pos
        # the angles and the harmonics of the grid
        self.angles, self.cos, self.sin, self.shell = torus(self.M, D)
        self.h, self.keep, self.freq, self.ik, self.iL0 = _harmonics(self.omega, self.M)
        #: the largest Fourier coefficient of the F_i = R_{i,1} on the outer shell
        self.outer = 0.0
        self._modes = [_mode_table(self.omega, model.internal, self.forced, self.M, self.tol, i)
                       for i in range(N)]

    # -- the recursion's vocabulary ---------------------------------------------------------
    def zero(self) -> JetSeries:
        return JetSeries(self, None, self.top)

    def jet(self, values: np.ndarray, deg: int) -> JetSeries:
        return JetSeries(self, values, deg)

    @classmethod
    def one_mode(cls, omega0: float, a, top: int, nodes: int) -> "JetAlgebra":
        """One unforced mode ``x'' + omega0**2 x = mu F(x, x')`` at the amplitudes ``a``
        (1-D), all at once: the case ``N = 1`` of :func:`kbm.derive_values`.  Its only
        resonant harmonics are ``psi`` and ``-psi`` (``omega0`` enters exactly, as the
        rational of its float)."""
        modes = _Modes(1, False, (sp.Rational(float(omega0)),), None, ())
        return cls(modes, SlowLattice(1, ()), np.asarray(a, dtype=float)[None, :], nodes,
                   top, None, 0.0)

    def const(self, value) -> JetSeries:
        """The series ``value`` (a number: no angle, no amplitude)."""
        v = np.zeros((len(self.index),) + self.shape)
        v[0] = float(value)
        return self.jet(v, self.top)

    def coef(self, value) -> float:
        """A factor free of the state (a number)."""
        return float(value)

    def scale(self, f: JetSeries, c) -> JetSeries:
        """``c f`` for a number or a jet."""
        return f.scale(c)

    def trig(self, kind: str, c) -> list[JetSeries]:
        """``g(c x_0)`` and its first three derivatives, ``g = sin`` or ``cos``, for one
        unforced mode: the Jacobi-Anger series with exact Bessel jets in ``Da``
        (:func:`~kbm.algebra.jet_fourier.jacobi_anger_jets`)."""
        if self.n != 1:
            raise UnsupportedTermError("the Jacobi-Anger jets take one unforced mode; the "
                                       "coupled jets expand F by its Taylor series "
                                       "(kbm.backend.jets)")
        a = np.atleast_1d(self.point[0])
        return [self.jet(v.reshape((self.top + 1,) + self.shape), self.top)
                for v in jacobi_anger_jets(kind, float(c), a, self.top, self.M)]

    def at_amplitudes(self, f: JetSeries) -> np.ndarray:
        """The grid function of ``f`` at the amplitudes (degree 0 of the jet)."""
        return f.value()

    def x0(self, i: int) -> JetSeries:
        """``a_i cos(psi_i)``: ``a*_i cos psi_i + Da_i cos psi_i``, exact (linear in ``Da``):
        known beyond ``top``, so ``d/da_i`` of it and the velocity ``V_1`` keep degree ``top``
        (once ``top >= 1`` holds its ``Da`` term)."""
        v = np.zeros((len(self.index),) + self.shape)
        c = self.cos[i]
        v[0] = self._amp[i] * c
        if self.top:
            v[self.pos[tuple(1 if k == i else 0 for k in range(self.dof))]] = c
        return self.jet(v, self.top + 1 if self.top else 0)

    def spectral(self, f: JetSeries, mult: np.ndarray) -> JetSeries:
        if f.values is None:
            return f
        spec = np.fft.fftn(f.values, axes=self.axes)
        return f._new(np.fft.ifftn(spec * mult, axes=self.axes).real, f.deg)

    def L0(self, f: JetSeries) -> JetSeries:
        return self.spectral(f, self.iL0)

    def inverse_amplitude(self, i: int) -> JetSeries:
        """``1/a_i``: ``sum_k (-Da_i)^k / a*_i^(k+1)``."""
        v = np.zeros((len(self.index),) + self.shape)
        for k in range(self.top + 1):
            alpha = tuple(k if l == i else 0 for l in range(self.dof))
            v[self.pos[alpha]] = (-1) ** k / self._amp[i] ** (k + 1)
        return self.jet(v, self.top)

    def _spectrum(self, R: JetSeries, i: int, n: int) -> np.ndarray:
        spec = np.fft.fftn(R.values, axes=self.axes)
        if n == 1:  # R_{i,1} = F_i: its largest coefficient on the outer shell
            outer = spec[0][..., self.shell] / self.shell.size
            self.outer = max(self.outer, float(np.max(np.abs(outer))) if outer.size else 0.0)
        _, _, refused, _ = self._modes[i]
        if refused:
            big = float(np.max(np.abs(spec))) or 1.0
            for idx, h in refused:
                if np.max(np.abs(spec[(Ellipsis,) + idx])) > PRESENT * big:
                    resonant_harmonic(h, i, n, self.omega, self.lattice, self.tol,
                                      self.forced)  # raises, naming the resonance
        return spec

    def secular(self, R: JetSeries, i: int, n: int) -> tuple[JetSeries, JetSeries]:
        """``(A_{i,n}, B_{i,n})``: the resonant part ``e^{i psi_i} G + c.c.`` of ``R_{i,n}``,
        ``G = sum_k c_{psi_i + k} e^{i k . psi}`` slow, gives ``A = Im G / omega_i`` and
        ``B = -Re G / (omega_i a_i)``."""
        if R.values is None:
            return self.zero(), self.zero()
        spec = self._spectrum(R, i, n)
        res_h, res_k, _, _ = self._modes[i]
        G = np.zeros_like(spec)
        for h, k in zip(res_h, res_k):
            G[(Ellipsis,) + k] = spec[(Ellipsis,) + h]
        g = np.fft.ifftn(G, axes=self.axes)
        wi = self.w[i]
        A = R._new(g.imag / wi, R.deg)
        aB = R._new(-g.real / wi, R.deg)
        return A, aB * self.inverse_amplitude(i)

    def solve(self, R: JetSeries, i: int, n: int) -> JetSeries:
        """``u_{i,n}``: every non-resonant harmonic over ``omega_i^2 - (h . omega)^2``."""
        if R.values is None:
            return R
        spec = self._spectrum(R, i, n)
        return R._new(np.fft.ifftn(spec * self._modes[i][3], axes=self.axes).real, R.deg)


@lru_cache(maxsize=32)
def torus(M: int, D: int):
    """The ``M^D`` grid of the torus: its angles, their cosines and sines (one array per
    angle), and the mask of its outer shell (a harmonic ``|h_l| >= M/2 - 1`` in some angle).

    Pure-function memo: the key is two integers, the value read-only arrays computed from
    them alone."""
    ang = 2 * np.pi * np.arange(M) / M
    angles = tuple(np.meshgrid(*([ang] * D), indexing="ij"))
    cos = tuple(np.cos(a) for a in angles)
    sin = tuple(np.sin(a) for a in angles)
    h1 = np.rint(np.fft.fftfreq(M) * M).astype(int)
    shell = np.zeros((M,) * D, dtype=bool)
    for hl in np.meshgrid(*([h1] * D), indexing="ij"):
        shell |= np.abs(hl) >= M // 2 - 1
    for arr in (*angles, *cos, *sin, shell):
        arr.flags.writeable = False
    return angles, cos, sin, shell


@lru_cache(maxsize=32)
def _harmonics(omega: tuple, M: int):
    """The harmonics ``h`` of the ``M^D`` grid (one integer array per angle), the mask of
    those off the Nyquist planes, their frequencies ``h . omega``, and the multipliers of
    ``d/dpsi_l`` and ``L0`` (``i h_l`` and ``i h . omega``, zero on the Nyquist planes).

    Pure-function memo: the key is a tuple of frequencies and an integer, the value
    read-only arrays computed from them alone."""
    D = len(omega)
    h1 = np.rint(np.fft.fftfreq(M) * M).astype(int)
    hs = np.meshgrid(*([h1] * D), indexing="ij")
    keep = np.ones(hs[0].shape, dtype=bool)
    for hl in hs:
        keep &= hl != -M // 2
    freq = sum(hl * float(w) for hl, w in zip(hs, omega))
    ik = tuple(np.where(keep, 1j * hl, 0.0) for hl in hs)
    iL0 = np.where(keep, 1j * freq, 0.0)
    for arr in (*hs, keep, freq, *ik, iL0):
        arr.flags.writeable = False
    return tuple(hs), keep, freq, ik, iL0


@lru_cache(maxsize=64)
def _mode_table(omega: tuple, internal: tuple, forced: bool, M: int, tol: float, i: int):
    """For mode ``i`` on the ``M^D`` grid: the resonant harmonics ``h = psi_i + k`` (index of
    ``h`` and of ``k``), the refused ones (undeclared, within ``tol``) with ``h``, and
    ``1/(omega_i^2 - (h . omega)^2)`` elsewhere (zero on the resonant ones, the refused ones
    and the Nyquist modes).

    Pure-function memo (the exact classification of
    :func:`~kbm.expansion.resonance.resonant_harmonic` is slow): the key is tuples of
    frequencies and frozen resonances, a ``bool``, integers and a float, the value tuples and
    a read-only array computed from them alone."""
    lattice = SlowLattice(len(omega), internal)
    hs, keep, freq, _, _ = _harmonics(omega, M)
    wi = float(omega[i])
    gap = np.abs(np.abs(freq) - wi) / wi
    res_h, res_k, refused = [], [], []
    mask = np.zeros(freq.shape, dtype=bool)
    for idx in np.argwhere((gap <= tol * (1 + 1e-9)) & keep):
        idx = tuple(int(v) for v in idx)
        h = tuple(int(hl[idx]) for hl in hs)
        try:
            res = resonant_harmonic(h, i, 0, omega, lattice, tol, forced)
        except UndeclaredResonanceError:
            refused.append((idx, h))
            continue
        if res is None:
            continue
        k, sgn = res
        mask[idx] = True
        if sgn > 0 and all(abs(v) < M // 2 for v in k):
            res_h.append(idx)
            res_k.append(tuple(v % M for v in k))
    ok = keep & ~mask
    for idx, _ in refused:
        ok[idx] = False
    inv = np.where(ok, 1.0 / np.where(ok, wi**2 - freq**2, 1.0), 0.0)
    inv.flags.writeable = False
    return tuple(res_h), tuple(res_k), tuple(refused), inv
