"""The escape's sink (:func:`tanh_sink`), its change as it moves out
(:func:`tanh_sink_slope`), and the two sinks of a rung of the sink ladders
(:func:`._sink.absorbing_limit` with ``adaptive`` and ``paired``) from one factorisation:
the rates at the rising and the falling ladder's offsets from the rate and its slope at
their midpoint (:func:`paired_rates`).

At each rung the rate is a straight line in the sink's offset (:mod:`._sink`), ``r_j(o) = r
- a w_j (o - o*_j)``, and it depends on the offset through ``o w_j`` only, so its curvature
falls like ``w_j^2``, four times per rung.  The slope at the midpoint ``o_m`` of the two
offsets is the first-order change of the slowest decay rate as the sinks move out
(:meth:`._folded.FoldedRungs.slope`: the left and the right slowest modes on the one
factorisation, the left one by Arnoldi on the transposed sweeps), and ``r(o_m) +- r'(o_m)
(o_high - o_low)/2`` are the two rungs' rates, their midpoint up to ``r'' (o_high -
o_low)^2/8`` and their half-gap up to ``r''' (o_high - o_low)^3/48``, and the grids'
difference (each rung on points crowded at its own centre, here both on the midpoint's).
CDC Delta = 3, kT = 0.35, mu = 5 (relative to the rate; the two sides each solved on its
own grid against the pair): rung 9 (182 functions, 392 intervals, offsets 2.12 and 1.80)
sides 3.4e-10 and 7.4e-11, the midpoint 2.1e-10; rung 11 (364, 392, 2.36 and 2.03) sides
+-3.8e-8 (the stated grid error there is 7.2e-8), the midpoint 1.3e-11; at rung 6 (200
intervals, offsets 2 and 1.25) the midpoint is 6.9e-8 off and at rung 0 (offsets 2 and 0)
2.1e-3; at rungs 7 and 8 (280 intervals) 5.7e-9 and 8.3e-10, but there the left mode's
Arnoldi (0.19 and 0.27 s) costs what the second factorisation does.  So the pairs start at
:data:`PAIRED`, where each rung's two factorisations are dearest (rung 9's grid step), and
the ladders that stop before it (mu <= 1) keep their bits.  One factorisation and two
Arnoldi runs (about ten solves) instead of two factorisations: at rung 11 1.45 + 0.3 s
against 2.9 s.
"""

from __future__ import annotations

import numpy as np

__all__ = ["PAIRED", "tanh_sink", "tanh_sink_slope", "paired_rates"]

#: the first rung whose two sinks are solved as a pair (:func:`paired_rates`): the grid
#: step of rung 9 (``._sink.GRID_STEPS``), where the rungs' factorisations grow dearest
PAIRED = 9


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


def tanh_sink_slope(xs, centres, kappa: float, width: float) -> np.ndarray:
    """``d kappa/d o`` of :func:`._sink_pairs.tanh_sink` at the points ``xs`` as the centres move
    out by ``width`` per unit offset ``o`` (``._sink.sink_rung``): ``-(kappa/2)
    [sech^2((|x| - c)/w) + 9 sech^2((|x| - c - 2.5 w)/w)]``."""
    edge = np.where(xs > 0, centres[1], -centres[0])
    r = np.abs(xs)
    near, far = np.tanh((r - edge) / width), np.tanh((r - edge - 2.5 * width) / width)
    return -0.5 * kappa * ((1 - near * near) + 9 * (1 - far * far))


def paired_rates(rung, j: int, o_low: float, o_high: float, nc: int, nh: int,
                 hermite: tuple):
    """``(n, (r(o_low), r(o_high)), (r_n(o_low), r_n(o_high)))``: the rates of rung ``j``
    on ``nc`` intervals at the two offsets from the rate and the slope at their midpoint
    (module docstring) with ``n`` Hermite functions, and with ``1/sqrt 2`` of them (the
    same slope: it moved by 1e-13 of the rate from 258 to 364 functions at CDC mu = 5,
    rung 11), ``n`` grown from ``nh`` as the sinks' own rungs grow (``hermite = (tol, up,
    down, most)``: by ``up(n)`` while the rate moves by more than ``tol`` from
    ``down(n)`` functions, up to ``most``; :func:`._sink.absorbing_limit`).
    ``rung(j, offset, nc, n, slope=True)`` gives ``(rate, slope)``, ``slope()`` the
    rate's derivative in the offset at the last solve (or ``None``: then this returns
    ``None`` and the caller solves both sinks)."""
    tol, up, down, most = hermite
    o_mid, n = 0.5 * (o_low + o_high), int(nh)
    while True:  # the smaller truncation first: the slope is the larger one's
        r_low = rung(j, o_mid, nc, down(n))
        r, slope = rung(j, o_mid, nc, n, slope=True)
        if abs(r - r_low) <= tol * abs(r) or up(n) > most:
            break
        n = up(n)
    d = slope()
    if d is None or not np.isfinite(d):
        return None
    shift = (d * (o_low - o_mid), d * (o_high - o_mid))
    return n, tuple(r + a for a in shift), tuple(r_low + a for a in shift)
