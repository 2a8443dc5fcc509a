"""The stationary Kramers solve on spectral elements (numerics/fokker_planck/_elements.py,
_elements_lu.py, _elements_solve.py) against references it does not produce: the
Gauss-Lobatto-Legendre rule's closed forms, a dense solve of the same matrix, the
Boltzmann density of a linear damping (quadrature) and, for the SEDF at rest, the
Hermite x Chebyshev solver of ._stationary_orthonormal."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.special import erf

from kbm.model.conservative import split_conservative
from kbm.errors import ParameterError
from numerics.fokker_planck import stationary_kramers
from numerics.fokker_planck._elements import (ElementOperator, element_edges, element_nodes,
                                              gll)
from numerics.fokker_planck._elements_solve import ElementKramersSolution, element_kramers
from numerics.fokker_planck._orthonormal import orthonormal_terms

CDC = {"mu": 0.15, "Delta": 2, "lam": 1.3, "Omega": 1}
SEDF = {"Delta": 3, "beta": 1, "lam": 1, "Omega": 1}


def _boltzmann(params: dict, kT: float):
    """``(G, Z, <x^2>)`` of ``exp(-G/kT)`` by adaptive quadrature (scipy.integrate.quad)."""
    G = split_conservative("cdc", params).numpy_functions()[2]

    def f(x, k):
        return x**k * math.exp(-float(G(x)) / kT)

    opts = dict(limit=500, epsabs=0.0, epsrel=1e-13, points=[0.0])
    Z = quad(f, -30, 30, args=(0,), **opts)[0]
    return G, Z, quad(f, -30, 30, args=(2,), **opts)[0] / Z


@pytest.mark.parametrize("p", [3, 7, 11, 15])
def test_gll_rule_closed_forms(p):
    """The Gauss-Lobatto-Legendre rule of degree ``p`` integrates ``r^k`` exactly for
    ``k <= 2p - 1`` (``2/(k + 1)`` for even ``k``, 0 for odd), its differentiation matrix
    is exact on ``r^p`` (``p r^(p-1)``), and ``Q = W D`` sums by parts,
    ``Q + Q^T = diag(-1, 0, .., 0, 1)`` (Karniadakis and Sherwin, *Spectral/hp Element
    Methods*, sec. 2.3 and 4.1)."""
    r, w, D = gll(p)
    for k in range(2 * p):
        assert float(w @ r**k) == pytest.approx(2.0 / (k + 1) if k % 2 == 0 else 0.0,
                                                abs=1e-14)
    assert np.max(np.abs(D @ r**p - p * r ** (p - 1))) <= 1e-12 * p * p
    B = np.zeros((p + 1, p + 1))
    B[0, 0], B[p, p] = -1.0, 1.0
    assert np.max(np.abs(w[:, None] * D + (w[:, None] * D).T - B)) <= 1e-13


def _condensed_and_dense(N: int, E: int, p: int, seed: int, first_pins=None):
    """The static condensation's solution and numpy's dense ``solve`` of the element
    matrix of the SEDF at rest (mu = 0.1, D = 0.05, on ``[-6, 6]``), assembled column by
    column from the operator's product, with the rows of the last node and of the first
    node's pinned orders (all unless ``first_pins``) replaced by the identity's, for a
    random right-hand side 0 there."""
    split = split_conservative("sedf", dict(SEDF, mu=0.1))
    edges = element_edges(E, 6.0)
    x, _ = element_nodes(edges, p)
    op = ElementOperator(orthonormal_terms(split, 0.05, 0.5, x, None, N), edges, p, x)
    M = x.size
    A = np.column_stack([op.matvec(e.reshape(N, M)).ravel() for e in np.eye(N * M)])
    first = np.arange(N) if first_pins is None else np.asarray(first_pins)
    b = np.random.default_rng(seed).standard_normal((N, M))
    b[:, -1] = 0.0
    b[first, 0] = 0.0
    for i in [n * M for n in first] + [n * M + M - 1 for n in range(N)]:
        A[i] = 0.0
        A[i, i] = 1.0
    dense = np.linalg.solve(A, b.ravel()).reshape(N, M)
    return op.join(*op.factor(first_pins=first_pins).solve(*op.split(b))), dense


def test_condensed_lu_is_the_dense_solve():
    """The static condensation (element interiors by order groups, the interfaces by the
    block LU with partial pivoting) solves the element matrix of the SEDF at rest as
    numpy's dense ``solve`` of the same matrix, assembled column by column from the
    operator's product (mu = 0.1, D = 0.05, 8 functions, 6 elements of degree 5: 1e-10
    of the solution)."""
    got, dense = _condensed_and_dense(8, 6, 5, 3)
    assert np.max(np.abs(got - dense)) <= 1e-10 * np.max(np.abs(dense))


def test_condensed_lu_with_pinned_orders_at_the_first_node_is_the_dense_solve():
    """As :func:`test_condensed_lu_is_the_dense_solve` with the first node solved for but
    for its odd orders, pinned to 0 (the fold of ._parity at ``x = 0``, ``first_pins``):
    9 functions, 6 elements of degree 7, 1e-10 of the solution."""
    got, dense = _condensed_and_dense(9, 6, 7, 5, first_pins=np.arange(1, 9, 2))
    assert np.max(np.abs(got - dense)) <= 1e-10 * np.max(np.abs(dense))


@pytest.mark.parametrize("mu, D, elements", [(0.15, 0.09, 32), (0.01, 0.006, 40)])
def test_linear_damping_is_boltzmann(mu, D, elements):
    """CDC at rest (paper eq. 12), kT = D/mu = 0.6: the stationary density of a linear
    damping is exactly ``exp(-H/kT)`` (Kramers 1940; Risken, *The Fokker-Planck
    Equation*, sec. 10.1), so ``<x^2>`` is the quadrature of ``x^2 exp(-G/kT)`` to 1e-9,
    ``<v^2> = kT`` and the mass below an energy is the quadrature of
    ``exp(-G/kT) erf(((E - G)/kT)^(1/2))`` over ``G < E``; at mu = 0.15 and at the low
    friction mu = 0.01 (elements of degree 13 by ``stationary_kramers(elements=...)``,
    whose velocity scale for a linear damping is ``kT^(1/2)``)."""
    params = dict(CDC, mu=mu)
    kT = D / mu
    G, Z, x2 = _boltzmann(params, kT)
    sol = stationary_kramers("cdc", params, D, n_hermite=4, elements=(elements, 13))
    assert isinstance(sol, ElementKramersSolution) and math.isnan(sol.hermite_change)
    assert sol.x2 == pytest.approx(x2, rel=1e-9)
    assert sol.v2 == pytest.approx(kT, rel=1e-9)
    for E in (0.5, 2.0):
        a, b = sol.stretches(E)[0]
        mass = quad(lambda x: math.exp(-float(G(x)) / kT)
                    * erf(math.sqrt(max(E - float(G(x)), 0.0) / kT)), a, b,
                    epsabs=0.0, epsrel=1e-12, limit=200)[0] / Z
        assert sol.mass_below(E) == pytest.approx(mass, abs=1e-8)


@pytest.mark.parametrize("elements, n_hermite, words", [
    ((41, 11), 64, "even number"), ((40, 12), 64, "odd degree"), ((40, 11), None, "n_hermite"),
    ("forty", 64, "(number of elements, degree)")])
def test_elements_bad_sizes_say_what_to_change(elements, n_hermite, words):
    """``stationary_kramers(elements=...)`` refuses sizes the element solve cannot use
    (an odd number of elements, an even degree, no Hermite functions given) with a
    ``ParameterError`` that names the fix."""
    with pytest.raises(ParameterError, match=re.escape(words)):
        stationary_kramers("sedf", dict(SEDF, mu=0.1), 0.05, n_hermite=n_hermite,
                           elements=elements)


def _element_pair(mu: float, coarse: tuple, fine: tuple):
    """Two element solves of the SEDF at rest, D = mu/2, and their change of ``<x^2>``
    and ``<v^2>`` (relative): the element solve's stated error."""
    runs = [element_kramers("sedf", dict(SEDF, mu=mu), mu / 2, n_hermite=n, elements=e,
                            degree=p) for n, e, p in (coarse, fine)]
    a, b = runs
    return b, max(abs(b.x2 - a.x2) / b.x2, abs(b.v2 - a.v2) / b.v2)


