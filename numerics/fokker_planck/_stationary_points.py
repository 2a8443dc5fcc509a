"""The velocity scale and the position points of the stationary Kramers solve of a nonlinear
damping (:func:`stationary_points`, what :func:`._stationary_orthonormal.stationary_orthonormal`
uses), and the separatrices' outer turning points (:func:`separatrix_turning_points`).

Where the points go.  At low friction the density is nearly a function of the energy,
``f(E)``, with a layer around each separatrix energy ``E_s = G(c)`` (``c`` a saddle,
a maximum of ``G``).  In the phase plane that layer follows the separatrix: across the
saddles, where :func:`._bases.cheb_centred` crowds points, and across ``v = 0`` again at
the orbit's outer turning point ``x_t``, ``G(x_t) = E_s``, where the separatrix is
vertical and the layer is a layer in ``x``.  Measured on the SEDF at rest, mu = 0.03,
Delta = 3, D = 0.015, 128 functions on 334 intervals (the last session's points, saddles
only), the error of the marginal against a 128 x 700 solve was largest at
``2.00 < x < 2.25`` (1.6e-4 of the peak; ``x_t = 2.057`` for the second saddle's
separatrix), with six points there.  The centres ``x_t`` of weight :data:`TURNING_WEIGHT`
and the width of their saddle's layer take the SEDF's <x^2> and <v^2> to six digits on
fewer points: with the folded ladder of :mod:`._stationary_orthonormal` (182 functions,
740 intervals), mu = 0.02 states 5.4e-7 with them and 1.2e-6 without; at mu = 0.03,
<x^2> of 182 functions on 524 intervals is 1.7e-8 from 182 x 1026 with them and 1.7e-7
without.  (The wider layers of the error sit on the flanks of the side wells, where the
separatrices are steep in the phase plane: a grid in ``x`` and ``v`` resolves a layer
slanted across both only with both fine, which is why no map of the points alone did.)

The bottom of the deepest well (``well``, the climb of
:func:`._stationary_orthonormal.stationary_orthonormal`).  At mu = 0.01 (D = 0.005) the
grid's error of <v^2> at 256 functions, measured point by point against 1282 intervals
(interpolated in the map's coordinate), sat at ``|x| < 0.5`` (70 % of it on 820
intervals, four points per 0.1 there against 14-18 by the saddles), where every
separatrix orbit passes at its largest speed.  A centre at ``x = 0`` as wide as the
distance to the nearest saddle, of weight :data:`WELL_WEIGHT`, takes <x^2> and <v^2> of
256 functions from 2.6e-7 and 1.9e-6 off to -1.4e-7 and 2.2e-7 on 820 intervals, and
from 1.0e-7 and 4.2e-7 to 2.2e-8 and 6.7e-8 on 1026 (against 362 x 1602).  Centres at all
seven wells' bottoms did worse (3.9e-7 in <v^2> on 820), as did a weight of 0.25
(6.2e-7).  At mu = 0.1 the centre moved 128 functions on 448 intervals from 1e-9 to
2.3e-8 off (the points it takes from the saddles), so only the climb uses it.

The floor of the velocity scale (:data:`TOP_REACH`).  The rule ``s = (delta V/(2 pi))^(1/2)``
resolves the reach ``V`` and the layer ``delta`` with ``N = pi V/delta`` functions, which
grows like ``mu^(-1/2)``: about 900 at mu = 0.005, 1400 at mu = 0.002, where the budget
stops the ladder at 258.  Those 258 functions then reach ``s (2N)^(1/2)`` = 3.1 at
mu = 0.002 (``s`` = 0.136) of a density with ``<v^2>^(1/2)`` = 1.37: <a^2> came out 3.669
(the first-order averaging's 4.0051, whose error is O(mu); stated 0.14).  Measured on the
SEDF at rest, Delta = 3, D = mu/2, mu = 0.005, on 800 intervals against 362 functions at
the scales 0.157 and 0.2 (which agree to 2e-7 in <x^2> and <v^2>), 258 functions are off
in <x^2>, <v^2> by -1.3e-5, -1.8e-5 at ``s`` = 0.17 (the rule's 0.171), +1.0e-6, +1.5e-6
at 0.185, -5.8e-6, -7e-6 at 0.2, -1.9e-5, -1.8e-5 at 0.22 and -1.9e-5, +3e-4 at 0.3; 182
functions are -4.9e-5, -2.9e-5 off at 0.2 and 2.6 %, 3.6 % at 0.17.  The best scale
makes the 258 functions reach ``2.8 <v^2>^(1/2)`` of the pilot (whose ``<v^2>`` = 2.41 is
30 % above the converged 1.86; 0.191 at mu = 0.005 and 0.002), so the scale is at least
that: ``s >= 2.8 (<v^2>/(2 * 258))^(1/2)``.  Above mu = 0.01 the rule is larger (0.2027
at mu = 0.01 against the floor's 0.190) and nothing changes.  At mu = 0.002 the route then
gives <a^2> = 4.00536 on 258 x 1040 (30 s CPU, where the route without the floor took
67 s), within 1.3e-4 of the averaging.

Other remedies judged by measurement: five other point maps and four other scales (the
fifteenth session) did not help; lower saddle weights
(0.6, 0.9 of 1.2) did no better (-2.1e-5 and -7.4e-6 at 334 intervals against -8.0e-6).
A multi-domain (patched) Chebyshev grid does not lower the work: the order-by-order LU
(:mod:`._pentadiagonal`) fills each order's Schur complement whatever the sparsity of
the derivative in ``x``, and ordering the unknowns by position instead costs
``m (p N)^2`` with ``N`` = 128-182 functions.  Factoring out ``exp(-H/kT_eff)`` leaves the
layers at ``E_s`` (they are in ``f(E)``, not in its Boltzmann part).  What lowered the
work is the symmetry of :mod:`._parity` (an eighth of the LU), which pays for the grids
the layers need.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["ALPHA", "SADDLE_WEIGHT", "LAYER_WIDTHS", "TURNING_WEIGHT", "WELL_WEIGHT",
           "VELOCITY_REACH", "TOP_REACH", "TOP_FUNCTIONS", "separatrix_turning_points",
           "stationary_points", "rule_functions"]

#: the Kosloff-Tal-Ezer parameter of the position points (:func:`._bases.cheb_mapped`)
ALPHA = 0.95
#: the saddles' total weight in the map of the points (:func:`._bases.cheb_centred`):
#: about ``pi w/(1 + pi w)`` = 79 % of the points within a few widths of the saddles
SADDLE_WEIGHT = 1.2
#: each saddle's width in the map, in layer widths ``l = (D/omega_b)^(1/2)/omega_b``: the
#: SEDF at mu = 0.1, Delta = 3, D = 0.05, 128 functions on 266 intervals: <x^2> 1.3e-5
#: off with 4 l, 1.2e-6 with 8 l, 1.7e-7 with 12 l, 1.3e-6 with 16 l (from 182 x 656)
LAYER_WIDTHS = 12.0
#: the weight of each separatrix's outer turning point in the map of the points, its
#: width that of its saddle (module docstring; SEDF mu = 0.02, 182 x 524: <x^2> 2.9e-7
#: and <v^2> 1.7e-6 from 362 x 1026, against 3.4e-6 in <x^2> without)
TURNING_WEIGHT = 0.1
#: the weight of the deepest well's bottom in the map of the points, its width the distance
#: to the nearest saddle (module docstring; SEDF mu = 0.01, D = 0.005, 256 functions on
#: 820 intervals: <x^2>, <v^2> off by 2.6e-7, 1.9e-6 without it, by -1.4e-7, 2.2e-7 with)
WELL_WEIGHT = 0.3
#: the density's reach in the velocity, in units of ``<v^2>^(1/2)`` (the scale's rule)
VELOCITY_REACH = 5.0
#: the reach the Hermite functions of the ladder's top rung at low friction
#: (:data:`TOP_FUNCTIONS`) keep at least, in units of the pilot's ``<v^2>^(1/2)``: the
#: floor of the scale (:func:`stationary_points`)
TOP_REACH = 2.8
#: the Hermite functions of the ladder's last rung at low friction within kbm noise's
#: budget (the climb of :func:`._stationary_orthonormal.stationary_orthonormal` to
#: 258 functions at mu = 0.01, 0.005, 0.002)
TOP_FUNCTIONS = 258


def separatrix_turning_points(G, saddles, half: float) -> list:
    """``[(x_t, i)]``: where the separatrix through each saddle ``c_i != 0`` meets
    ``v = 0`` again, the first point beyond ``c_i`` away from ``x = 0`` with
    ``G(x_t) = G(c_i)``, within ``(-half, half)`` (module docstring)."""
    from scipy.optimize import brentq

    out = []
    for i, c in enumerate(saddles):
        if c == 0:
            continue
        E = float(G(np.array(c)))
        z = c + np.sign(c) * np.linspace(0.0, half - abs(c), 4001)[1:]
        k = np.flatnonzero(np.asarray(G(z), float) > E)
        if k.size == 0 or k[0] == 0:
            continue
        a, b = z[k[0] - 1], z[k[0]]
        out.append((float(brentq(lambda q: float(G(np.array(q))) - E, min(a, b), max(a, b),
                                 xtol=1e-14)), i))
    return out


def stationary_points(split, D: float, G, half: float, v2: float,
                      sigma: float | None = None, well: bool = False) -> tuple[float, dict]:
    """``(sigma, points)``: the velocity scale and the keywords of the position points of
    :func:`._stationary_solve.orthonormal_stationary` (steps 2 and 3 of
    :func:`._stationary_orthonormal.stationary_orthonormal`).

    ``sigma`` (unless given) resolves the reach ``V = 5 <v^2>^(1/2)`` and the velocity
    layer ``delta = (D/omega)^(1/2)``, ``omega^2`` the largest ``|g'|`` on the range:
    ``sigma = (delta V/(2 pi))^(1/2)``, and at least ``TOP_REACH (<v^2>/(2 TOP_FUNCTIONS))
    ^(1/2)`` (the module docstring: below mu = 0.01 the functions that rule needs are
    beyond the budget, and the ladder's last rung must reach the density).  The points
    crowd at the saddles (maxima of ``G``, each ``12 l`` wide, ``l = delta_b/omega_b``) and
    at their separatrices' outer turning points (:func:`separatrix_turning_points`, the
    same width), and with ``well`` at the bottom of the deepest well too
    (:data:`WELL_WEIGHT`, as wide as the distance to the nearest saddle); without saddles
    the Kosloff-Tal-Ezer map alone."""
    from scipy.optimize import brentq

    g, gp = split.numpy_functions()[:2]
    z = np.linspace(-half, half, 20001)
    gz = np.asarray(g(z), float)
    saddles = [brentq(g, z[i], z[i + 1], xtol=1e-14)
               for i in np.flatnonzero((gz[:-1] > 0) & (gz[1:] <= 0))]
    wmax = _largest_frequency(gp, z)
    if sigma is None:
        sigma = max(math.sqrt(math.sqrt(D / wmax) * VELOCITY_REACH * math.sqrt(v2)
                              / (2 * math.pi)),
                    TOP_REACH * math.sqrt(v2 / (2 * TOP_FUNCTIONS)))
    if not saddles:
        return float(sigma), dict(alpha=ALPHA)
    wb = [math.sqrt(abs(float(gp(np.array(c))))) for c in saddles]
    layers = [LAYER_WIDTHS * math.sqrt(D / w) / w for w in wb]
    turns = separatrix_turning_points(G, saddles, half)
    bottoms = _deepest_wells(g, G, z, gz) if well else []
    reach = [min(abs(c - b) for c in saddles) for b in bottoms]
    return float(sigma), dict(
        alpha=ALPHA, centres=tuple(saddles) + tuple(t for t, _ in turns) + tuple(bottoms),
        widths=tuple(layers) + tuple(layers[i] for _, i in turns) + tuple(reach),
        weight=(SADDLE_WEIGHT / len(saddles),) * len(saddles) + (TURNING_WEIGHT,) * len(turns)
        + (WELL_WEIGHT,) * len(bottoms))


def rule_functions(split, D: float, half: float, v2: float) -> float:
    """``N = pi V/delta``: the Hermite functions that resolve the reach ``V = 5 <v^2>^(1/2)``
    and the velocity layer ``delta = (D/omega)^(1/2)`` at the scale of the rule
    (:func:`stationary_points`; ``omega^2`` the largest ``|g'|`` on ``(-half, half)``)."""
    gp = split.numpy_functions()[1]
    delta = math.sqrt(D / _largest_frequency(gp, np.linspace(-half, half, 20001)))
    return math.pi * VELOCITY_REACH * math.sqrt(v2) / delta


def _largest_frequency(gp, z: np.ndarray) -> float:
    """``max |g'|^(1/2)`` at the points ``z``."""
    return math.sqrt(float(np.max(np.abs(gp(z)))))


def _deepest_wells(g, G, z: np.ndarray, gz: np.ndarray) -> list:
    """The bottoms of the deepest wells (minima of ``G``, the roots of ``g`` where it turns
    positive, within ``1e-9`` of the lowest ``G``: a mirrored pair in an even potential),
    a root within ``1e-12`` of the range of 0 set to 0 (the points stay symmetric)."""
    from scipy.optimize import brentq

    roots = []
    for i in np.flatnonzero((gz[:-1] < 0) & (gz[1:] >= 0)):
        r = z[i + 1] if gz[i + 1] == 0 else brentq(g, z[i], z[i + 1], xtol=1e-14)
        roots.append(0.0 if abs(r) <= 1e-12 * z[-1] else float(r))
    depth = np.asarray(G(np.array(roots)), float)
    scale = max(float(np.max(np.abs(depth))), 1.0)
    return [r for r, d in zip(roots, depth) if d <= depth.min() + 1e-9 * scale]
