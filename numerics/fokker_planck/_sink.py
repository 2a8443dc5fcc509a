"""The escape's sink (:func:`tanh_sink`) and the rate in the limit of a perfectly absorbing
sink (:func:`absorbing_limit` by :func:`sink_bracket`, run by :func:`.escape.kramers_escape`
where the two sinks of ``sink_error`` disagree by more than :data:`SINK_TOL` of the rate).

The rate of :mod:`.escape` is that of first passages to the lines ``x = x_w`` at the next
wells' bottoms: the limit of a sink that absorbs everything past ``x_w`` at once.  At low
friction the limit is reached at the first sink (CDC Delta = 3, kT = 0.35: 2e-12 apart at
mu = 0.02, 5e-8 relative at mu = 0.2), since a particle that crossed the saddle with an
energy above the barrier rarely comes back.  As the friction grows the density relaxes in
``x`` by diffusion, the next well's bottom (1.65 kT below the saddle there) holds density
that goes back to the saddle, and the rate depends on where the absorption happens: moving
the line by 0.01 moves the rate by 1.4e-5 relative at mu = 1 and by 2e-3 at mu = 5.  A sink
``kappa [1 + tanh((|x| - c)/w)]/2`` absorbs a particle of speed ``v`` where its optical
depth ``int kappa dx/v`` reaches one, about ``(w/2) ln(kappa w/2v)`` before its centre
``c``, so a sharper sink (``3 kappa``, ``w/2``) moves the line by a fraction of ``w`` and
the rate converges only algebraically in ``w`` (the Kramers equation's absorbing wall is a
singular limit: Milne's boundary layer of width ``sqrt(kT)/gamma``): with the first sink
the stated ``sink_error`` was 7 times smaller than the distance to the limit at mu = 1
(4.7e-7 against 3.4e-6) and 3.5 times at mu = 5.

The ladders: rung ``j`` has the width ``w_j = w/2^j`` and the strength ``kappa_j = kappa 4^j``
(the optical depth doubles), so the line where a particle of speed ``v`` is absorbed lies
``(o - o_c) w_j`` past ``x_w`` for a centre ``o + j ln(2)/2`` widths past it (``o_c`` about
half the log of the first optical depth).  At each rung the rate is then a straight line
in the offset, ``r_j(o) = r - a w_j (o - o*_j)`` (``a > 0``; a sink moved out is smaller
everywhere, so the rate falls with ``o``, Feynman-Kac; CDC mu = 10, offsets 0.5 to 2: the
slope halves per rung to 1e-3 and the curvature is 5e-5 of it): the rung's rate lies below
the limit ``r`` past the critical offset ``o*_j`` and above it short of it.  ``o*_j`` is not
constant (the slow particles are not absorbed ballistically): it grows about linearly with
the rung, ``o*_j = o_0 + k j`` (CDC Delta = 3, kT = 0.35: ``k`` = 0.10-0.11 per rung at mu = 5
and 10 up to the tenth rung; at mu = 1 0.16 at the first rungs, levelling off at 1.9 by the
ninth), so every fixed offset is passed (h-sink2's falling ladder at 1.6 rose from the
seventh rung at mu = 10).  The step between rungs ``j`` and ``j + 1`` at the offset ``o`` is
``a w_j [(o - o*_j) + k]/2``: it vanishes at ``o*_j - k = o*_{j-1}`` (:func:`step_zero`),
which both ladders measure, the straight line of each rung through their two rates.  From
rung :data:`TRACK` on (:func:`ladder_offsets`) the falling ladder sits at ``s + k``, ``s``
the last zero of the step and ``k`` its last growth (the critical offset of two rungs back:
short of the current one while it grows) and the rising one :data:`MARGIN` past ``s + 3 k``
(the current one where it grows linearly; past it where it levels off), never short of
:data:`OFFSET`; before, the rising ladder is centred :data:`OFFSET` widths out and the
falling one ``RAMP j`` (h-sink2's rule), but from rung :data:`CAP` no further out than
``s + k`` (at mu = 20 and 50 the critical offset is 0.9-1.3 widths over the first rungs;
``RAMP j`` came within 0.1 widths of it (mu = 20) or past it (mu = 50) at rung 5, and the
falling ladder rose at rung 6: 4.0e-5 and 5.3e-5 of the rate stated; capped, both ladders
are monotone, 7.9e-6 and 1.1e-5).
:func:`sink_bracket` climbs both ladders until the half-gap is within :data:`BRACKET_TOL`
of the rate (or :data:`MAX_RUNGS`; the grid grows at the rungs of :data:`GRID_STEPS`,
:func:`rung_intervals`): the rate is their midpoint and the stated ``sink_error`` half their
gap, a bracket of the limit while the lower ladder rises and the upper falls (checked at
every rung; where it fails the error is the whole gap plus the last steps).  No value is
extrapolated: the predicted ``o*`` only places the sinks (its error, measured against the
limit at rungs 5-9, is -0.22 to +0.27 widths over mu = 2-50, as large as the margins, so
closer ladders would not stay on their sides).  Linear damping in an even potential
(h-sink5, ``adaptive``): the rungs in orthonormal Hermite functions at a fraction of the
thermal speed (:data:`SINK_SCALE`, :func:`sink_scale`; Risken's pair at ``sqrt(kT)`` was
1e-6 off at rung 9 with 256 functions), each rung's truncation grown until
``1/sqrt 2`` of it moves the rate by :data:`HERMITE_TOL` at most, on points crowded at
the sink on four-fold scales (:func:`sink_grading`), and from rung 9 the ladders stop at
:data:`LOOSE_TOL`.  CDC Delta = 3, kT = 0.35 (relative: half-gap + grid + truncation, top
rung; h-sink4's in brackets): mu = 1 2.7e-7 + 1.3e-10 + 2.7e-8, rung 8 (4.2e-7, rung 8);
mu = 2 7.5e-7 + 2e-10 + 8e-9, rung 9 (1.9e-6, rung 9); mu = 5 8.7e-7 + 7.2e-8 + 6e-9,
rung 11 (5.2e-6); mu = 10 6.7e-7 + 9e-9 + 4.9e-8, rung 12 (6e-6); mu = 20 7.6e-7 + 4e-9 +
1.3e-8 (8e-6) and mu = 50 7.8e-7 + 1.3e-9 + 4e-10 (1.1e-5), rung 12; docs/noise.rst.
"""