def _against_ladder(mu: float, coarse: tuple, fine: tuple, **ladder) -> None:
    """``<x^2>`` and ``<v^2>`` of the element solve against the Hermite x Chebyshev
    ladder of ``stationary_kramers`` (``basis="orthonormal"``: the SEDF's default is now
    the element ladder) within the sum of both stated errors."""
    ref = stationary_kramers("sedf", dict(SEDF, mu=mu), mu / 2, basis="orthonormal", **ladder)
    sol, change = _element_pair(mu, coarse, fine)
    bound = ref.hermite_change + change
    assert change <= 1e-6
    assert abs(sol.x2 - ref.x2) <= bound * ref.x2
    assert abs(sol.v2 - ref.v2) <= bound * ref.v2


@pytest.mark.slow  # the element ladder's default test compares the same case
def test_sedf_agrees_with_the_chebyshev_ladder():
    """SEDF at rest, Delta = 3, beta = 1, mu = 0.1, D = 0.05: ``<x^2>`` and ``<v^2>`` of
    the element solve against the Hermite x Chebyshev ladder of ``stationary_kramers``
    (the present route, ._stationary_orthonormal, at the budget 2e6: 90 x 499, stated
    1.1e-6) within the sum of both stated errors (the ladder's ``hermite_change``; the
    elements' change from 128 functions on 40 elements of degree 11 to 182 on 56)."""
    _against_ladder(0.1, (128, 40, 11), (182, 56, 11), max_cost=2e6)


