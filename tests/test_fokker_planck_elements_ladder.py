"""The element ladder of the stationary Kramers solve (numerics/fokker_planck/
_elements_ladder.py, the default route of a multi-well SEDF) and its ``P(E)``
(_energy_quadrature.py on elements) against a second discretisation it does not produce:
the Hermite x Chebyshev ladder of ._stationary_orthonormal (``basis="orthonormal"``), and
reference solves of that discretisation at low friction; and the advice of an element
solve beyond six digits (thermal/_kramers_outputs.py)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from kbm.errors import ModelError, ParameterError
from numerics.fokker_planck import stationary_kramers
from numerics.fokker_planck._elements_solve import ElementKramersSolution
from numerics.fokker_planck._energy_density import (energy_density, energy_density_change,
                                                    energy_density_report)
from numerics.fokker_planck._stationary_solve import OrthonormalKramersSolution

SEDF = {"Delta": 3, "beta": 1, "lam": 1, "Omega": 1}


def _moments_agree(sol, ref) -> None:
    """``<x^2>``, ``<v^2>``, ``<a^2>`` of two solutions within the sum of their stated
    errors (``hermite_change``, relative)."""
    bound = sol.hermite_change + ref.hermite_change
    for k in ("x2", "v2", "a2"):
        assert abs(getattr(sol, k) - getattr(ref, k)) <= bound * abs(getattr(ref, k)), k


@pytest.fixture(scope="module")
def sedf_pair():
    """SEDF at rest, mu = 0.1, D = 0.05: the default route's solution and the Chebyshev
    ladder's (``basis="orthonormal"`` at the budget 2e6), solved once for this module."""
    params = dict(SEDF, mu=0.1)
    return (stationary_kramers("sedf", params, 0.05),
            stationary_kramers("sedf", params, 0.05, basis="orthonormal", max_cost=2e6))


def test_sedf_routes_to_the_element_ladder_and_agrees_with_chebyshev(sedf_pair):
    """SEDF at rest, Delta = 3, mu = 0.1, D = 0.05 (Risken ch. 10's Kramers equation, the
    multi-well potential): the default route is the element ladder, which states six digits
    (128 functions on 58 elements, 5.7e-8), and its moments agree with the Chebyshev
    ladder's (``basis="orthonormal"`` at the budget 2e6, 90 x 499, stated 1.1e-6) within
    the sum of the stated errors; the ``refinements`` are a Hermite and an element step."""
    sol, ref = sedf_pair
    assert isinstance(sol, ElementKramersSolution)
    assert not isinstance(ref, ElementKramersSolution)
    assert sol.hermite_change <= 1e-6
    assert sol.hermite_change >= sol.chebyshev_change
    (hc, hf), (ec, ef) = sol.refinements
    assert hc.coef.shape[0] < hf.coef.shape[0] and len(hc.edges) == len(hf.edges)
    assert ec.coef.shape[0] == ef.coef.shape[0] and len(ec.edges) < len(ef.edges)
    _moments_agree(sol, ref)


def test_sedf_energy_density_on_elements_agrees_with_chebyshev(sedf_pair):
    """``P(E)`` of the element ladder's solution (SEDF mu = 0.1, D = 0.05; the
    report takes it from one element step more when its change exceeds six digits, as
    for the Chebyshev grid) against ``P(E)`` of the Chebyshev ladder at the same energies,
    within the element report's stated change plus the Chebyshev solution's change under
    its own refinements (and its quadrature's), relative to the peak."""
    sol, ref = sedf_pair
    rep = energy_density_report(sol)
    E, P = np.array(rep["E"]), np.array(rep["P"])
    peak = float(np.max(np.abs(P)))
    Pr, quad = energy_density(ref, E, quadrature=True)
    ref_change = energy_density_change(ref, E, Pr) * np.abs(Pr) + quad
    assert rep["change_peak"] <= 1e-5
    assert np.all(np.abs(P - Pr) <= rep["change_peak"] * peak + np.max(ref_change))


