"""What ``kbm noise --json`` reports of the stationary Kramers solution: its moments
within a cost budget (:func:`fokker_planck_moments`, for :mod:`.stationary`), the density
of the energy ``P(E)`` with its stated error (:func:`energy_density_output`) and what to
do when the moments' stated error exceeds six digits (:func:`fp_advice`)."""

from __future__ import annotations

import math

from kbm.errors import ParameterError
from kbm.model.builtins import SLIDERS

from ..noise.budget import FP_BUDGET, FP_DEFAULT_BUDGET

__all__ = ["energy_density_output", "fokker_planck_moments", "fp_advice"]


def fokker_planck_moments(model, params: dict, D: float, omega0: float,
                          required: bool = False, budget: float | None = None,
                          energy_density: bool = True,
                          workers: int | None = None) -> tuple[dict | None, str]:
    """``<x^2>``, ``<a^2>`` of the stationary Kramers equation, or ``None`` and why.

    Applies to the one-degree-of-freedom models at rest (a slider at ``v = 0``) whose damping
    is polynomial in ``x'`` (:mod:`numerics.fokker_planck`).  With ``required`` the reason
    is raised instead (``--method fokker-planck``).  ``budget`` is the solve's ``max_cost``
    (``kbm noise --fp-budget``; default :data:`FP_BUDGET` with ``required``, else
    :data:`FP_DEFAULT_BUDGET`); the record keeps it as ``budget``.  ``P(E)``
    (:func:`energy_density_output`) with ``required`` and ``energy_density`` only.
    ``workers`` bounds the solve's processes (``kbm noise --workers``; the same bits).
    """
    from kbm.errors import KBMError

    from ..fokker_planck import stationary_kramers

    if budget is None:
        budget = FP_BUDGET if required else FP_DEFAULT_BUDGET
    why = ""
    if driven(model, params):
        why = DRIVEN
    else:
        try:
            sol = stationary_kramers(model, {k: v for k, v in params.items() if k != "v"}, D,
                                     omega0=omega0, max_cost=budget, workers=workers,
                                     refine_ahead=required and energy_density)
            change = sol.hermite_change  # inf: a second truncation passed the budget
            return {"energy_density": (energy_density_output(sol, model, params, D, omega0,
                                                              workers)
                                       if required and energy_density else None),
                    "x2": sol.x2, "a2": sol.a2, "v2": sol.v2, "hermite": sol.coef.shape[0],
                    "chebyshev": sol.x.size, "half_width": float(sol.x[0]),
                    "elements": len(sol.edges) - 1 if hasattr(sol, "edges") else None,
                    "sigma": sol.sigma, "solution": sol, "basis": sol.basis, "budget": budget,
                    "hermite_change": change if math.isfinite(change) else None,
                    "chebyshev_change": (sol.chebyshev_change
                                         if math.isfinite(sol.chebyshev_change) else None)}, ""
        except KBMError as exc:
            why = f"no Fokker-Planck solution: {exc}" + (
                " (raise --fp-budget above that cost)" if "not affordable" in str(exc) else "")
    if required:
        if why == DRIVEN:  # named as the escape names it
            why += DRIVEN_REQUIRED
        raise ParameterError(f"--method fokker-planck: {why}")
    return None, why


#: why a pulled slider has no stationary Kramers solution
DRIVEN = "the driven slider (v != 0) is not at rest: no stationary Kramers equation"
#: and what to do when ``--method fokker-planck`` asks for one
DRIVEN_REQUIRED = ("; the stationary state is computed at rest, v = 0, and -p v is not taken "
                   "by --method fokker-planck: leave out -p v, or leave out --method "
                   "fokker-planck to simulate the pulled slider")


def driven(model, params: dict) -> bool:
    """Whether ``model`` is a slider pulled at ``v != 0`` (no stationary Kramers equation:
    :func:`fokker_planck_moments` gives its reason, :func:`.stationary.noise_report`
    refuses ``--method fokker-planck`` for it before any averaging or simulation)."""
    name = model if isinstance(model, str) else model.name
    return name in SLIDERS and float(params.get("v", 0)) != 0


