"""The setup of the escape problem of :mod:`.escape`: the temperature of a linear damping
(:func:`kT_gamma`), the Hermite truncations of a ladder (:func:`hermite_ladder`, also the
stationary ladder's rule) and the range, the next wells and the first sink
(:func:`escape_problem`)."""

from __future__ import annotations

import math

import numpy as np

from ._model import next_wells
from .kramers import _linear_temperature
from ._model import velocity_terms

__all__ = ["kT_gamma", "hermite_ladder", "escape_problem"]


def kT_gamma(split, D: float):
    """``(kT, gamma)`` for linear damping ``mu h = -gamma x'`` (``kT = D/gamma``), else
    ``(None, None)``."""
    kT = _linear_temperature(velocity_terms(split), D)
    return (None, None) if kT is None else (kT, D / kT)


def hermite_ladder(start: int, stop: int) -> list:
    """Hermite truncations ``start * 2^(k/2)`` (even, rounded) up to ``stop``."""
    out, k = [], 0
    while True:
        n = 2 * int(round(start * 2 ** (k / 2) / 2))
        if n > stop:
            return out
        out.append(n)
        k += 1


def escape_problem(split, D: float, saddles: tuple, margin: float | None = None) -> tuple:
    """``(sigma, wells, half, kappa0, width)``: the Hermite scale (``sqrt(kT)`` for linear
    damping, else ``sqrt(D/mu)``), the next wells' bottoms, the half-width of the range
    (``margin`` past the farther bottom, default half the larger saddle-to-bottom
    distance), and the sink's strength and width (:func:`._sink_pairs.tanh_sink`): absorbed
    within a tenth of the saddle-to-bottom distance at the speed of the bottom."""
    xl, xr = saddles
    kT = kT_gamma(split, D)[0]
    sigma = math.sqrt(kT if kT is not None else D / float(split.mu))
    g, _, G = split.numpy_functions()[:3]
    wells = next_wells(g, (xl, xr))
    gap = min(wells[1] - xr, xl - wells[0])
    drop = min(float(G(np.array(s))) - float(G(np.array(w))) for s, w in zip((xl, xr), wells))
    kappa0 = 10 * math.sqrt(2 * max(drop, 0.0)) / gap + 1.0
    half = max(-wells[0], wells[1]) + (0.5 * max(wells[1] - xr, xl - wells[0])
                                       if margin is None else float(margin))
    return sigma, wells, half, kappa0, 0.1 * gap
