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
(the optical depth doubles), so the line where absorption happens lies ``(o - o_c) w_j``
past ``x_w`` for a centre ``o + j ln(2)/2`` widths past it (``o_c`` about half the log of
the first optical depth).  The rates of a ladder then approach the limit like ``(o - o_c)
w_j`` plus terms in ``w_j^2``: from below if ``o`` is beyond the critical offset, from
above if it is short of it.  The rising ladder is centred :data:`OFFSET` widths out; the
falling one starts on the bottoms (offset 0) and moves out by :data:`RAMP` per rung to
:data:`UPPER` (short of the critical offset, which grows from about 1.4 at the fifth rung to
1.75 at the ninth at mu = 5; at a fixed offset 1.5 the rates rise until the seventh rung
there, at offset 0 they fall only 1.7 times per rung, where the gap
halves).  The gap between the ladders is ``(OFFSET - UPPER) w_j`` in line position: a
fifth of the gap of offsets 2 and 0.  :func:`sink_bracket` climbs both ladders until the
half-gap is within :data:`BRACKET_TOL` of the rate (or :data:`MAX_RUNGS`; past
:data:`FINE_RUNG` the grid grows with the rung, :func:`rung_intervals`): the rate is their
midpoint and the stated ``sink_error`` half their gap, a bracket of the limit while the
lower ladder rises and the upper falls (checked at every rung; where it fails the error is
the whole gap plus the last steps).  CDC Delta = 3, kT = 0.35: half-gaps 2.8e-7 (mu = 1, eighth
rung), 9.0e-7 (mu = 2, tenth) and 4.3e-6 (mu = 5, tenth) of the rate, where offsets 2 and 0
left 2.8e-6, 3.5e-5 and 1.7e-4 at the seventh.  At mu = 10 the critical offset
is below 1.6 from the seventh rung on: the falling ladder is not monotone, and the stated
error is the whole gap plus the last steps (2.6e-5 of the rate; docs/noise.rst).  No value
is extrapolated.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["SINK_TOL", "BRACKET_TOL", "OFFSET", "UPPER", "RAMP", "WEIGHT", "MAX_RUNGS",
           "SINK_INTERVALS", "SINK_HERMITE", "FINE_RUNG", "GRID_GROWTH", "tanh_sink",
           "sink_rung", "falling_offset", "rung_intervals", "bracket_error", "sink_bracket",
           "absorbing_limit"]

#: the relative change between the two sinks above which the ladders run (and the default
#: target of :func:`sink_bracket`)
SINK_TOL = 1e-7
#: the bracket's half-width (relative) at which :func:`absorbing_limit` stops climbing (CDC
#: mu = 0.5 stops at the third rung with 2.9e-7, mu = 1 at the eighth with 2.8e-7; at 1e-7
#: mu = 1 climbs to the tenth rung, whose grid error is 1.5e-8 of the rate)
BRACKET_TOL = 5e-7
#: the rising ladder's first centre past the next wells' bottoms, in sink widths
OFFSET = 2.0
#: the falling ladder's centre past the bottoms (in widths, beyond ``j ln2/2``) from rung
#: ``UPPER/RAMP`` on, reached by ``RAMP`` per rung from 0 (:func:`falling_offset`)
UPPER, RAMP = 1.6, 0.25
#: the share of the points crowded at each sink's centre (:func:`._bases.cheb_centred`)
WEIGHT = 0.15
#: the rungs of each ladder at most (the width falls to ``w/2^(MAX_RUNGS - 1)``)
MAX_RUNGS = 10


def sink_rung(wells, kappa0: float, width: float, j: int, offset: float = OFFSET) -> tuple:
    """``(centres, kappa, w)`` of rung ``j``: width ``width/2^j``, strength ``kappa0 4^j``,
    centres ``offset + j ln(2)/2`` widths past the bottoms ``wells`` (:data:`OFFSET`: the
    rising ladder; :func:`falling_offset`: the falling one)."""
    w = width / 2**j
    kappa = kappa0 * 4.0**j
    c = (offset + j * math.log(2.0) / 2) * w
    return (wells[0] - c, wells[1] + c), kappa, w


def falling_offset(j: int) -> float:
    """The falling ladder's offset at rung ``j``: ``min(UPPER, RAMP j)`` widths."""
    return min(UPPER, RAMP * j)


def bracket_error(low, high) -> float:
    """The stated error of the midpoint of the ladders' top rungs: half their gap while
    ``low`` rises and ``high`` falls with ``low[-1] <= high[-1]`` (the limit between them);
    else the whole gap plus both last steps."""
    gap = high[-1] - low[-1]
    monotone = (all(b > a for a, b in zip(low, low[1:]))
                and all(b < a for a, b in zip(high, high[1:])))
    if monotone and gap >= 0:
        return gap / 2
    steps = (abs(low[-1] - low[-2]) + abs(high[-1] - high[-2])) if len(low) > 1 else 0.0
    return abs(gap) + steps


