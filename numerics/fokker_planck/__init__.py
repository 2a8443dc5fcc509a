"""Fokker-Planck (Kramers) equation of the one-degree-of-freedom models at rest: the stationary
density (:mod:`.kramers`) and the escape rate from the well at the origin (:mod:`.escape`,
its setup in :mod:`._problem`), solved numerically in Hermite functions of the velocity
times Chebyshev points in the position; :mod:`._bases` holds the two bases,
:mod:`._solution` the stationary density's class, :mod:`._blocks` the block tridiagonal LU
of the Kramers matrix in the Hermite index, :mod:`._fraction` the escape matrix of a
linearly damped model in closed-form blocks, folded by parity (the matrix continued fraction
in LU form, eliminated upward), :mod:`._sweeps` its compiled solve sweeps, :mod:`._rungs`
the escape ladder's solves sharing one factorisation per grid, :mod:`._orthonormal` the
escape of a nonlinearly damped model in orthonormal Hermite functions, :mod:`._folded` the
same for linear damping at low friction, folded by parity and eliminated upward (order by
order in the sink ladders' rungs, :mod:`._folded_orders`), and
:mod:`._stationary_solve` its stationary density in the same functions (one solve; the
ladders that choose and measure its sizes in :mod:`._stationary_orthonormal`), factorised
order by order by :mod:`._pentadiagonal` when the damping is linear in the velocity (its
factors on disk beyond a memory cap, :mod:`._pentadiagonal_disk`; on the largest grids in
single precision, the preconditioner of GMRES in :mod:`._bordered`), on the
points chosen by :mod:`._stationary_points` and folded by :mod:`._parity` when the model is
symmetric under ``(x, v) -> (-x, -v)``, its ladder's last step in :mod:`._stationary_climb`;
:mod:`._hermite_functions` holds those functions' values and integrals,
:mod:`._energy_density` the density of the energy ``P(E)`` of a stationary solution with its
stated error (its quadrature in :mod:`._energy_quadrature`).  A second discretisation of the
stationary solve in ``x``, spectral elements factorised by static condensation
(:mod:`._elements`, :mod:`._elements_lu`, one solve in :mod:`._elements_solve`), is the
default for a nonlinear damping whose potential has saddles on the range (the multi-well
SEDF), with its own ladder of Hermite functions and elements and its stated error
(:mod:`._elements_ladder`; ``basis="orthonormal"`` keeps the Chebyshev ladder there,
``basis="elements"`` asks for the element ladder elsewhere), and ``P(E)`` on each element
(:meth:`._elements_solve.ElementKramersSolution.pieces`); one solve at given sizes by
``stationary_kramers(elements=(E, p), n_hermite=N)``.  A linear damping is solved on the
same elements by :mod:`._linear_elements` (12 functions, its error the change on a finer
element grid)."""

from .escape import KramersEscape, kramers_escape
from .kramers import kramers_operator, stationary_kramers
from ._model import velocity_terms
from ._solution import KramersSolution

__all__ = ["KramersSolution", "kramers_operator", "stationary_kramers", "velocity_terms",
           "KramersEscape", "kramers_escape"]