from __future__ import annotations

import math

import numpy as np

from ._sink_pairs import PAIRED, paired_rates

__all__ = ["SINK_TOL", "BRACKET_TOL", "LOOSE_TOL", "OFFSET", "RAMP", "CAP", "TRACK",
           "MARGIN", "DRIFT", "WEIGHT", "MAX_RUNGS", "SINK_INTERVALS", "SINK_HERMITE",
           "SINK_SCALE", "LOW_SCALE", "RUNG_HERMITE", "MAX_HERMITE", "GRID_HERMITE",
           "HERMITE_TOL", "GRID_STEPS", "RUNG_INTERVALS", "GRID_CHECK", "GRID_FACTOR",
           "sink_scale", "sink_grading", "sink_rung",
           "step_zero", "ladder_offsets", "rung_intervals", "bracket_error", "sink_bracket",
           "absorbing_limit"]

#: the relative change between the two sinks above which the ladders run (and the default
#: target of :func:`sink_bracket`)
SINK_TOL = 1e-7
#: the bracket's half-width (relative) at which :func:`absorbing_limit` stops climbing (CDC
#: mu = 0.5 stops at the third rung with 2.9e-7, mu = 1 at the eighth with 2.6e-7; at 1e-7
#: mu = 1 climbs to the tenth rung, whose grid error is 1.5e-8 of the rate)
BRACKET_TOL = 5e-7
#: from the rung of the second grid step (:data:`GRID_STEPS`, rung 9; each rung then costs
#: about 2.5 times the last) the ladders of linear damping in an even potential stop at this
#: half-width (``adaptive``; with the top rungs' Hermite and grid errors, 1e-6 at most)
LOOSE_TOL = 9e-7
#: the rising ladder's centre past the next wells' bottoms (in widths, beyond ``j ln2/2``)
#: at the rungs before :data:`TRACK`, and its least centre after
OFFSET = 2.0
#: the falling ladder's centre at rung ``j < TRACK``: ``RAMP j`` widths (0 on the bottoms)
RAMP = 0.25
#: from rung ``CAP`` on the falling ladder's ramp stops at the measured critical offset
#: (:func:`ladder_offsets`): CDC mu = 20 and 50 (step zeros 0.91-1.15 and 1.0-1.26 at the
#: first rungs) came within 0.1 widths of it or past it at ``RAMP j`` by rung 5, and the
#: falling ladder rose at rung 6
CAP = 3
#: from rung ``TRACK`` on both ladders follow the critical offset (:func:`ladder_offsets`)
TRACK = 6
#: the rising ladder's distance past the predicted critical offset, in widths, from rung
#: :data:`TRACK` on (:func:`ladder_offsets`)
MARGIN = 0.1
#: the largest growth of the critical offset per rung that :func:`ladder_offsets` predicts
#: (measured: 0.03-0.16 at CDC mu = 1, 0.09-0.11 at mu = 5 and 10)
DRIFT = 0.2
#: the share of the points crowded at each sink's centre (:func:`._bases.cheb_centred`)
WEIGHT = 0.15
#: the rungs of each ladder at most (the width falls to ``w/2^(MAX_RUNGS - 1)``)
MAX_RUNGS = 15


