"""The escape rate in the limit of a perfectly absorbing sink (:func:`sink_limit`, run by
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

The ladder: rung ``j`` has the width ``w_j = w/2^j``, the strength ``kappa_j = kappa 4^j``
(the optical depth doubles) and the centre :data:`OFFSET` ``+ ln(2^j)/2`` widths past
``x_w`` (the line where absorption happens then stays near ``x_w``: the rates rise toward
the limit, the differences shrinking by 2.4 to 2.9 per rung at mu = 1 to 5), on points
crowded at the centres (:data:`WEIGHT`).  The limit is Aitken's ``Delta^2`` extrapolation
of the last three rungs; the ladder stops when two successive extrapolations agree to
``tol`` of the rate, and their difference is the stated ``sink_error``.  The independent
check (tests/test_fokker_planck_sink.py): the ladder of the sinks centred on ``x_w``
(``offset = 0``), whose rates fall toward the limit from above.
"""

from __future__ import annotations

import math

__all__ = ["SINK_TOL", "OFFSET", "WEIGHT", "MAX_RUNGS", "sink_rung", "aitken", "sink_limit"]

#: the relative change between the two sinks above which the ladder runs (and its target)
SINK_TOL = 1e-7
#: the first rung's centre past the next wells' bottoms, in sink widths
OFFSET = 2.0
#: the share of the points crowded at each sink's centre (:func:`._bases.cheb_centred`)
WEIGHT = 0.15
#: the rungs at most (the width falls to ``w/2^(MAX_RUNGS - 1)``)
MAX_RUNGS = 7


def sink_rung(wells, kappa0: float, width: float, j: int, offset: float = OFFSET) -> tuple:
    """``(centres, kappa, w)`` of rung ``j``: width ``width/2^j``, strength ``kappa0 4^j``,
    centres ``offset + j ln(2)/2`` widths past the bottoms ``wells``."""
    w = width / 2**j
    kappa = kappa0 * 4.0**j
    c = (offset + j * math.log(2.0) / 2) * w
    return (wells[0] - c, wells[1] + c), kappa, w


def aitken(r0: float, r1: float, r2: float) -> float:
    """Aitken's ``Delta^2`` limit of ``r0, r1, r2``; ``r2`` when the differences do not
    shrink geometrically with one sign (no extrapolation then)."""
    d1, d2 = r1 - r0, r2 - r1
    if d1 == 0 or d2 == 0 or d2 / d1 <= 0 or d2 / d1 >= 1:
        return r2
    return r2 + d2 * d2 / (d1 - d2)


def sink_limit(solve, *, tol: float = SINK_TOL, max_rungs: int = MAX_RUNGS,
               first: int = 4) -> dict:
    """The rate of the perfectly absorbing sink from the ladder ``solve(j)`` (the rate with
    the sink of :func:`sink_rung` ``j``).

    Returns
    -------
    dict
        ``rate`` (the last extrapolation), ``sink_error`` (its change from the one before),
        ``rungs`` (the rates) and ``limits`` (the extrapolations of each three).
    """
    rates, limits = [], []
    for j in range(max_rungs):
        rates.append(solve(j))
        if j >= 2:
            limits.append(aitken(*rates[-3:]))
        if (j + 1 >= first and len(limits) >= 2
                and abs(limits[-1] - limits[-2]) <= tol * abs(limits[-1])):
            break
    err = abs(limits[-1] - limits[-2]) if len(limits) >= 2 else abs(rates[-1] - rates[-2])
    return dict(rate=limits[-1] if limits else rates[-1], sink_error=err,
                rungs=tuple(rates), limits=tuple(limits))
