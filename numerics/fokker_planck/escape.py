"""The escape rate from the well at the origin by the Kramers equation: the slowest decay
rate of the density when everything that reaches a neighbouring well is removed.

At the bottoms ``x_wl < x_l < 0 < x_r < x_wr`` of the next wells beyond the saddles a sink
``kappa(x)`` (:func:`._sink_pairs.tanh_sink`: ``kappa_0 [1 + tanh((|x| - |x_w|)/w)]/2``, ten times stronger
from ``2.5 w`` past the bottoms) is added to the Kramers operator (:mod:`.kramers`); ``w``
is a tenth of the saddle-to-bottom distance and ``kappa_0`` absorbs a particle arriving at
the bottom's speed ``sqrt(2 (E_b - G(x_w)))`` within ``w``.  The population of the well
then decays as ``exp(-r t)`` with ``r`` the smallest eigenvalue of ``-(L - kappa)``
(Hanggi, Talkner and Borkovec, Rev. Mod. Phys. 62 (1990) 251, sec. II.C: the rate as the
lowest nonvanishing eigenvalue): the rate of transitions to the next wells (flux over
population), what Kramers' and Mel'nikov-Meshkov's formulas describe, and the rate of
simulated first passages to the lines ``x = x_w``.

Every damping (``basis="orthonormal"``, the default; :mod:`._orthonormal`): orthonormal
Hermite functions of the velocity at the scale ``s`` of
:func:`._orthonormal.velocity_scale` (in Risken's pair the high orders grow where the
damping is negative, and the ladder did not converge), the blocks assembled from the terms
(:mod:`._blocks`) and shift-invert Arnoldi, on Kosloff-Tal-Ezer points crowded at the
saddles and the sink (:func:`._bases.cheb_centred`).  Where ``(x, v) -> (-x, -v)`` maps
the model onto itself (linear damping in an even potential; the SEDF at rest, whose
``mu (beta x^2 - 1)`` is even, :func:`._parity.reflection_symmetric`) the operator is
folded by parity and eliminated from the lowest orders up, one factorisation for the
whole Hermite ladder (:mod:`._folded`; the SEDF, Delta = 3, D = 0.2 mu: mu = 0.02 10 s of
CPU against 47 s unfolded, the same rate to 6e-16, and mu = 0.005 within the default
budget, docs/noise-escape.rst).  Where the layer's ``2.2 L/l`` intervals exceed
``max_cheb`` (low friction) a folded model's ladder runs on spectral elements instead
(:mod:`._escape_elements`, ``chebyshev`` then counts their intervals).  Linear damping in Risken's
pair at ``sigma = sqrt(kT)`` (``basis="pair"``, :mod:`._fraction`, :mod:`._rungs`): the
matrix is block tridiagonal with blocks known in closed form, eliminated the same way; the
independent check of the orthonormal rate.

Why the velocity expansion needs many functions at low friction (docs/noise.rst): the
density has a layer along the separatrix, sharpest at the saddle, where the stream that the
saddle reflects back into the well (energies below ``E_b``) meets no stream from outside
(the particles above ``E_b`` left for the sink).  Its width in the velocity is about
``delta = (D/omega_b)^(1/2) = sigma (gamma/omega_b)^(1/2)``, so Risken's functions at the
scale ``sigma`` needed grow like ``omega_b/gamma`` (about ``10 omega_b/gamma`` for 1e-6;
that ladder starts there, not at 64), the orthonormal ones at the scale ``s`` only like
``(omega_b/gamma)^(1/2)`` (they resolve ``delta`` and reach the Maxwellian's tail:
CDC, mu = 0.02, 128 against 2896), and the Chebyshev intervals like ``L/l``,
``l = (D/omega_b)^(1/2)/omega_b`` the layer's width in ``x``.  This is the physics of the rate (Mel'nikov-Meshkov's boundary layer), not
of the sink: whatever removes the particles that crossed leaves it, and the rate does not
depend on the sink's sharpness to 1e-7 at mu = 0.02.

The Hermite truncation grows by ``sqrt 2`` until two successive rates agree to ``tol``; the
last change is ``truncation_error``, the change on a finer position grid
``chebyshev_error`` and the change under the sharper sink (three times stronger, half as
wide) ``sink_error``.  Where that change exceeds ``1e-7`` of the rate (any damping;
higher friction: the density near the next wells' bottoms goes back to the saddle, and
the rate depends on where the absorption happens), the rate of first passages to ``x =
+-x_w`` lies between two ladders of sharpening sinks, one rising and one falling
(:mod:`._sink`): the rate is the midpoint of their top rungs and ``sink_error`` half
their gap, and the other two errors include the midpoint's changes on a finer grid and
one Hermite truncation lower (linear damping in an even potential: the rungs in
orthonormal functions at a fraction of the thermal speed, folded, on points crowded at the
sink on several scales, :func:`._sink.absorbing_limit` with ``adaptive``; from rung 9
both sinks of a rung from one factorisation at their midpoint and the rate's slope there,
:mod:`._sink_pairs`).  Compared
(tests/test_fokker_planck_escape.py, docs/noise.rst) with simulated first passages,
Kramers' spatial-diffusion rate, the Mel'nikov-Meshkov rate and the energy-diffusion MFPT
of the averaged energy.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from kbm.model.conservative import split_conservative
from kbm.errors import ModelError, ParameterError
from kbm.parameters.names import noise_intensity

from ..noise.budget import ESCAPE_FP_BUDGET
from ._bases import cheb_centred
from ._blocks import on_one_blas_thread
from ._escape_elements import ElementRungs
from ._folded import FoldedRungs
from ._ladder import budget_to_give
from ._orthonormal import nonlinear_escape, orthonormal_slowest
from ._parity import reflection_symmetric, symmetric
from ._rungs import FractionRungs, pair_escape
from ._problem import escape_problem, hermite_ladder, kT_gamma
from ._sink_pairs import tanh_sink, tanh_sink_slope
from ._sink import (SINK_HERMITE, SINK_INTERVALS, SINK_TOL, WEIGHT, absorbing_limit, sink_grading,
                    sink_rung, sink_scale)

__all__ = ["KramersEscape", "kramers_escape"]

#: the Kosloff-Tal-Ezer parameter of the position grid for linear damping
#: (:func:`._bases.cheb_mapped`): at mu = 0.02 (docs/noise.rst) 288 mapped intervals give
#: the rate to 1.3e-7, where plain Chebyshev points are 2.5e-6 off
ALPHA = 0.9
#: the weights of the saddles and of the sink's centres (the next wells' bottoms) in the map
#: of the points for linear damping (:func:`._bases.cheb_centred`; widths half the saddles'
#: distances from the bottom, and 2.5 sink widths): about three quarters of the points near
#: the saddles, where the layer is sharpest, and enough at the sink to resolve the sharper
#: one of ``sink_error``.  The saddles' weight is 0 where ``n_cheb`` exceeds the layer's
#: ``2.2 L/l`` intervals (higher friction: the layer is wide, the sink matters more).  CDC
#: Delta = 3, kT = 0.35, mu = 0.02, 2048 Hermite functions (docs/noise.rst): 214 intervals
#: give the rates of both sinks to 7e-10 of the Kosloff-Tal-Ezer points' on 286 intervals
#: (themselves 2e-8 from 344), where the Kosloff-Tal-Ezer points alone on 200 intervals are
#: 5.4e-5 off; the high Hermite orders need more (docs/noise.rst)
SADDLES, WELLS = 1.0, 0.05
#: linear damping in an even potential: Risken's pair (``basis="pair"``) where its first
#: Hermite truncation ``8 omega_b/gamma`` is at most this, else the folded orthonormal
#: functions (``basis="auto"``).  CDC Delta = 3, kT = 0.35, the rate alone (CPU, pair against
#: orthonormal): mu = 1 0.12 against 0.72 s, mu = 0.2 (168) 0.3-0.4 against 0.5-0.7 s,
#: mu = 0.1 (335) 1.2-1.4 against 1.0-1.1 s, mu = 0.05 2.6 against 1.1-1.2 s, mu = 0.02
#: about 9 against 2.8 s: the orthonormal blocks hold two orders (4 times the work per
#: order) and the scale check adds a factorisation, against far fewer orders
PAIR_HERMITE = 256
#: the grid's top on spectral elements (``basis="auto"`` where the layer's ``2.2 L/l``
#: intervals exceed ``max_cheb``, :mod:`._escape_elements`), in units of ``2.2 L/l``
ELEMENT_TOP = 4
#: the weight of the sink's centres in the elements' map (the saddles' is 1): CDC mu = 0.05
#: with ``max_cheb=200`` (elements), the two sinks 4.8e-7 of the rate apart with none (the
#: sink ladders then ran), where the Chebyshev points' end crowding gives 4e-9
WELL_ELEMENTS = 0.15
#: the first number of position intervals for linear damping, in units of ``L/l``
#: (``l`` the layer's width in ``x``, :func:`kramers_escape`)
LAYER_INTERVALS = 2.2


@dataclass(frozen=True)
class KramersEscape:
    """The escape rate from the well at the origin by the Kramers equation.

    Attributes
    ----------
    rate : float
        The slowest decay rate at the largest Hermite truncation.
    sink_error, truncation_error : float
        The change of the rate under a sink three times stronger and half as wide (at the
        truncation before the last), and from the truncation before the last.
    saddles : tuple of float
    hermite, chebyshev : int
        The Hermite truncation of :attr:`rate` and the Chebyshev points.
    wells : tuple of float
        The next wells' bottoms, where the sink sits.
    ladder : tuple of (int, int, float)
        ``(Hermite functions, Chebyshev intervals, rate)`` of every solve (the
        convergence table).
    chebyshev_error : float
        The change of the rate on 1.2 times as many Chebyshev intervals.
    scale_error : float
        The change of the rate at the largest truncation when the velocity scale of the
        orthonormal Hermite functions is 1.3 times larger (another basis;
        :mod:`._orthonormal`), included in :attr:`truncation_error`; ``nan`` for Risken's
        pair (``basis="pair"``).
    velocity_scale : float
        The scale ``s`` of the velocity's Hermite functions
        (:func:`._orthonormal.velocity_scale`; ``nan`` for Risken's pair, whose scale is
        ``sqrt(kT)``).
    sink_ladder : tuple of float
        The rates of the sink ladders (:mod:`._sink`) where they ran (the two sinks
        disagreed by more than :data:`._sink.SINK_TOL`), the rising ladder's then the
        falling one's (each half): :attr:`rate` is then the midpoint of their top rungs,
        which bracket a perfectly absorbing sink's rate, and :attr:`sink_error` half their
        gap; empty where the first sink's rate is kept.
    budget_note : str
        Where the Hermite and grid ladders stopped (the budget ``max_cost`` or their tops)
        with a measured change above ``tol`` of the rate: the changes and the next rung's
        cost (:func:`._ladder.hermite_chebyshev_ladder`); where a rung of the sink ladders
        exceeded the budget: which, its cost and the budget to give (the rate is then the
        first sink's, with the two sinks' change as its ``sink_error``); ``""`` otherwise.
    sink_offsets : tuple of (float, float)
        The sinks' offsets ``(rising, falling)`` of each rung of :attr:`sink_ladder`
        (:func:`._sink.ladder_offsets`).
    """

    rate: float
    sink_error: float
    truncation_error: float
    saddles: tuple
    hermite: int
    chebyshev: int
    wells: tuple = ()
    ladder: tuple = ()
    chebyshev_error: float = float("nan")
    scale_error: float = float("nan")
    velocity_scale: float = float("nan")
    sink_ladder: tuple = ()
    sink_offsets: tuple = ()
    budget_note: str = ""

    def __repr__(self) -> str:
        return (f"KramersEscape(rate={self.rate:.7g} +- {self.sink_error:.2g} (sink) +- "
                f"{self.truncation_error:.2g} (truncation) +- {self.chebyshev_error:.2g} (Chebyshev))")


@on_one_blas_thread
def kramers_escape(model, params: dict, D: float, saddles: tuple, *, n_hermite: int = 64,
                   n_cheb: int = 128, margin: float | None = None, tol: float | None = None,
                   max_hermite: int = 4096, max_cheb: int = 720,
                   max_cost: float = ESCAPE_FP_BUDGET, basis: str = "auto",
                   sink_tol: float | None = None) -> KramersEscape:
    """The rate of transitions out of the well at the origin from the Kramers equation with
    a sink at the next wells' bottoms.

    Parameters
    ----------
    model : str or kbm.model.builtins.Oscillator
        An autonomous model with a well at the origin (a slider at ``v = 0``).
    params : dict
        Its parameters with ``mu``.
    D : float
        Noise intensity, ``> 0``.
    saddles : (float, float)
        The saddles ``x_l < 0 < x_r`` bounding the well.
    n_hermite : int
        The smallest first Hermite truncation; it grows by ``sqrt 2`` until two successive
        rates agree to ``tol`` (or ``max_hermite``; the last change is
        ``truncation_error``).  The functions are orthonormal Hermite functions at the
        scale of :func:`._orthonormal.velocity_scale`, and the ladder also stops only when
        the rate at a 1.3 times larger scale agrees (``scale_error``).  In Risken's pair
        (``basis="pair"``) the first truncation is at least ``8 omega_b/gamma`` (the
        velocity layer at the saddle, of width ``(D/omega_b)^(1/2) = sigma
        (gamma/omega_b)^(1/2)``, needs that many).
    n_cheb : int
        The smallest first number of Chebyshev intervals in the position (at least
        ``2.2 L/l`` (:data:`LAYER_INTERVALS`),
        ``l = (D/omega_b)^(1/2)/omega_b`` the layer's width in ``x``, on points crowded at
        the saddles, :func:`._bases.cheb_centred`; for linear damping only where ``2.2
        L/l`` exceeds ``n_cheb``): after the Hermite ladder the rate is recomputed on 1.2
        times as many intervals; when it moves by more than ``tol`` the ladder runs again
        on the finer grid (up to ``max_cheb``).
    margin : float, optional
        How far past the next wells' bottoms the range reaches (default half the larger
        saddle-to-bottom distance; the sink lives there).
    tol : float, optional
        Relative change of the rate at which the ladders stop (default ``1e-6``).
    max_hermite, max_cheb : int
        The ladders' tops.
    max_cost : float
        The factorisation keeps at most ``3 max_cost`` numbers (720 MB at 3e7): ``3
        n_hermite n_cheb^2`` for the block LU in orthonormal functions (``2 n_hermite
        (n_cheb/2 + 1)^2`` folded by parity, :class:`._folded.FoldedRungs`), ``n_hermite
        n_points^2`` in Risken's pair (``n_points`` about ``n_cheb/2`` when folded by
        parity), ``max_cost`` a third of it: no solve exceeds it.  The Hermite ladder stops
        at its last rung that fits, the grid's check and growth where they do not fit
        (:mod:`._ladder`), the sink ladders at their first rung that does not
        (``budget_note``).
    basis : {"auto", "orthonormal", "pair"}
        The velocity's functions: orthonormal Hermite functions (every damping), or
        Risken's pair at ``sqrt(kT)`` (linear damping only; the ladder of 2896 functions
        at mu = 0.02 where the orthonormal one needs 128).  ``"auto"``: the pair for linear
        damping where ``8 omega_b/gamma <= PAIR_HERMITE`` (:data:`PAIR_HERMITE`, higher
        friction) or the potential is not even, else orthonormal.
    sink_tol : float, optional
        The relative change between the two sinks above which the rate is the sink
        ladders' limit (:mod:`._sink`; default :data:`._sink.SINK_TOL`, 1e-7; ``inf``: the
        first sink's rate and change).

    Returns
    -------
    KramersEscape

    Raises
    ------
    numerics.errors.BudgetError
        Before any solve, when the first two rungs of the Hermite ladder or its first grid
        check exceed ``max_cost`` (the message gives their costs).
    """
    D = noise_intensity(D, "the escape needs noise")
    xl, xr = map(float, saddles)
    if not (math.isfinite(xl) and math.isfinite(xr) and xl < 0 < xr):
        raise ModelError(f"saddles {saddles}: need x_l < 0 < x_r (a well at the origin "
                         "bounded on both sides)")
    split = split_conservative(model, {k: v for k, v in dict(params).items() if k != "D"})
    mu = float(split.mu)
    if not mu > 0:
        raise ParameterError(f"mu = {mu:g} must be > 0")
    kT, gamma = kT_gamma(split, D)
    linear = kT is not None
    if basis not in ("auto", "orthonormal", "pair"):
        raise ParameterError(f"basis = {basis!r}: choose 'auto', 'orthonormal' or 'pair'")
    if basis == "pair" and not linear:
        raise ParameterError("basis = 'pair' needs linear damping -gamma x' (the pair's high "
                             "orders grow where the damping is negative); use "
                             "'orthonormal'")
    sigma, wells, half, kappa0, width = escape_problem(split, D, (xl, xr), margin)
    gp = split.numpy_functions()[1]
    tol = 1e-6 if tol is None else float(tol)
    wb = max(math.sqrt(abs(float(gp(np.array(s))))) for s in (xl, xr))
    layer = math.sqrt(D / wb) / wb
    by_layer = 2 * math.ceil(LAYER_INTERVALS / 2 * half / layer)
    # linear damping: the points crowd at the saddles only where the layer sets their number
    crowd = SADDLES if not linear or by_layer > n_cheb else 0.0

    def points(nc):
        return cheb_centred(nc, half, ALPHA, (xl, xr) + tuple(wells),
                            (-xl / 2, xr / 2, 2.5 * width, 2.5 * width),
                            (crowd, crowd, WELLS, WELLS))

    def sink(xs, sharp):  # sharp = 2: the sharper sink of sink_error
        return tanh_sink(xs, wells, kappa0 * (3 if sharp > 1 else 1), width / sharp)

    xs = points(64)[0]
    # folded by parity (._folded) wherever (x, v) -> (-x, -v) maps the model, the points and
    # the sink onto themselves: linear damping in an even potential, and the SEDF at rest
    fold = (symmetric(split.numpy_functions()[0](xs), wells, xs)
            and (linear or reflection_symmetric(split, xs)))
    slowest = FoldedRungs(max_hermite) if fold else None
    if basis == "auto" and fold and by_layer > max_cheb:  # the layer's points beyond the
        # Chebyshev grid's top: spectral elements (._escape_elements), the grid's top theirs
        slowest = ElementRungs(half, (xl, xr) + tuple(wells),
                               (-xl / 2, xr / 2, 2.5 * width, 2.5 * width),
                               (1.0, 1.0, WELL_ELEMENTS, WELL_ELEMENTS))
        max_cheb = ELEMENT_TOP * by_layer
    if basis == "auto":  # the pair where its ladder is short (docs/noise.rst: faster there)
        basis = ("orthonormal" if not linear or (fold and 8 * wb / gamma > PAIR_HERMITE)
                 else "pair")
    if basis == "orthonormal":  # orthonormal Hermite functions (._orthonormal, ._folded)
        out = nonlinear_escape(
            split, D, (xl, xr), half, sink, points, hermite_ladder, n_hermite=n_hermite, n_cheb=n_cheb, tol=tol,
            max_hermite=max_hermite, max_cheb=max_cheb, max_cost=max_cost,
            layer_intervals=LAYER_INTERVALS, slowest=slowest)
    else:  # Risken's pair (._rungs): the first truncation from the saddle's layer
        start = next(n for n in hermite_ladder(int(n_hermite),
                                               2 * int(n_hermite) + 16 * wb / gamma)
                     if n >= 8 * wb / gamma or n >= max_hermite)
        out = pair_escape(split, sigma, gamma, wells, sink, points, hermite_ladder,
                          start=start, n_cheb=max(int(n_cheb), by_layer), tol=tol,
                          max_hermite=max_hermite, max_cheb=max_cheb, max_cost=max_cost)
    # the sink ladders where the two sinks disagree (._sink; nonlinear damping on the sizes
    # of its own ladder)
    sink_tol = SINK_TOL if sink_tol is None else float(sink_tol)
    if out["sink_error"] > sink_tol * abs(out["rate"]):

        adaptive = linear and fold  # orthonormal functions at SINK_SCALE sqrt(kT) (._sink)
        solvers: dict = {}  # the factors of the current rung's two sinks (and grids)
        last: list = [None]  # the last rung's slowest mode: the next factors' first start

        def rung_cost(nh, nc):  # in the budget's units, as the ladders' (numbers kept / 3)
            if basis == "pair" and not adaptive:
                m = nc // 2 + 1 if fold else nc + 1
                return nh * m * m / 3
            return (FoldedRungs.numbers(nh, nc) if adaptive or fold else 3 * nh * nc**2) / 3

        def rung(j, offset, nc, nh, slope=False):  # the rate with rung j's sink (._sink)
            if rung_cost(nh, nc) > max_cost:
                raise _OverBudget(j, nh, nc, rung_cost(nh, nc))
            centres, kap, w = sink_rung(wells, kappa0, width, j, offset)
            grading = sink_grading(j) if adaptive else ((2.5, WEIGHT),)

            widths = tuple(f * w for f, _ in grading for _ in (0, 1))
            weights = tuple(q for _, q in grading for _ in (0, 1))

            def pts(m):
                return cheb_centred(m, half, ALPHA, (xl, xr) + centres * len(grading),
                                    (-xl / 2, xr / 2) + widths, (crowd, crowd) + weights)

            def snk(xs, sharp=1):
                return tanh_sink(xs, centres, kap, w)

            if adaptive:  # one factorisation per sink and grid, extended up the truncations
                for key in [k for k in solvers if k[0] != j or k[2] != nc]:
                    del solvers[key]  # the factors of another rung or grid freed first
                solver = solvers.get((j, offset, nc))
                if solver is None:
                    solver = solvers[j, offset, nc] = FoldedRungs(4 * nh, by_order=True,
                                                                  start=last[0])
                rate = solver(split, D, sink_scale(j) * math.sqrt(kT), pts, nh, nc, snk)
                last[0] = solver.mode
                if slope:  # and dr/d(offset) on demand (._sink_pairs)
                    return rate, lambda: solver.slope(
                        lambda xs: tanh_sink_slope(xs, centres, kap, w))
                return rate
            if basis == "pair":
                return FractionRungs(split, sigma, gamma, centres, snk, pts).rate(nh, nc)
            solver = FoldedRungs(nh) if fold else orthonormal_slowest
            return solver(split, D, out["velocity_scale"], pts, nh, nc, snk)

        try:
            out = absorbing_limit(out, rung, least=(SINK_HERMITE, SINK_INTERVALS) if linear
                                  else (0, 0), adaptive=adaptive, paired=adaptive)
        except _OverBudget as over:
            j, nh, nc, c = over.args
            out = dict(out, budget_note="; ".join(filter(None, [out.get("budget_note", ""), (
                f"the sink ladder's rung {j} needs {nh} Hermite functions x {nc + 1} Chebyshev "
                f"points (cost {c:.3g}), above --fp-budget {max_cost:.3g}: the rate is the "
                "first sink's and its sink error the change between two sinks; raise "
                f"--fp-budget to {budget_to_give(c)} or more for the perfectly absorbing "
                "limit")])))
    return KramersEscape(saddles=(xl, xr), wells=wells, **out)


class _OverBudget(Exception):
    """A rung of the sink ladders above the budget: ``(rung, n_hermite, n_cheb, cost)``."""
