"""The coupled KBM recursion to any order for any smooth ``F``, at one point of the amplitudes.

:func:`kbm.expansion.coupled.derive_coupled` runs the recursion on exact series (polynomial ``F``);
this is the one numeric coupled backend for any smooth ``F``, forced or not: the first order
(:func:`first_order`, behind :func:`kbm.backend.coupled.numeric_average`) is the same recursion on
jets of degree 0, one FFT of ``F`` on the torus per mode.  Beyond the first order the
recursion differentiates in the amplitudes
(``D_j = sum_l A_{l,j} d/da_l + B_{l,j} d/dpsi_l``), so the numeric backend needs the
quantities of the lower orders *with* their amplitude derivatives.  Here every quantity is a
**jet**: its Taylor coefficients in ``Da = a - a*`` at the point ``a*`` up to a degree, each a
function on the ``M^D`` grid of the torus of the fast angles (``D = N``, one more for the
forcing angle ``theta``; the algebra of :mod:`kbm.algebra.coupled_jets`).  Then

- products, ``d/da_l`` (a jet of degree ``r`` gives one of degree ``r - 1``; the recursion
  starts from degree ``order - 1``, which leaves the rates of the last order known at
  ``Da = 0``; ``x0`` is linear in ``Da``, exact), ``L0``, the resonant part and the
  division by ``omega_i^2 - (h . omega)^2`` are :class:`~kbm.algebra.coupled_jets.JetAlgebra`'s;
- ``F(x0 + Dx, v0 + Dv, theta)`` is its Taylor series in the ``2 N`` state variables
  (:class:`kbm.algebra.smooth.TaylorOf`), the partial derivatives taken symbolically and
  compiled (:class:`kbm.algebra.smooth.TaylorTable`); their jets in ``Da`` along
  ``x0_l = a_l cos psi_l``, ``v0_l = -omega_l a_l sin psi_l`` come from higher partial
  derivatives at ``a*``.

The derivatives in ``a`` are exact (no differences, no interpolation); the only truncation is
the grid in the angles, exact for a polynomial ``F`` once the grid holds its harmonics (the
result reports the largest coefficient on the grid's outer shell).  The recursion itself is
:func:`kbm.expansion.recursion.kbm_recursion`, every engine's, on this algebra.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
import sympy as sp

from ..algebra.lazy_series import Tail
from ..algebra.smooth import TaylorOf, TaylorTable
from ..errors import ModelError, OrderError, ParameterError, ResolutionError
from ..expansion.recursion import kbm_recursion
from ..algebra.coupled import coupled_rhs
from ..algebra.coupled_jets import JetAlgebra, JetSeries
from ..model.coupled import CoupledOscillators, positions, velocities
from ..expansion.resonance import SlowLattice, lattice_on_grid, slow_point

__all__ = ["JetExpansion", "jet_expansion", "MAX_ORDER_JETS"]

#: highest order of the numeric coupled recursion (the partial derivatives of F up to this
#: total order are compiled; the harmonics of u_n grow like the order)
MAX_ORDER_JETS = 6

#: the default bound on the outer Fourier coefficients of the u_n, relative to the largest
DEFAULT_TAIL = 1e-10

#: the largest adaptive grid: points per angle, and in all
MAX_NODES_JETS = 256
MAX_GRID_JETS = 2**18


@lru_cache(maxsize=64)
def _lattice(D: int, resonances: tuple) -> SlowLattice:
    """The slow lattice of ``D`` angles and the declared resonances.  Pure-function memo: the
    key is an ``int`` and frozen resonances; the lattice's only state is its own memo of
    :meth:`~kbm.expansion.resonance.SlowLattice.coords`, a function of its generators."""
    return SlowLattice(D, resonances)


@lru_cache(maxsize=64)
def _slow_terms(gens: tuple, D: int, M: int):
    """The slow lattice's wavevectors on the grid: their indices and coordinates ``n``
    (``q . psi = n . gamma``).  Pure-function memo: integers in, read-only arrays out."""
    terms = lattice_on_grid(gens, D, M)
    index = tuple(np.array([int(q[k]) % M for q, _ in terms]) for k in range(D))
    coords = np.array([c for _, c in terms], dtype=float).reshape(len(terms), -1)
    for arr in (*index, coords):
        arr.flags.writeable = False
    return index, coords


class JetBuilder:
    """Makes ``F(x0 + Dx, v0 + Dv, theta)`` as a :class:`~kbm.algebra.smooth.TaylorOf`
    over the ``2 N`` leaves (the ``builder`` of :func:`kbm.algebra.coupled.coupled_rhs`)."""

    def __init__(self, alg: JetAlgebra, leaves: dict):
        self.alg = alg
        self.names, self.values = alg.parameters
        n = alg.dof
        self.vars = (*positions(n), *velocities(n))
        self.leaves = [leaves[v] for v in self.vars]
        self.x0 = [alg.point[l] * alg.cos[l] for l in range(n)]
        self.v0 = [-alg.w[l] * alg.point[l] * alg.sin[l] for l in range(n)]
        # d x0_l / d a_l and d v0_l / d a_l on the grid
        self.dx = list(alg.cos[:n])
        self.dv = [-alg.w[l] * alg.sin[l] for l in range(n)]
        self.theta = alg.angles[-1] if alg.forced else np.zeros(alg.shape)

    def build(self, expr: sp.Expr):
        zero = self.alg.zero
        table = _table(expr, self.vars, (sp.Symbol("theta"), *self.names))
        deltas = [Tail(zero, leaf) for leaf in self.leaves]
        return TaylorOf(zero, self._sampler(table), *deltas)

    def _sampler(self, table: TaylorTable):
        alg = self.alg
        n = alg.dof
        args = (*self.x0, *self.v0, self.theta, *self.values)

        def evaluate(beta):
            if table.expr(*beta) == 0:
                return None
            with np.errstate(all="ignore"):
                vals = np.broadcast_to(np.asarray(table.function(*beta)(*args), dtype=float),
                                       alg.shape)
            if not np.all(np.isfinite(vals)):
                raise ParameterError(
                    f"F = {table.F} or its derivative of order {list(beta)} is not finite "
                    f"on the orbit of the amplitudes {list(alg.point)}: the numeric "
                    "backend needs F smooth and finite there")
            return vals

        def sample(*beta):
            """The jet of ``F_beta(x0(a), v0(a), theta)`` in ``Da`` to degree
            ``top - |beta|``: ``F_beta`` first enters ``R_n`` at ``n = |beta| + 1``, which
            is known to degree ``top - |beta|``."""
            deg = max(alg.top - sum(beta), 0)
            out = np.zeros((len(alg.index),) + alg.shape)
            any_ = False
            for alpha in alg.index:
                if sum(alpha) > deg:
                    break
                # split alpha_l between the x_l and the v_l derivative
                for split in itertools.product(*[range(a + 1) for a in alpha]):
                    delta_x = split
                    delta_v = tuple(a - s for a, s in zip(alpha, split))
                    full = tuple(b + d for b, d in zip(beta, (*delta_x, *delta_v)))
                    vals = evaluate(full)
                    if vals is None:
                        continue
                    w = np.ones(alg.shape)
                    for l in range(n):
                        if delta_x[l]:
                            w = w * self.dx[l] ** delta_x[l] / math.factorial(delta_x[l])
                        if delta_v[l]:
                            w = w * self.dv[l] ** delta_v[l] / math.factorial(delta_v[l])
                    out[alg.pos[alpha]] += vals * w
                    any_ = True
            return alg.jet(out, deg) if any_ else alg.zero()

        return sample


@lru_cache(maxsize=64)
def _table(expr: sp.Expr, variables: tuple, extra: tuple) -> TaylorTable:
    """The partial derivatives of one ``F``, with the parameters as arguments.  Pure-function
    memo: the key is an expression and tuples of symbols; the table's only state is its own
    memo of derivatives, each a function of the key and its multi-index alone (taken from the
    same neighbour whatever the order of the requests)."""
    return TaylorTable(expr, extra=extra, variables=variables)


@dataclass(frozen=True)
class JetExpansion:
    """The rates of every order at one point of the amplitudes.

    ``A[i][n - 1]`` and ``B[i][n - 1]`` are ``A_{i,n}``, ``B_{i,n}`` at the amplitudes
    :attr:`amplitudes` and the slow phases :attr:`gammas` (multiply by ``mu**n``); ``tail`` the
    largest Fourier coefficient of the rates' grid functions on the grid's outer shell,
    relative to the largest (a measure of the angle grid's truncation).
    """

    amplitudes: tuple[float, ...]
    gammas: tuple[float, ...]
    order: int
    A: tuple[tuple[float, ...], ...]
    B: tuple[tuple[float, ...], ...]
    tail: float
    nodes: int
    dA: tuple | None = None
    dB: tuple | None = None


def _slow_value(alg: JetAlgebra, f: np.ndarray, gens, gammas) -> tuple[float, np.ndarray]:
    """The slow grid function ``f`` (a function of the combinations ``gamma_r = g_r . psi``
    only) at the given ``gammas`` by its Fourier series on the slow lattice, and its
    derivatives in the ``gammas``."""
    spec = np.fft.fftn(f) / f.size
    if not gens:
        return float(spec[(0,) * alg.n].real), np.zeros(0)
    index, coords = _slow_terms(tuple(gens), alg.n, alg.M)
    terms = spec[index] * np.exp(1j * (coords @ np.asarray(gammas, dtype=float)))
    return float(terms.sum().real), (1j * coords * terms[:, None]).sum(axis=0).real


def jet_expansion(model: CoupledOscillators, values: Mapping[str, float], order: int,
                  amplitudes: Sequence[float], gammas: Sequence[float] = (), *,
                  nodes: int = 32, tolerance: float | None = None,
                  gradient: bool = False, tol: float = DEFAULT_TAIL,
                  adapt: bool = True) -> JetExpansion:
    """``A_{i,n}``, ``B_{i,n}`` for ``n = 1..order`` at one point, for any smooth ``F``.

    Parameters
    ----------
    model
        The coupled model, its internal resonances declared (``model.with_internal``).
    values
        A float for every parameter ``F`` holds, and for the declared detunings.
    order
        ``1..MAX_ORDER_JETS``.
    amplitudes, gammas
        The point: ``N`` positive amplitudes and one slow phase per declared resonance.
    nodes
        Grid points per angle to start with (even, at least 8).
    tol, adapt
        With ``adapt``, the grid is doubled while the outer coefficients of the ``u_n``
        (:attr:`JetExpansion.tail`) exceed ``tol`` times the largest, up to
        :data:`MAX_NODES_JETS` points per angle and :data:`MAX_GRID_JETS` in all.
    gradient
        Also the derivatives of every rate in the amplitudes and the slow phases
        (:attr:`JetExpansion.dA`, ``dB``): the jets are taken one degree further.

    Raises
    ------
    kbm.errors.OrderError
        For an order out of range.
    kbm.expansion.resonance.UndeclaredResonanceError
        For a resonance present in ``F`` that was not declared.
    kbm.errors.ModelError
        For a forcing frequency ``nu`` written in ``F`` (it puts ``mu`` into ``F``).
    kbm.errors.ResolutionError
        If the largest grid leaves outer coefficients above ``tol`` (the numbers are in the
        message).
    """
    from ..expansion.coupled import TOLERANCE

    if not isinstance(order, int) or isinstance(order, bool) or \
            not 1 <= order <= MAX_ORDER_JETS:
        raise OrderError(f"the order of the numeric coupled averaging must be an integer "
                         f"from 1 to {MAX_ORDER_JETS}, got {order!r}")
    model, F, parameters, sigma, a, g, lattice = _point(model, values, order, amplitudes,
                                                        gammas)
    D = lattice.dof  # the fast angles, theta included
    check_nodes(nodes)
    M = nodes
    while True:
        alg = JetAlgebra(model, lattice, a, M, order - (0 if gradient else 1), sigma,
                         TOLERANCE if tolerance is None else tolerance, parameters)
        ex = _on_grid(alg, F, order, gradient, lattice, a, g)
        if not adapt or ex.tail <= tol:
            return ex
        if 2 * M > MAX_NODES_JETS or (2 * M) ** D > MAX_GRID_JETS:
            raise ResolutionError(
                f"the outer Fourier coefficients of the u_n are {ex.tail:.1e} of the largest "
                f"on {M}^{D} grid points, above the tolerance {tol:.0e}, and the next grid "
                f"would pass the limit of {MAX_NODES_JETS} points per angle and "
                f"{MAX_GRID_JETS} in all: F has too many harmonics at these amplitudes "
                f"{[float(v) for v in a]}; take smaller amplitudes or a larger tol")
        M *= 2


def _point(model: CoupledOscillators, values: Mapping[str, float], order: int,
           amplitudes: Sequence[float], gammas: Sequence[float]):
    """The model with exact frequencies, its right-hand sides (:func:`_right_hand_sides`),
    the point ``(a, gamma)`` checked and the slow lattice."""
    fixed = model.with_frequencies(values)  # the sliders' Omega: exact frequencies
    if fixed is not model:
        values = {k: v for k, v in values.items() if k in fixed.parameters}
        model = fixed
    F, parameters, sigma = _right_hand_sides(model, values, order)
    a, g = slow_point(model.dof, len(model.internal), amplitudes, gammas)
    lattice = _lattice(model.dof + (1 if model.forced else 0), model.internal)
    return model, F, parameters, sigma, a, g, lattice


def _on_grid(alg: JetAlgebra, F, order: int, gradient: bool, lattice: SlowLattice,
             a: np.ndarray, g: np.ndarray, last_u: bool = True) -> JetExpansion:
    """The expansion on one grid (see :func:`jet_expansion`; ``last_u=False`` leaves out
    the last ``u_n``, and the tail with it, when only the rates are asked for)."""
    n = alg.dof
    A, B, U = kbm_recursion(alg, coupled_rhs(alg, F, JetBuilder), order, last_u=last_u)
    gens = lattice.generators
    unit = [alg.pos.get(tuple(1 if k == l else 0 for k in range(n))) for l in range(n)]

    def at_point(f: JetSeries):
        """The value and, with ``gradient``, the derivatives in ``(a, gamma)``."""
        v, dg = _slow_value(alg, f.value(), gens, g)
        if not gradient:
            return v, None
        da = [0.0 if f.values is None else _slow_value(alg, f.values[k], gens, g)[0]
              for k in unit]
        return v, tuple(float(x) for x in (*da, *dg))

    outA, outB, dA, dB = [], [], [], []
    for i in range(n):
        ra = [at_point(A[i][m]) for m in range(order)]
        rb = [at_point(B[i][m]) for m in range(order)]
        outA.append(tuple(v for v, _ in ra))
        outB.append(tuple(v for v, _ in rb))
        dA.append(tuple(d for _, d in ra))
        dB.append(tuple(d for _, d in rb))
    # the angle grid's truncation: the outer shell of every u_n (the harmonics of F along
    # the orbit, and their products), relative to the largest coefficient
    tail = 0.0
    for i in range(n):
        for u in U[i]:
            if u.values is not None:
                spec = np.abs(np.fft.fftn(u.values[0]))
                big = float(np.max(spec))
                if big > 0:
                    tail = max(tail, float(np.max(spec[alg.shell])) / big)
    return JetExpansion(tuple(float(v) for v in a), tuple(float(v) for v in g), order,
                        tuple(outA), tuple(outB), tail, int(alg.M),
                        tuple(dA) if gradient else None, tuple(dB) if gradient else None)


def check_nodes(nodes) -> None:
    """Refuse a number of grid points per angle that is not an even integer ``>= 8``."""
    if not isinstance(nodes, int) or isinstance(nodes, bool) or nodes < 8 or nodes % 2:
        raise ParameterError(f"nodes must be an even integer >= 8, got {nodes!r}")


def check_weak(model: CoupledOscillators) -> None:
    """Refuse a hard forcing ``K cos(theta)`` (the numeric backend takes ``mu F(theta)``)."""
    if model.hards:
        raise ModelError(f"{model.name!r} has a hard forcing K cos(theta): the numeric "
                         "averaging takes weak forcing mu F(theta) (the exact engine takes "
                         "hard forcing: kbm.expansion.coupled.derive_coupled)")


def _right_hand_sides(model: CoupledOscillators, values: Mapping[str, float], order: int):
    """``F[i][k]``, the coefficient of ``mu**k`` of mode ``i`` (:func:`symbolic_rhs`), the
    parameters ``(symbols, values)`` and the forcing detuning's value."""
    F, names = symbolic_rhs(model, order > 1)
    free = [k for k in names if k not in values]
    if free:
        raise ParameterError(f"give values for {', '.join(free)} (-p NAME=VALUE)")
    sigma = None
    if model.forced and model.nu_detuning:
        sigma = float(values.get(model.nu_detuning, 0.0))
    parameters = (tuple(sp.Symbol(k) for k in names), tuple(float(values[k]) for k in names))
    return [list(row) for row in F], parameters, sigma


@lru_cache(maxsize=64)
def symbolic_rhs(model: CoupledOscillators, higher: bool):
    """``F[i][k]`` and the names of the parameters in them: a declared detuning
    ``omega_j -> omega_j + mu sigma`` enters as in the exact engine; at the first order
    (``higher`` false) a forcing frequency ``nu`` in ``F`` is ``nu0 + mu sigma``, ``mu`` a
    parameter.

    Pure-function memo: the key is a frozen :class:`~kbm.model.coupled.CoupledOscillators`
    and a ``bool``, the value tuples of sympy expressions and names computed from them
    alone."""
    check_weak(model)
    n = model.dof
    nu = sp.Symbol("nu")
    if any(f.has(nu) for f in model.rhs) and higher:
        raise ModelError(f"{model.name!r} holds the forcing frequency nu in F (nu = nu0 + mu "
                         "sigma puts mu into F): beyond the first order the numeric coupled "
                         "averaging takes F free of nu")
    F = [[sp.expand(f)] for f in model.rhs]
    if model.forced and any(f.has(nu) for f in model.rhs):
        shift = sp.nsimplify(model.nu0) + sp.Symbol("mu") * sp.Symbol(model.nu_detuning
                                                                      or "sigma")
        F = [[sp.expand(f.subs(nu, shift))] for f in model.rhs]
    for r in model.internal:
        if r.detuning and not r.forcing:  # omega_j -> omega_j + mu sigma, as the exact engine
            sig = sp.Symbol(r.detuning)
            xj = positions(n)[r.j - 1]
            wj = model.omegas[r.j - 1]
            F[r.j - 1][0] = F[r.j - 1][0] - 2 * wj * sig * xj
            F[r.j - 1].append(-sig**2 * xj)
    # the parameters stay symbols, their values arguments of the compiled derivatives
    names = sorted({s.name for row in F for f in row for s in f.free_symbols}
                   - {s.name for s in model.state} - {"theta"})
    return tuple(tuple(row) for row in F), tuple(names)


def first_order(model: CoupledOscillators, values: Mapping[str, float],
                amplitudes: Sequence[float], gammas: Sequence[float], nodes: int
                ) -> tuple[np.ndarray, np.ndarray, float]:
    """``(A_1, B_1, outer)`` at one point on the ``nodes^D`` grid: the first order of the
    same recursion on jets of degree 0 (no amplitude derivatives are needed), and the
    largest Fourier coefficient of the ``F_i`` on the grid's outer shell (no refinement)."""
    from ..expansion.coupled import TOLERANCE

    model, F, parameters, sigma, a, g, lattice = _point(model, values, 1, amplitudes, gammas)
    alg = JetAlgebra(model, lattice, a, nodes, 0, sigma, TOLERANCE, parameters)
    ex = _on_grid(alg, F, 1, False, lattice, a, g, last_u=False)
    return np.array([r[0] for r in ex.A]), np.array([r[0] for r in ex.B]), alg.outer