def sink_rung(wells, kappa0: float, width: float, j: int, offset: float = OFFSET) -> tuple:
    """``(centres, kappa, w)`` of rung ``j``: width ``width/2^j``, strength ``kappa0 4^j``,
    centres ``offset + j ln(2)/2`` widths past the bottoms ``wells``."""
    w = width / 2**j
    kappa = kappa0 * 4.0**j
    c = (offset + j * math.log(2.0) / 2) * w
    return (wells[0] - c, wells[1] + c), kappa, w


def step_zero(a: tuple, b: tuple) -> float:
    """The offset at which the rates of two successive rungs are equal: the root of
    ``r_b(o) - r_a(o)``, each rung's rate ``r(o)`` the straight line through its two
    ladders' rates ``a = (o_low, o_high, r_low, r_high)`` (the rate is linear in the offset
    at each rung to 1e-4 of its change over 0.5 widths: CDC mu = 10; module docstring)."""
    def line(r):
        slope = (r[3] - r[2]) / (r[1] - r[0])
        return slope, r[2] - slope * r[0]

    (sa, ia), (sb, ib) = line(a), line(b)
    return (ib - ia) / (sa - sb)


def ladder_offsets(history) -> tuple:
    """``(o_low, o_high)``: the offsets of the rising and the falling ladder at the next
    rung ``J``, from ``history``, the ``(o_low, o_high, r_low, r_high)`` of the rungs so far.

    Before :data:`CAP`: :data:`OFFSET` and ``RAMP J``; from :data:`CAP` to :data:`TRACK`
    the falling ladder at ``RAMP J`` or ``s + k`` (below), whichever is smaller (at high
    friction the critical offset is near the ramp: CDC mu = 20 and 50).  Then, with ``s``
    the last zero of the step (:func:`step_zero` of rungs ``J - 2`` and ``J - 1``: the
    critical offset of rung ``J - 3`` where it grows linearly with the rung, closer to
    rung ``J``'s where it levels off; module docstring) and ``k`` its last growth (within
    ``[0, DRIFT]``): the falling ladder at ``s + k`` (short of rung ``J``'s critical
    offset ``s + 3 k`` by ``2 k``), the rising one at ``s + 3 k + MARGIN``, and at
    :data:`OFFSET` at least."""
    j = len(history)
    if j < CAP:
        return OFFSET, RAMP * j
    s_prev, s = (step_zero(a, b) for a, b in list(zip(history, history[1:]))[-2:])
    k = min(max(s - s_prev, 0.0), DRIFT)
    if j < TRACK:
        return OFFSET, min(RAMP * j, s + k)
    return max(OFFSET, s + 3 * k + MARGIN), s + k


