"""The phase portrait of the conservative part ``x'' + g(x) = 0``.

Equilibria are the zeros of ``g`` (centers where ``g' > 0``, saddles where
``g' < 0``); the closed orbits of energy ``E = v**2/2 + G(x)`` form period
annuli, organised as the merge tree of the wells of ``G``: each well up to its
lowest bounding saddle, bands of orbits encircling several wells between
consecutive saddle energies, and the outer annulus above the highest saddle.

Integrals over an orbit use the substitution ``x = c - r cos s`` (``c``, ``r``
from the turning points ``x- < x+``), for which ``E - G(x) = r**2 sin(s)**2 q``
with ``q > 0`` smooth, so that

``T(E) = 2 int_0^pi ds / sqrt(2 q)``,
``Gamma(E) = int_0^pi [h(x, v+) - h(x, -v+)] r sin(s) ds``, ``v+ = r sin(s) sqrt(2 q)``

have smooth, even, periodic integrands: the midpoint (Gauss-Chebyshev) rule
converges spectrally.  The number of nodes is doubled until two estimates agree
to the tolerance; near a separatrix (``T -> inf``) that takes many nodes, and
the error estimate reports it.

References
----------
S. Coppola and R. H. Rand, Acta Mechanica 81 (1990); paper eq. (10) for Gamma.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from kbm.model.conservative import ConservativeSplit

from . import _turning
from ._zeros import _bracket, _zeros

__all__ = ["Equilibrium", "Annulus", "Portrait", "phase_portrait", "Quadrature"]


@dataclass(frozen=True)
class Equilibrium:
    """A zero of ``g``: ``kind`` is ``"center"`` (``g' > 0``) or ``"saddle"`` (``g' < 0``).

    Attributes
    ----------
    x : float
    kind : str
    energy : float
        ``G(x)``.
    curvature : float
        ``g'(x)``.
    """

    x: float
    kind: str
    energy: float
    curvature: float


@dataclass(frozen=True)
class Quadrature:
    """Result of the spectral orbit integrals at a vector of energies.

    Attributes
    ----------
    period, gamma : numpy.ndarray
        ``T(E)`` and ``Gamma(E)`` (``gamma`` is zeros when not requested).
    error : numpy.ndarray
        ``|I_2n - I_n|`` of the last doubling, for ``T`` and ``Gamma`` (the larger).
    nodes : int
        Nodes of the last rule.
    converged : bool
        Whether every energy met the tolerance.
    """

    period: np.ndarray
    gamma: np.ndarray
    error: np.ndarray
    nodes: int
    converged: bool


@dataclass(frozen=True, eq=False)
class Annulus:
    """A period annulus ``energy_min < E < energy_max`` of the conservative system.

    Attributes
    ----------
    label : str
        ``"central well"``, ``"side well at x=+1.02"``, ``"band around 5 wells"``, ``"outer"``.
    energy_min, energy_max : float
        Bottom (center or highest inner saddle energy) and top (bounding saddle
        energy, ``inf`` for the outer annulus).
    wells : tuple of float
        The centers encircled.
    bounds : tuple of float
        ``(left_outer, left_inner, right_inner, right_outer)``: ``x-`` lies in
        ``(left_outer, left_inner)``, ``x+`` in ``(right_inner, right_outer)``.
    """

    label: str
    energy_min: float
    energy_max: float
    wells: tuple
    bounds: tuple
    _fun: tuple = ()
    _tables: dict = field(default_factory=dict, repr=False, compare=False)
    _scalar: tuple = ()

    @property
    def bounded(self) -> bool:
        """``False`` for the annulus reaching infinity."""
        return bool(np.isfinite(self.energy_max))

    def _solve(self, E, a, b, increasing):
        return _turning.solve(self._fun, self._tables, E, a, b, increasing)

    def _solve1(self, E: float, a: float, b: float, increasing: bool) -> float:
        """One turning point in Python floats (the math-module ``g``, ``G`` when known)."""
        if not self._scalar:
            return float(self._solve(np.array([E]), a, b, increasing)[0])
        return _turning.solve1(self._scalar, self._fun, self._tables, E, a, b, increasing)

    def turning_points(self, E) -> tuple[np.ndarray, np.ndarray]:
        """``(x-(E), x+(E))``, the solutions of ``G(x) = E`` bounding the orbit (vectorised)."""
        lo_out, lo_in, hi_in, hi_out = self.bounds
        return (self._solve(E, lo_out, lo_in, increasing=False),
                self._solve(E, hi_in, hi_out, increasing=True))

    def orbit_integrals(self, E, integrands, *, tol: float = 1e-12, n_start: int = 32,
                        n_max: int = 1 << 16) -> tuple[list, np.ndarray, int, bool]:
        """Integrals ``int_0^pi f(x(s), v+(s), sqrt(2 q(s))) ds`` over the upper half orbit.

        Parameters
        ----------
        E : array_like
            Energies inside the annulus.
        integrands : sequence of callable
            Each ``f(x, v, sq)`` with ``x = c - r cos s``, ``v = v+(x) = r sin(s) sq``
            and ``sq = sqrt(2 q) > 0`` (so ``dt = ds/sq``, ``dx = v ds/sq``); it must be
            a smooth even periodic function of ``s`` for spectral accuracy.
        tol : float
            Relative tolerance, against ``int |f| ds``.
        n_start, n_max : int
            First and largest number of midpoint nodes (doubled in between; the
            doubling also stops on the rounding plateau).

        Returns
        -------
        values : list of numpy.ndarray
        error : numpy.ndarray
            Largest relative change of the last doubling, per energy.
        nodes : int
            Nodes of the last rule (the largest over the energies: each energy is
            refined on its own until it meets the tolerance).
        converged : bool
        """
        G = self._fun[2]
        E = np.atleast_1d(np.asarray(E, float))
        xm, xp = self.turning_points(E)
        c, r = 0.5 * (xp + xm), 0.5 * (xp - xm)

        def rule(n, k):
            s = (np.arange(n) + 0.5) * np.pi / n
            xs = c[k, None] - r[k, None] * np.cos(s)
            rs = r[k, None] * np.sin(s)
            q = np.maximum((E[k, None] - G(xs)) / rs**2, np.finfo(float).tiny)
            sq = np.sqrt(2 * q)
            vals = [f(xs, rs * sq, sq) for f in integrands]
            w = np.pi / n
            return ([w * np.sum(v, axis=1) for v in vals],
                    [w * np.sum(np.abs(v), axis=1) for v in vals])

        # each energy is refined on its own: only those not yet converged get the
        # doubled rule (near a separatrix or at large E the others would be dragged along)
        nE = len(E)
        out = [np.zeros(nE) for _ in integrands]
        err = np.full(nE, np.inf)
        last = np.full(nE, np.inf)
        active = np.arange(nE)
        n = n_start
        I0, _ = rule(n, active)
        n_used = n
        while len(active):
            I1, S1 = rule(2 * n, active)
            e = np.max([np.abs(a - b) / np.maximum(s, 1e-300)
                        for a, b, s in zip(I1, I0, S1)], axis=0)
            n *= 2
            n_used = n
            err[active] = e
            for o, v in zip(out, I1):
                o[active] = v
            # stop at the tolerance, at n_max, or on the rounding plateau (E - G(x) loses
            # digits in shallow wells: the estimate then stops decreasing)
            stop = (e <= tol) | (2 * n > n_max) | ((n >= 256) & (e > 0.25 * last[active]))
            last[active] = e
            keep = ~stop
            active = active[keep]
            I0 = [v[keep] for v in I1]
        return out, err, n_used, bool(np.all(err <= tol))

    def quadrature(self, E, *, gamma: bool = False, tol: float = 1e-12,
                   n_start: int = 32, n_max: int = 1 << 16) -> Quadrature:
        """``T(E)`` and optionally ``Gamma(E) = oint h v dt`` (see :meth:`orbit_integrals`).

        Parameters
        ----------
        E : array_like
            Energies inside the annulus.
        gamma : bool
            Also integrate ``Gamma = int_{x-}^{x+} [h(x, v+) - h(x, -v+)] dx``.
        tol : float
            Relative tolerance of each integral.
        n_start, n_max : int
            First and largest number of nodes.
        """
        h = self._fun[3]
        funs = [lambda x, v, sq: 2.0 / sq]
        if gamma:
            funs.append(lambda x, v, sq: (h(x, v) - h(x, -v)) * v / sq)
        vals, err, n, ok = self.orbit_integrals(E, funs, tol=tol, n_start=n_start, n_max=n_max)
        gam = vals[1] if gamma else np.zeros_like(vals[0])
        return Quadrature(vals[0], gam, err, n, ok)

    def period(self, E, tol: float = 1e-12) -> np.ndarray:
        """``T(E)``, vectorised (see :meth:`quadrature`)."""
        return self.quadrature(E, tol=tol).period

    def summary(self) -> dict:
        """JSON-ready description (``energy_max`` ``None`` when infinite)."""
        return {"label": self.label, "energy_min": float(self.energy_min),
                "energy_max": float(self.energy_max) if self.bounded else None,
                "wells": [float(w) for w in self.wells]}


@dataclass(frozen=True, eq=False)
class Portrait:
    """Equilibria, separatrix energies and period annuli of ``x'' + g(x) = 0``.

    Attributes
    ----------
    split : kbm.model.conservative.ConservativeSplit
    equilibria : tuple of Equilibrium
        Sorted by ``x``.
    separatrix_energies : tuple of float
        The distinct saddle energies, increasing.
    annuli : tuple of Annulus
        Sorted by ``energy_min``.
    bracket : float
        All zeros of ``g`` lie in ``[-bracket, bracket]``.
    """

    split: ConservativeSplit
    equilibria: tuple
    separatrix_energies: tuple
    annuli: tuple
    bracket: float
    functions: tuple

    @property
    def outer(self) -> Annulus:
        """The annulus reaching infinity."""
        return next(a for a in self.annuli if not a.bounded)


def _label(wells, top, scale) -> str:
    if not np.isfinite(top) and len(wells) > 1:
        return "outer"
    if len(wells) == 1:
        w = wells[0]
        if abs(w) <= 1e-9 * scale:
            return "central well"
        return f"side well at x={w:+.3g}"
    return f"band around {len(wells)} wells"


def _scalar_functions(split: ConservativeSplit, fun: tuple) -> tuple:
    """``(g, G)`` lambdified for Python floats (``()`` when the math module cannot, or
    they disagree with the numpy ones)."""
    try:
        g, G = split.scalar_functions()
        z = np.array([-1.7, 0.3, 2.9])
        ok = all(np.allclose([float(f(v)) for v in z], F(z), rtol=1e-13, atol=1e-13)
                 for f, F in ((g, fun[0]), (G, fun[2])))
    except Exception:  # noqa: BLE001 - any failure: the numpy path
        return ()
    return (g, G) if ok else ()


def phase_portrait(split: ConservativeSplit) -> Portrait:
    """The conservative phase portrait of a split model.

    Parameters
    ----------
    split : kbm.model.conservative.ConservativeSplit

    Returns
    -------
    Portrait

    Raises
    ------
    kbm.model.conservative.NotConfiningError
        If ``g`` has no bracket outside of which it pushes back to the origin.
    """
    fun = split.numpy_functions()
    g, dg, G, _ = fun
    scalar = _scalar_functions(split, fun)
    L = _bracket(g, split)
    zs = _zeros(g, L)
    xs = np.array([z for z, _ in zs])
    kinds = ["center" if s > 0 else "saddle" for _, s in zs]
    Gs = G(xs) if len(xs) else np.array([])
    eqs = tuple(Equilibrium(float(xv), k, float(Ge), float(dg(np.array(xv))))
                for xv, k, Ge in zip(xs, kinds, Gs))
    scale = max(1.0, float(np.max(np.abs(xs)))) if len(xs) else 1.0
    etol = 1e-12 * max(1.0, float(np.max(np.abs(Gs)))) if len(Gs) else 1e-12
    annuli: list[Annulus] = []

    def build(i, j, top):
        lo_out = xs[i - 1] if i > 0 else -np.inf
        hi_out = xs[j + 1] if j + 1 < len(xs) else np.inf
        saddles = [k for k in range(i, j + 1) if kinds[k] == "saddle"]
        wells = tuple(float(xs[k]) for k in range(i, j + 1) if kinds[k] == "center")
        bottom = max(Gs[k] for k in saddles) if saddles else Gs[i]
        annuli.append(Annulus(_label(wells, top, scale), float(bottom), float(top), wells,
                              (lo_out, float(xs[i]), float(xs[j]), hi_out), fun,
                              _scalar=scalar))
        if not saddles:
            return
        cut = [k for k in saddles if Gs[k] >= bottom - etol]
        starts = [i] + [k + 1 for k in cut]
        ends = [k - 1 for k in cut] + [j]
        for a, b in zip(starts, ends):
            build(a, b, float(bottom))

    build(0, len(xs) - 1, np.inf)
    annuli.sort(key=lambda a: (a.energy_min, a.wells[0]))
    seps = tuple(sorted({round(float(G_), 12) for G_, k in zip(Gs, kinds) if k == "saddle"}))
    return Portrait(split, eqs, seps, tuple(annuli), L, fun)