def fp_advice(fp: dict, budget: float) -> str:
    """What to do when the Kramers moments' stated error (``fp``: the record of
    :func:`.stationary.fokker_planck_moments`) exceeds six digits at the cost ``budget``
    (``""`` else).

    Within a digit of six (a stated error up to 1e-5, or unmeasured): the sizes about 1.4
    times this solve's, to compare (SEDF mu = 0.01, D = 0.005, before the ladder climbed a
    Hermite rung: 182 x 740 stated 9.6e-6; the climb now states 2.9e-7 on 258 x 1040 and
    prints no advice).  Beyond it, the digits the solve has and the sizes six digits need at
    the least: ``ceil(log10(e/5e-7))`` steps of each ladder (1.4 times the functions, 1.25
    times the intervals), ``e`` its part of the stated error (``chebyshev_change`` the
    grid's, the rest the functions'; both the whole when the record has no grid part), as
    if each step gained a whole digit, which the grid's steps did not at low friction
    (SEDF at rest, Delta = 3, D = mu/2, 258 functions: 592 -> 832 -> 1040 intervals moved
    <v^2> by 8.9e-5, 1.5e-5 at mu = 0.005, by 2.3e-4, 1.3e-4 at mu = 0.002; the functions'
    182 -> 258 -> 364 by 4.4e-4, 2.7e-6 at mu = 0.005, by 4.5e-4, 1.5e-4 at mu = 0.002), with
    the memory (``N m^2``) and time (``N m^3``) of those sizes against this solve's.  Both
    name ``kbm noise --fp-budget`` with ``budget`` times the ratio of the costs ``N m^2``
    of those sizes and this solve's, the least raise that affords them (the ladders choose
    their sizes within it, :mod:`numerics.fokker_planck._stationary_orthonormal`, and state
    what they reach; before, the advice named a call of
    :func:`numerics.fokker_planck.stationary_kramers` with ``n_hermite``, ``n_cheb`` and
    ``max_cost``, the one way to more digits); beyond ``FACTOR_MEMORY``
    (:mod:`numerics.fokker_planck._pentadiagonal_disk`) the factors are kept on disk."""
    change, n, m = fp["hermite_change"], fp["hermite"], fp["chebyshev"] - 1
    if change is not None and change <= 1e-6:
        return ""
    if fp.get("elements"):
        return _element_advice(fp, budget)
    if change is None or change <= 1e-5:
        nb, mb = 2 * round(0.7 * n), 2 * round(0.7 * m)
        return (f"six digits need more than the Fokker-Planck budget ({budget:.2g}) "
                f"affords (this solve: {n} Hermite functions of x' x {m} Chebyshev intervals; "
                f"at low friction both must grow); for more digits (about {nb} x {mb}) rerun "
                f"with --fp-budget {budget * (nb / n) * (mb / m) ** 2:.2g} and compare")
    grid = fp.get("chebyshev_change")
    parts = (change, change) if grid is None else (max(change - grid, 0.0), grid)
    kh, kc = (max(0, math.ceil(math.log10(e / 5e-7) - 1e-9)) if e > 5e-7 else 0
              for e in parts)
    n6, m6 = 2 * round(n * 2 ** (kh / 2) / 2), 2 * round(m * 1.25**kc / 2)
    digits = max(0, math.floor(-math.log10(change)))
    return (f"the Fokker-Planck moments have about {digits} digits (stated relative "
            f"error {change:.2g}: the last refinements of the Hermite functions and the grid "
            f"moved them by that much, {n} Hermite functions of x' x {m} Chebyshev intervals, "
            f"within the Fokker-Planck budget {budget:.2g}); six digits are out of reach of "
            f"this solve: even if each step gained a digit (the grid's steps did not in the "
            f"SEDF at low friction), they need {kh} step{'s' * (kh != 1)} of the functions and "
            f"{kc} of the grid, at least {n6} x {m6}, "
            f"{(n6 / n) * (m6 / m) ** 2:.0f} times this solve's memory and "
            f"{(n6 / n) * (m6 / m) ** 3:.0f} times its time: rerun with --fp-budget "
            f"{budget * (n6 / n) * (m6 / m) ** 2:.2g}")


def energy_density_output(sol, model, params: dict, D: float, omega0: float,
                          workers: int | None = None) -> dict:
    """``P(E)`` of the Kramers solution with its stated error
    (:func:`numerics.fokker_planck._energy_density.energy_density_report`: the change under
    the solution's refinements; for Risken's pair, whose moments' error is not measured,
    the change on 1.25 times the intervals)."""
    from ..fokker_planck import stationary_kramers
    from ..fokker_planck._energy_density import energy_density_report

    finer = None
    if sol.basis == "risken":
        finer = stationary_kramers(model, {k: v for k, v in params.items() if k != "v"}, D,
                                   omega0=omega0, n_hermite=sol.coef.shape[0],
                                   n_cheb=2 * math.ceil(0.625 * (sol.x.size - 1)),
                                   sigma=sol.sigma, L=float(sol.x[0]))
    return energy_density_report(sol, finer, workers=workers)


def _element_advice(fp: dict, budget: float) -> str:
    """:func:`fp_advice` of the element ladder (:mod:`numerics.fokker_planck._elements_ladder`,
    ``fp["elements"]`` elements): the steps of each ladder its part of the stated error
    asks for, as if each gained a digit (functions by ``2^(1/2)``, elements by 1.2), and
    the budget ``N^2 E`` of those sizes against this solve's."""
    change, n, e = fp["hermite_change"], fp["hermite"], fp["elements"]
    grid = fp.get("chebyshev_change")
    if change is None:
        kh, ke = 1, 1
    else:
        parts = (change, change) if grid is None else (max(change - grid, 0.0), grid)
        kh, ke = (max(0, math.ceil(math.log10(p / 5e-7) - 1e-9)) if p > 5e-7 else 0
                  for p in parts)
    n6, e6 = 2 * round(n * 2 ** (kh / 2) / 2), 2 * math.ceil(e * 1.2**ke / 2)
    ratio = (n6 / n) ** 2 * (e6 / e)
    stated = "not measured" if change is None else f"{change:.2g}"
    return (f"six digits need more than the Fokker-Planck budget ({budget:.2g}) affords "
            f"(stated relative error {stated}: {n} Hermite functions of x' x {e} spectral "
            f"elements); they need {kh} step{'s' * (kh != 1)} of the functions and {ke} of "
            f"the elements, at least {n6} x {e6}, about {ratio:.0f} times this solve's "
            f"memory: rerun with --fp-budget {budget * ratio:.2g}")