def bracket_error(low, high) -> float:
    """The stated error of the midpoint of the ladders' top rungs: half their gap while
    ``low`` rises and ``high`` falls (to 8 ulps) with ``low[-1] <= high[-1]`` (the limit
    between them); else the whole gap plus both last steps."""
    gap = high[-1] - low[-1]
    ulps = 8 * np.finfo(float).eps  # rungs equal to rounding are no reversal
    monotone = (all(b > a - ulps * abs(a) for a, b in zip(low, low[1:]))
                and all(b < a + ulps * abs(a) for a, b in zip(high, high[1:])))
    if monotone and gap >= 0:
        return gap / 2
    steps = (abs(low[-1] - low[-2]) + abs(high[-1] - high[-2])) if len(low) > 1 else 0.0
    return abs(gap) + steps


def sink_bracket(solve, *, tol: float = SINK_TOL, max_rungs: int = MAX_RUNGS,
                 offsets=ladder_offsets, loose: tuple | None = None, pair=None) -> dict:
    """The rate of the perfectly absorbing sink between the rising ladder and the falling
    one (``solve(j, offset)``: the rate with the sinks of :func:`sink_rung`; the offsets of
    each rung ``offsets(history)``, :func:`ladder_offsets`), climbed until the half-gap is
    within ``tol`` of the rate (or, with ``loose = (tol2, j2)``, within ``tol2`` from rung
    ``j2`` on; ``pair(j, o_low, o_high)``, where given and not ``None``, both rates).

    Returns
    -------
    dict
        ``rate`` (the midpoint of the top rungs), ``sink_error`` (:func:`bracket_error`),
        ``rungs`` (the rising ladder's rates), ``upper`` (the falling ladder's) and
        ``offsets`` (each rung's ``(o_low, o_high)``).
    """
    low, high, history = [], [], []
    for j in range(max_rungs):
        o_low, o_high = offsets(history)
        both = None if pair is None else pair(j, o_low, o_high)
        lo, hi = both if both is not None else (solve(j, o_low), solve(j, o_high))
        low.append(lo)
        high.append(hi)
        history.append((o_low, o_high, low[-1], high[-1]))
        err = bracket_error(low, high)
        rate = abs(low[-1] + high[-1]) / 2
        if j >= 1 and err <= tol * rate:
            break
        if loose is not None and j >= loose[1] and err <= loose[0] * rate:
            break
    return dict(rate=(low[-1] + high[-1]) / 2, sink_error=err, rungs=tuple(low),
                upper=tuple(high), offsets=tuple(h[:2] for h in history))


#: the position intervals and Hermite functions of the sink ladder at least
#: (:func:`absorbing_limit`) in Risken's pair (linear damping in a potential that is not
#: even).  CDC Delta = 3, kT = 0.35, mu = 1: the rate of the seventh rung moves by 1.2e-9
#: from 200 to 280 intervals and by 1e-13 from 280 to 400; the sharper sinks need more
#: Hermite functions (the absorbing wall's layer at small speeds): at the sixth rung the
#: rate moves by 1.5e-8 from 90 to 128 functions, by 5.7e-9 from 128 to 180 and by 1.8e-9
#: from 180 to 256 (mu = 5: 1.5e-8, 1.7e-9, 1e-10); at the tenth (mu = 5) 256 functions
#: were still 1e-6 of the rate off
SINK_INTERVALS, SINK_HERMITE = 280, 256
#: linear damping in an even potential (:func:`absorbing_limit` with ``adaptive``): the
#: rungs in orthonormal Hermite functions of ``v/s`` at ``s = SINK_SCALE sqrt(kT)``
#: (:mod:`._folded`), half the thermal speed: the sharper sinks leave a layer at small
#: speeds (the absorbing wall's: the density of the particles coming back is nil at the
#: wall) whose width falls with the sink's, and functions at half the scale resolve twice
#: as fine while still reaching the Maxwellian's tail (it takes about 90 of them, the
#: ratio 0.6 per two orders).  CDC Delta = 3, kT = 0.35, mu = 5, rung 9 on 548
#: intervals: 182 functions give the rate to 3e-9 and 256 to 4e-10 (the pair at
#: ``sqrt(kT)``: 1e-6 off at 256, 2.9e-7 at 362); a third of the scale does not reach the
#: tail (4e-3 off at 128)
SINK_SCALE = 0.5
#: below the rung ``GRID_STEPS[1][0]`` (9) the rungs' scale is ``LOW_SCALE sqrt(kT)``: their
#: layer is wide, and at half the thermal speed the Maxwellian's own expansion needed 128
#: functions at mu = 10 (the rate moved by 1.6e-7 from 90 to 128 at the first rung; at
#: 0.6 sqrt(kT) 2e-12), where at rung 12 0.6 was 1.3e-6 off at 128 and 0.5 2e-7
LOW_SCALE = 0.6