def sink_bracket(solve, *, tol: float = SINK_TOL, max_rungs: int = MAX_RUNGS) -> dict:
    """The rate of the perfectly absorbing sink between the rising ladder ``solve(j,
    OFFSET)`` and the falling one ``solve(j, falling_offset(j))`` (the rates with the sinks
    of :func:`sink_rung`), climbed until the half-gap is within ``tol`` of the rate.

    Returns
    -------
    dict
        ``rate`` (the midpoint of the top rungs), ``sink_error`` (:func:`bracket_error`),
        ``rungs`` (the rising ladder's rates) and ``upper`` (the falling ladder's).
    """
    low, high = [], []
    for j in range(max_rungs):
        low.append(solve(j, OFFSET))
        high.append(solve(j, falling_offset(j)))
        err = bracket_error(low, high)
        if j >= 1 and err <= tol * abs(low[-1] + high[-1]) / 2:
            break
    return dict(rate=(low[-1] + high[-1]) / 2, sink_error=err, rungs=tuple(low),
                upper=tuple(high))


def tanh_sink(xs, wells, kappa0: float, width: float) -> np.ndarray:
    """The sink at the points ``xs``: ``kappa0 [1 + tanh((|x| - |x_w|)/width)]/2``, and nine
    times as strong from ``2.5 width`` past the bottom ``|x_w|`` (the same profile): what
    gets past the bottom is gone long before the end of the range (``5 width`` past it by
    default), where the pinned rows ``c_n(+-L) = 0`` are no boundary condition of the
    Kramers equation (with the first stage alone the rate converged like ``1/n_cheb`` and
    moved by 1e-5 with the range at mu = 1; docs/noise.rst)."""
    edge = np.where(xs > 0, wells[1], -wells[0])
    far = edge + 2.5 * width
    r = np.abs(xs)
    return kappa0 * 0.5 * ((1 + np.tanh((r - edge) / width))
                           + 9 * (1 + np.tanh((r - far) / width)))


#: the position intervals and Hermite functions of the sink ladder at least
#: (:func:`absorbing_limit`).  CDC Delta = 3, kT = 0.35, mu = 1: the rate of the seventh rung
#: moves by 1.2e-9 from 200 to 280 intervals and by 1e-13 from 280 to 400; the sharper
#: sinks need more Hermite functions (the absorbing wall's layer at small speeds): at the
#: sixth rung the rate moves by 1.5e-8 from 90 to 128 functions, by 5.7e-9 from 128 to 180
#: and by 1.8e-9 from 180 to 256 (mu = 5: 1.5e-8, 1.7e-9, 1e-10)
SINK_INTERVALS, SINK_HERMITE = 280, 256
#: past rung ``FINE_RUNG`` the intervals grow by ``GRID_GROWTH`` per rung (the crowded points
#: follow the width, but the sharper sinks need more of them): CDC mu = 2, rung j = 8, 280
#: and 400 intervals 8.5e-9 apart; j = 9, 400 and 560 1.1e-8; j = 10, 400 and 560 9e-8
FINE_RUNG, GRID_GROWTH = 8, 1.4


def rung_intervals(n_cheb: int, j: int) -> int:
    """The position intervals of rung ``j`` (even): ``n_cheb`` up to :data:`FINE_RUNG`, then
    :data:`GRID_GROWTH` times more per rung."""
    return 2 * int(round(n_cheb * GRID_GROWTH ** max(0, j - FINE_RUNG) / 2))


def absorbing_limit(out: dict, rung) -> dict:
    """``out`` with the rate of the perfectly absorbing sink between the rising and the
    falling sink ladders (:func:`sink_bracket` to :data:`BRACKET_TOL`) at the ladders' Hermite
    truncation and grid (at least :data:`SINK_HERMITE` and :data:`SINK_INTERVALS`, the grid
    growing past :data:`FINE_RUNG`, :func:`rung_intervals`), and its errors:
    ``sink_error`` the bracket's half-width, ``chebyshev_error`` and ``truncation_error``
    the larger of the first sink's and the midpoint's change when both top rungs are solved
    on 1.5 times the top rung's intervals, or with the Hermite truncation below (``sqrt 2``
    fewer); ``hermite`` and ``chebyshev`` the top rungs' sizes; ``sink_ladder`` the rising
    ladder's rates, then the falling one's."""
    nh = max(int(out["hermite"]), SINK_HERMITE)
    nc = max(int(out["chebyshev"]) - 1, SINK_INTERVALS)
    lim = sink_bracket(lambda j, offset: rung(j, offset, rung_intervals(nc, j), nh),
                       tol=BRACKET_TOL)
    low, high = lim["rungs"], lim["upper"]
    top = len(low) - 1
    nt = rung_intervals(nc, top)

    def moved(n_c, n_h):  # the midpoint's change with both top rungs on another grid
        lo, hi = rung(top, OFFSET, n_c, n_h), rung(top, falling_offset(top), n_c, n_h)
        return abs((lo + hi) / 2 - lim["rate"])

    cheb = moved(2 * int(round(1.5 * nt / 2)), nh)
    trunc = moved(nt, 2 * int(round(nh / math.sqrt(2) / 2)))
    return {**out, "rate": lim["rate"], "sink_error": lim["sink_error"],
            "chebyshev_error": max(out["chebyshev_error"], cheb),
            "truncation_error": max(out["truncation_error"], trunc),
            "sink_ladder": low + high, "hermite": nh, "chebyshev": nt + 1}

