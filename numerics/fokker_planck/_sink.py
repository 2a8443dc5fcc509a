"""The escape rate in the limit of a perfectly absorbing sink (:func:`sink_bracket`, run by
:func:`.escape.kramers_escape` where the two sinks of ``sink_error`` disagree by more than
:data:`SINK_TOL` of the rate).

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
(the optical depth doubles).  Centred :data:`OFFSET` ``+ ln(2^j)/2`` widths past ``x_w``,
the line where absorption happens stays just past ``x_w`` and the rates **rise** toward the
limit; centred ``ln(2^j)/2`` widths past ``x_w`` (offset 0) absorption happens before it
and the rates **fall** toward the limit (the differences shrink by 2.4 to 2.9 per rung at mu = 1 to 5, on points
crowded at the centres, :data:`WEIGHT`).  :func:`sink_bracket` climbs both ladders until
the two top rungs are within ``2 tol`` of the rate: the rate is their midpoint and the
stated ``sink_error`` half their gap, a bracket of the limit while the lower ladder rises and
the upper falls (checked at every rung; where it fails the error is the whole gap plus the
last steps).  No value is extrapolated.
"""

from __future__ import annotations

import math

__all__ = ["SINK_TOL", "OFFSET", "WEIGHT", "MAX_RUNGS", "sink_rung", "sink_bracket"]

#: the relative change between the two sinks above which the ladders run (and the target of
#: the bracket's half-width)
SINK_TOL = 1e-7
#: the rising ladder's first centre past the next wells' bottoms, in sink widths
OFFSET = 2.0
#: the share of the points crowded at each sink's centre (:func:`._bases.cheb_centred`)
WEIGHT = 0.15
#: the rungs of each ladder at most (the width falls to ``w/2^(MAX_RUNGS - 1)``)
MAX_RUNGS = 7


def sink_rung(wells, kappa0: float, width: float, j: int, offset: float = OFFSET) -> tuple:
    """``(centres, kappa, w)`` of rung ``j``: width ``width/2^j``, strength ``kappa0 4^j``,
    centres ``offset + j ln(2)/2`` widths past the bottoms ``wells`` (``offset = 0``: the
    falling ladder)."""
    w = width / 2**j
    kappa = kappa0 * 4.0**j
    c = (offset + j * math.log(2.0) / 2) * w
    return (wells[0] - c, wells[1] + c), kappa, w


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
    OFFSET)`` and the falling one ``solve(j, 0.0)`` (the rates with the sinks of
    :func:`sink_rung`).

    Returns
    -------
    dict
        ``rate`` (the midpoint of the top rungs), ``sink_error`` (:func:`bracket_error`),
        ``rungs`` (the rising ladder's rates) and ``upper`` (the falling ladder's).
    """
    low, high = [], []
    for j in range(max_rungs):
        low.append(solve(j, OFFSET))
        high.append(solve(j, 0.0))
        err = bracket_error(low, high)
        if j >= 1 and err <= tol * abs(low[-1] + high[-1]) / 2:
            break
    return dict(rate=(low[-1] + high[-1]) / 2, sink_error=err, rungs=tuple(low),
                upper=tuple(high))