#: the least Hermite functions of a rung (``adaptive``) below rung 9 (at :data:`LOW_SCALE`:
#: 90 give the rate to 2e-12 of 128 at the first rung, mu = 10) and from rung 9 (at
#: :data:`SINK_SCALE`: 128 were 1.6e-7 off at mu = 10), and the most
RUNG_HERMITE, MAX_HERMITE = (90, 182), 724
#: the Hermite functions of the top rungs' grid check (``adaptive``)
GRID_HERMITE = 128
#: a rung's truncation grows by ``sqrt 2`` while its rate moves by more than this (relative)
#: from ``1/sqrt 2`` of its functions (the smaller truncation costs no factorisation: the
#: elimination runs upward, order by order, :class:`._folded_orders.FoldedOrderLU`)
HERMITE_TOL = 5e-8
#: ``(rung, factor)``: from each of these rungs on the intervals are ``factor`` times the
#: first rung's (:func:`rung_intervals`; for linear damping the points crowd at the sink on
#: the scales of :func:`sink_grading`).  CDC kT = 0.35, orthonormal functions at
#: :data:`SINK_SCALE` (relative changes of the rate): rung 6 on 200 intervals 1.8e-9 from
#: 280 (mu = 5; 160 intervals 4.6e-8 at mu = 10), rung 7 4e-9 (mu = 50); mu = 5, rung 9 on
#: 280 9e-8 from 392 and 548; rung 10 280 5e-7, 392 1.2e-9 from 548; rung 12 392 2.3e-7
#: from 548; mu = 50, rung 11 280 5.4e-7, 392 4e-9 from 548; rung 12 392 2.3e-8; rung 13
#: 392 2.3e-7, 548 1.3e-9 from 768.  (Crowded at one scale, ``2.5 w_j``, rung 9 at mu = 5
#: needed 548 intervals for 6e-8.)
GRID_STEPS = ((7, 1.4), (9, 1.96), (12, 2.35), (14, 2.74))
#: the least intervals of the rungs of linear damping in an even potential (``adaptive``)
RUNG_INTERVALS = 200
#: the top rungs' grid check (``adaptive``): the rising ladder's top rung solved on
#: ``GRID_CHECK`` times the intervals with :data:`GRID_HERMITE` functions, against the same
#: functions on the rung's grid (whose factors the rung's solve left); the stated error is
#: ``GRID_FACTOR`` times the change, the error of the coarser grid where the finer one's is
#: at most a third of it (measured: about 50 times smaller per 1.25 times the intervals, CDC
#: mu = 5, rung 10).  The two top rungs differ only by their centres, 0.33 widths apart,
#: each on points crowded at its own centre on the same scales, and their grids' changes
#: agree (CDC Delta = 3, kT = 0.35, absolute: 1.4912e-9 both at mu = 5, 1.1360e-10 both at mu = 10,
#: 3.70e-12 and 3.69e-12 at mu = 50): the midpoint's is the rising rung's (both: 2.9 s of 15)
GRID_CHECK, GRID_FACTOR = 1.25, 1.5