@pytest.mark.slow
@pytest.mark.parametrize("mu, coarse, fine", [
    (0.05, (128, 40, 11), (182, 56, 11)),
    (0.02, (182, 56, 11), (258, 72, 11)),
])
def test_sedf_low_friction_agrees_with_the_chebyshev_ladder(mu, coarse, fine):
    """As :func:`test_sedf_agrees_with_the_chebyshev_ladder` at mu = 0.05 and 0.02
    (D = mu/2; the ladder at its default budget)."""
    _against_ladder(mu, coarse, fine)


@pytest.mark.slow
def test_sedf_low_friction_against_the_reference_solve():
    """SEDF at rest, mu = 0.01, D = 0.005: ``<x^2>`` against 2.1574351299, the Hermite x
    Chebyshev solve of 364 functions on 1300 intervals (the present route's ladder gives
    2.1574350902 and states 3.0e-7), within the element solve's own change (258 functions
    on 100 elements of degree 13 against 364 on 120) plus 1e-8."""
    sol, change = _element_pair(0.01, (258, 100, 13), (364, 120, 13))
    assert change <= 1e-6
    assert abs(sol.x2 - 2.1574351299) <= (change + 1e-8) * 2.1574351299


@pytest.mark.slow
def test_sedf_lowest_friction_against_the_present_route():
    """SEDF at rest, mu = 0.005, D = 0.0025: ``<x^2>`` and ``<v^2>`` against the present
    route's (``kbm noise sedf -p mu=0.005 -p Delta=3 -p beta=1 -p D=0.0025 --method
    fokker-planck --fp-budget 8.6e7``: 364 functions x 1627 points, <x^2> = 2.1430565722,
    <v^2> = 1.8635864626, stated 5.6e-7; 146 s CPU) within the sum of both stated
    errors (the elements': 364 functions on 120 elements of degree 13 against 440 on
    140)."""
    sol, change = _element_pair(0.005, (364, 120, 13), (440, 140, 13))
    bound = 5.6e-7 + change
    assert change <= 1e-6
    assert abs(sol.x2 - 2.1430565722) <= bound * 2.1430565722
    assert abs(sol.v2 - 1.8635864626) <= bound * 1.8635864626