def test_element_ladder_same_bits_with_one_and_two_processes(monkeypatch):
    """The element ladder's solution is the same bits whether its solve runs beside the
    element pair in a second process or here (KBM_FP_WORKERS = 2, 1; SEDF mu = 0.05,
    D = 0.025, where it is started ahead)."""
    from numerics.fokker_planck import _ahead

    params = dict(SEDF, mu=0.05)
    runs = []
    for workers in ("2", "1"):
        monkeypatch.setenv(_ahead.ENV, workers)
        runs.append(stationary_kramers("sedf", params, 0.025))
    a, b = runs
    assert a.coef.tobytes() == b.coef.tobytes()
    assert (a.x2, a.v2, a.hermite_change, a.chebyshev_change) == \
        (b.x2, b.v2, b.hermite_change, b.chebyshev_change)


def test_other_models_keep_their_routes_and_bad_sizes_say_what_to_change():
    """vdp (no saddle) keeps the Chebyshev ladder, an explicit ``basis="elements"`` runs
    the element ladder on it (its moments within the sum of both stated errors of the
    Chebyshev ladder's), ``basis="elements"`` with sizes is refused naming the fix, and a
    budget below the first rung (0.6 ``N^2 E/2`` folded) is refused with that cost."""
    vdp = stationary_kramers("vdp", {"mu": 0.3}, 0.15, max_cost=2e6)
    assert isinstance(vdp, OrthonormalKramersSolution)
    assert not isinstance(vdp, ElementKramersSolution)
    el = stationary_kramers("vdp", {"mu": 0.3}, 0.15, basis="elements", max_cost=2e6)
    assert isinstance(el, ElementKramersSolution)
    _moments_agree(el, vdp)
    with pytest.raises(ParameterError, match="leave out n_hermite"):
        stationary_kramers("sedf", dict(SEDF, mu=0.1), 0.05, basis="elements", n_cheb=200)
    with pytest.raises(ParameterError, match="'elements'"):
        stationary_kramers("sedf", dict(SEDF, mu=0.1), 0.05, basis="cells")
    # the first rung's cost, 0.6 x 64^2 x 48/2 = 5.9e4 (folded; COST_SHARE), is refused at a
    # budget below it
    with pytest.raises(ModelError, match=r"64 Hermite functions x 48 elements \(cost 5.9e\+04"):
        stationary_kramers("sedf", dict(SEDF, mu=0.1), 0.05, max_cost=5e4)


@pytest.mark.slow
@pytest.mark.parametrize("mu", [0.02, 0.01])
def test_sedf_low_friction_element_ladder_against_the_chebyshev_ladder(mu):
    """SEDF at rest, D = mu/2: the element ladder's moments and ``P(E)`` against the
    Chebyshev ladder's (its default budget) within the sum of the stated errors (``P``
    at the element report's energies, from the Chebyshev solve one grid step finer when
    its report takes it, with that step's change)."""
    params = dict(SEDF, mu=mu)
    sol = stationary_kramers("sedf", params, mu / 2, max_cost=2.5e7)
    ref = stationary_kramers("sedf", params, mu / 2, basis="orthonormal", max_cost=2.5e7)
    assert sol.hermite_change <= 1e-6
    _moments_agree(sol, ref)
    rep = energy_density_report(sol)
    ref_rep = energy_density_report(ref)
    E, P = np.array(rep["E"]), np.array(rep["P"])
    fine = ref.refine() if ref.refine is not None else ref
    Pr = energy_density(fine, E)
    bound = (rep["change_peak"] + ref_rep["change_peak"]) * float(np.max(np.abs(P)))
    assert np.all(np.abs(P - Pr) <= bound)


@pytest.mark.slow
def test_sedf_lowest_friction_element_ladder_against_the_reference_solves():
    """SEDF at rest, mu = 0.005, D = 0.0025: the element ladder (kbm noise's budget 2.5e7)
    states six digits and its ``<x^2>``, ``<v^2>`` agree with the Chebyshev route's
    (``--fp-budget 8.6e7``: 364 functions x 1627 points, <x^2> = 2.1430565722,
    <v^2> = 1.8635864626, stated 5.6e-7) within the sum of the stated errors."""
    sol = stationary_kramers("sedf", dict(SEDF, mu=0.005), 0.0025, max_cost=2.5e7)
    assert sol.hermite_change <= 1e-6
    bound = 5.6e-7 + sol.hermite_change
    assert abs(sol.x2 - 2.1430565722) <= bound * 2.1430565722
    assert abs(sol.v2 - 1.8635864626) <= bound * 1.8635864626
    assert dataclasses.is_dataclass(sol) and len(sol.refinements) == 2