def sink_scale(j: int) -> float:
    """The velocity scale of rung ``j``'s orthonormal functions, in units of ``sqrt(kT)``:
    :data:`LOW_SCALE` below rung 9, then :data:`SINK_SCALE`."""
    return LOW_SCALE if j < GRID_STEPS[1][0] else SINK_SCALE


def sink_grading(j: int) -> tuple:
    """``((width, weight), ...)``: the scales (in units of rung ``j``'s width ``w_j``) and
    shares of the points crowded at each sink's centre (:func:`._bases.cheb_centred`) for
    linear damping: ``2.5 w_j 4^i`` with the weights 0.25, 0.2, 0.15 and 0.1 after, while
    ``4^i`` stays within ``2^j/8`` (the widths up to about a third of the first sink's).
    Between the sink's width and the Milne layer's ``sqrt(kT)/gamma`` the density near an
    absorbing wall has structure on every scale: crowded on one scale (``2.5 w_j``, weight
    0.15, :data:`WEIGHT`), CDC mu = 5 at rung 9 on 392 intervals was 8.2e-7 of the rate
    off, on the four scales of this rule 1e-10 (rung 11: 4.7e-9; mu = 50, rung 12, five
    scales: 2.3e-8; relative to 548 or 768 intervals)."""
    out, i = [], 0
    while i == 0 or 4 ** i <= 2 ** j / 8:
        out.append((2.5 * 4 ** i, max(0.1, 0.25 - 0.05 * i)))
        i += 1
    return tuple(out)


def rung_intervals(n_cheb: int, j: int) -> int:
    """The position intervals of rung ``j`` (even): ``n_cheb`` times the factor of the last
    of :data:`GRID_STEPS` at or below ``j``."""
    factor = max([f for k, f in GRID_STEPS if j >= k], default=1.0)
    return 2 * int(round(n_cheb * factor / 2))


def _up(n: int) -> int:
    return 2 * int(round(n * math.sqrt(2) / 2))


def _down(n: int) -> int:
    return 2 * int(round(n / math.sqrt(2) / 2))


