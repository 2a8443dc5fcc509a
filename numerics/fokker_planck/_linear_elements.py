"""The stationary Kramers equation of a linear damping ``-gamma x'`` on spectral elements
with its error measured (:func:`linear_stationary`, what :func:`.kramers.stationary_kramers`
runs for it unless sizes or ``basis`` are given).

Why elements and not Risken's pair on one Chebyshev grid (the route before, still
``basis="risken"``).  The exact density is ``exp(-H/kT)``: ``c_0 = exp(-G/kT)`` in the
Maxwellian of scale ``sigma^2 = kT`` and every other order zero, so the truncation in the
velocity costs nothing, and a grid that resolves ``exp(-G/kT)`` should give it.  On the
Chebyshev grid it did not at low friction: the grid's residual of ``c_0' + G' c_0/kT = 0``
(``_chebyshev_size`` resolves ``exp(-G/kT)`` to 1e-9) is driven by the transport, which the
friction ``gamma`` alone damps, and the solve returned it amplified.  The CDC at rest
(``Delta = 2``, ``lam = 1.3``, kT = 0.6), ``<x^2>`` against the quadrature of
``x^2 exp(-G/kT)``, relative: -1.5e-10, -8.8e-10, -2.2e-8, +1.4e-6, +1.1e-5 at ``mu`` =
0.15, 0.03, 0.01, 0.003, 0.001, and it was reported with the stated error 0 (its
``hermite_change``); refining the grid did not converge (370, 462, 554, 740 intervals at
``mu = 0.001``: +1.1e-5, -8.2e-6, +1.5e-6, +1.6e-5), and 24 functions instead of 12 made it
worse (-3.3e-2 at 370 intervals).  On continuous-Galerkin elements (:mod:`._elements`) the
transport is skew-symmetric but for the ends (summation by parts), so the friction is the
only symmetric part, as in the equation: the same case is 1e-12 off at ``mu = 0.01``,
2e-10 at 0.001, 2e-9 at 1e-4 (40 elements of degree 13, 12 functions, under 0.2 s).

The sizes: the Chebyshev intervals ``n`` that resolve ``exp(-G/kT)`` to 1e-9
(:func:`._model._chebyshev_size`) become ``2 ceil(n/16)`` elements of degree
:data:`DEGREE` (about 0.8 ``n`` nodes); the stated error (``hermite_change`` and
``chebyshev_change``) is the change of ``<x^2>`` and ``<v^2>`` on 1.25 times the elements,
and the grid grows by that step while the change exceeds ``tol`` (at most
:data:`MAX_STEPS` times).  The pair is kept in ``refinements``, so ``P(E)``'s stated error
is its change under the same step (:func:`._energy_density.energy_density_change`).
"""

from __future__ import annotations

import dataclasses
import math

from ._elements_solve import ElementKramersSolution, element_stationary
from ._model import _chebyshev_size, _half_width
from ._solution import moments_moved

__all__ = ["linear_stationary", "DEGREE", "HERMITE", "MAX_STEPS"]

#: the elements' degree (odd: :mod:`._elements`)
DEGREE = 13
#: the Hermite functions (the Maxwellian is the first; the rest carry the grid's residual)
HERMITE = 12
#: the most grid steps by 1.25 after the first pair
MAX_STEPS = 4


def _finer(E: int) -> int:
    return 2 * math.ceil(1.25 * E / 2)


def linear_stationary(split, D: float, kT: float, G, omega0: float, *, L: float | None = None,
                      sigma: float | None = None, tol: float = 1e-8
                      ) -> ElementKramersSolution:
    """The stationary density of a linear damping (module docstring) with its stated error.

    Parameters
    ----------
    split : kbm.model.conservative.ConservativeSplit
        The model at rest, its damping ``-gamma x'`` (``kT = D/gamma``).
    D, kT : float
        The noise intensity and the temperature.
    G, omega0
        The potential (numpy) and the linear frequency of ``a^2``.
    L, sigma : float, optional
        The half width of the range (default: where ``exp(-G/kT)`` is negligible,
        :func:`._model._half_width`) and the velocity scale (default ``kT^(1/2)``).
    tol : float
        The stated error aimed at (relative, ``<x^2>`` and ``<v^2>``).

    Returns
    -------
    ElementKramersSolution
        On ``2 ceil(n/16)`` elements or as many grid steps more as the change needed;
        ``hermite_change = chebyshev_change`` the last step's change, ``refinements`` that
        pair.
    """
    half = _half_width(G, kT) if L is None else float(L)
    s = math.sqrt(kT) if sigma is None else float(sigma)
    E = 2 * math.ceil(_chebyshev_size(G, kT, half) / 16)

    def solve(n: int) -> ElementKramersSolution:
        return element_stationary(split, D, s, half, HERMITE, n, DEGREE, G, omega0)

    sol = solve(E)
    for _ in range(MAX_STEPS + 1):
        fine = solve(_finer(E))
        change = moments_moved(sol, fine)
        if change <= tol:
            break
        sol, E = fine, _finer(E)
    return dataclasses.replace(sol, hermite_change=change, chebyshev_change=change,
                               refinements=((sol, fine),))