def test_element_advice_names_the_sizes_and_budget_six_digits_need():
    """Beyond six digits the advice of an element solve (``fp_advice``) counts the steps of
    each ladder as digits of its part of the stated error above 5e-7 (SEDF mu = 0.002:
    2.0e-4 stated, 9.5e-7 the elements': 3 steps of the functions, 1 of the elements),
    362 * 2^(3/2) = 1024 functions x 332 * 1.2 = 400 elements, and the budget in ``N^2 E``:
    (1024/362)^2 * 400/332 = 9.64 times 2.5e7; within six digits it says nothing."""
    from numerics.thermal._kramers_outputs import fp_advice

    rec = {"hermite_change": 2.0e-4, "chebyshev_change": 9.5e-7, "hermite": 362,
           "chebyshev": 4317, "elements": 332}
    text = fp_advice(rec, 2.5e7)
    assert "1024 x 400 spectral" not in text and "at least 1024 x 400" in text
    assert "3 steps of the functions and 1 of the elements" in text
    assert f"--fp-budget {2.5e7 * (1024 / 362) ** 2 * 400 / 332:.2g}" in text
    assert fp_advice(dict(rec, hermite_change=5e-7), 2.5e7) == ""


@pytest.mark.slow
@pytest.mark.parametrize("mu, reference", [(0.01, (362, 230)), (0.005, (512, 300))])
def test_sedf_low_friction_energy_density_within_its_measured_change_of_a_fine_solve(mu,
                                                                                   reference):
    """SEDF at rest, Delta = 3, mu = 0.01, D = 0.005 (Risken ch. 10's Kramers equation),
    kbm noise's budget with ``P(E)`` wanted: the element ladder's ``<x^2>``, ``<v^2>`` and
    ``P(E)`` against a much finer solve it does not make (362 functions on 230 elements,
    whose ``P`` is 5e-9 of its peak from 512 x 220's), each within its stated error, both
    stated within six digits; and ``P``'s stated error is no smaller than the change of
    ``P`` under either refinement that states the moments' error (a stated error below a
    measured change is an extrapolation: the report took ``P`` from one element step more
    and stated that step's change times ``r/(1 - r)``, 5.4e-7 of the peak, where the last
    element step of the ladder had moved ``P`` by 3.6e-6).  mu = 0.005, D = 0.0025 against
    512 functions on 300 elements: with the element cost counted as the band LU's memory
    the budget stopped ``P``'s elements at 190, stated 3.7e-6; counted as the one-node LU's
    (``COST_SHARE``, the same 2.5 GB) they reach 240."""
    from numerics.fokker_planck._elements_solve import element_kramers
    from numerics.noise.budget import FP_BUDGET

    params = dict(SEDF, mu=mu)
    sol = stationary_kramers("sedf", params, mu / 2, max_cost=FP_BUDGET, refine_ahead=True)
    rep = energy_density_report(sol)
    assert sol.hermite_change <= 1e-6 and rep["change_peak"] <= 1e-6
    E, P = np.array(rep["E"]), np.array(rep["P"])
    peak = float(np.max(np.abs(P)))
    stated = rep["change_peak"] * peak
    for coarse, fine in sol.refinements:
        assert np.max(np.abs(energy_density(fine, E) - energy_density(coarse, E))) <= stated
    ref = element_kramers("sedf", params, mu / 2, n_hermite=reference[0],
                          elements=reference[1], degree=13)
    for k in ("x2", "v2"):
        assert abs(getattr(sol, k) - getattr(ref, k)) <= sol.hermite_change * getattr(ref, k)
    assert np.max(np.abs(P - energy_density(ref, E))) <= stated