def absorbing_limit(out: dict, rung, least: tuple = (SINK_HERMITE, SINK_INTERVALS),
                    adaptive: bool = False, paired: bool = False) -> dict:
    """``out`` with the rate of the perfectly absorbing sink between the rising and the
    falling sink ladders (:func:`sink_bracket` to :data:`BRACKET_TOL`) and its errors:
    ``sink_error`` the bracket's half-width, ``chebyshev_error`` and ``truncation_error``
    the larger of the first sink's and the midpoint's change when both top rungs are solved
    on a finer grid or with fewer Hermite functions; ``hermite`` and ``chebyshev`` the top
    rungs' sizes; ``sink_ladder`` the rising ladder's rates, then the falling one's, and
    ``sink_offsets`` each rung's offsets.

    ``rung(j, offset, nc, nh)``: the rate of rung ``j`` on ``nc`` intervals with ``nh``
    Hermite functions.  ``adaptive=False`` (Risken's pair, nonlinear damping): at least
    ``least`` = (Hermite functions, intervals), the grid growing at :data:`GRID_STEPS`
    (:func:`rung_intervals`), the grid's change on 1.5 times the top rung's intervals and
    the truncation's with ``sqrt 2`` fewer functions.  ``adaptive=True`` (orthonormal
    functions at :func:`sink_scale`, folded, on :data:`RUNG_INTERVALS` at least): each
    rung from :data:`RUNG_HERMITE` functions (never fewer than the rung below) grown by
    ``sqrt 2`` while the rate moves by more than
    :data:`HERMITE_TOL` from ``1/sqrt 2`` of them (the truncation error: the top rungs'
    midpoint's change), and the grid's error :data:`GRID_FACTOR` times the rising top
    rung's change on :data:`GRID_CHECK` times its intervals at :data:`GRID_HERMITE`
    functions (the falling one's is the same: :data:`GRID_CHECK`).  ``paired`` (with
    ``adaptive``): from rung :data:`._sink_pairs.PAIRED` on both rates of a rung from one
    factorisation at the midpoint offset (:func:`._sink_pairs.paired_rates`; ``rung(j,
    offset, nc, nh, slope=True)`` gives ``(rate, slope)``, ``slope()`` the rate's
    derivative in the offset), whose grid change stands for both."""
    if not adaptive:
        nh = max(int(out["hermite"]), int(least[0]))
        nc = max(int(out["chebyshev"]) - 1, int(least[1]))
    else:  # the rungs' own points, crowded at the sink (the first sink's grid is not theirs)
        nh, nc = RUNG_HERMITE[0], RUNG_INTERVALS
    size = {"nh": nh}
    low_rates: dict = {}

    def solve(j, offset):
        n_c = rung_intervals(nc, j)
        if not adaptive:
            return rung(j, offset, n_c, nh)
        size["nh"] = max(size["nh"], RUNG_HERMITE[j >= GRID_STEPS[1][0]])
        while True:
            n = size["nh"]
            r, r_low = rung(j, offset, n_c, n), rung(j, offset, n_c, _down(n))
            if abs(r - r_low) <= HERMITE_TOL * abs(r) or _up(n) > MAX_HERMITE:
                low_rates[j, offset] = (n, r, r_low)
                return r
            size["nh"] = _up(n)

    def pair(j, o_low, o_high):  # from rung PAIRED on: one factorisation (._sink_pairs)
        if not (adaptive and paired) or j < PAIRED:
            return None
        out = paired_rates(rung, j, o_low, o_high, rung_intervals(nc, j),
                           max(size["nh"], RUNG_HERMITE[1]),
                           hermite=(HERMITE_TOL, _up, _down, MAX_HERMITE))
        if out is None:
            return None
        size["nh"], r, r_low = out
        for o, a, b in zip((o_low, o_high), r, r_low):
            low_rates[j, o] = (size["nh"], a, b)
        return r

    lim = sink_bracket(solve, tol=BRACKET_TOL, pair=pair,
                       loose=(LOOSE_TOL, GRID_STEPS[1][0]) if adaptive else None)
    low, high = lim["rungs"], lim["upper"]
    top = len(low) - 1
    nt = rung_intervals(nc, top)
    o_low, o_high = lim["offsets"][top]
    nh = size["nh"]

    if not adaptive:
        def moved(n_c, n_h):  # the midpoint's change with both top rungs on another grid
            lo, hi = rung(top, o_low, n_c, n_h), rung(top, o_high, n_c, n_h)
            return abs((lo + hi) / 2 - lim["rate"])

        cheb = moved(2 * int(round(1.5 * nt / 2)), nh)
        trunc = moved(nt, _down(nh))
    else:
        if low_rates[top, o_low][0] != nh:  # the rising rung before the truncation grew
            lo = rung(top, o_low, nt, nh)
            low = low[:-1] + (lo,)
            lim = dict(lim, rungs=low, rate=(lo + high[-1]) / 2,
                       sink_error=bracket_error(low, high))
        nl = _down(nh)  # the top rungs at 1/sqrt 2 of the functions (solve()'s, if at nh)
        lo_l, hi_l = (low_rates[top, o][2] if low_rates.get((top, o), (0,))[0] == nh
                      else rung(top, o, nt, nl) for o in (o_low, o_high))
        trunc = abs((lo_l + hi_l) / 2 - lim["rate"])
        n_fine, nb = 2 * int(round(GRID_CHECK * nt / 2)), GRID_HERMITE
        o_grid = o_low if top < PAIRED else (o_low + o_high) / 2  # the factors kept
        here = rung(top, o_grid, nt, nb)  # one rung stands for both
        cheb = GRID_FACTOR * abs(rung(top, o_grid, n_fine, nb) - here)  # (GRID_CHECK)
    return {**out, "rate": lim["rate"], "sink_error": lim["sink_error"],
            "chebyshev_error": max(out["chebyshev_error"], cheb),
            "truncation_error": max(out["truncation_error"], trunc),
            "sink_ladder": low + high, "sink_offsets": lim["offsets"], "hermite": nh,
            "chebyshev": nt + 1}
