"""Zeros of the conservative force ``g`` (the equilibria) on a bracket found by doubling."""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

import numpy as np

from kbm.slowflow.roots import brentq  # scipy.optimize.brentq's floats, no scipy (issue 39)

if TYPE_CHECKING:
    from kbm.model.conservative import ConservativeSplit


def _bracket(g: Callable, split: "ConservativeSplit") -> float:
    """Smallest ``L = 2**j`` with ``g > 0`` on ``[L, 4L]`` and ``g < 0`` on ``[-4L, -L]``
    (4001 samples each): past it ``g`` pushes back towards the wells."""
    L = 1.0
    for _ in range(60):
        far = np.linspace(L, 4 * L, 4001)
        if np.all(g(far) > 0) and np.all(g(-far) < 0):
            return L
        L *= 2.0
    from kbm.model.conservative import NotConfiningError

    raise NotConfiningError(f"g(x) = {split.g} keeps changing sign out to |x| = {L:.3g}: "
                            "the potential does not confine")


def _zeros(g: Callable, L: float) -> list[tuple[float, int]]:
    """Sign changes of ``g`` on ``[-L, L]`` (grid doubled until their count is stable,
    refined by Brent's method) as ``(x, +1 center / -1 saddle)``; tangential zeros,
    where ``g`` does not change sign, are not found."""
    n = 4096
    prev = None
    while True:
        xs = np.linspace(-L, L, n + 1)
        gs = g(xs)
        idx = np.nonzero(np.sign(gs[:-1]) * np.sign(gs[1:]) < 0)[0]
        exact = np.nonzero(gs == 0)[0]
        count = len(idx) + len(exact)
        if count == prev or n >= 1 << 22:
            break
        prev, n = count, 2 * n
    out = []
    for i in idx:
        z = brentq(lambda s: float(g(np.array(s))), xs[i], xs[i + 1], xtol=1e-15, rtol=1e-15)
        out.append((z, 1 if gs[i + 1] > gs[i] else -1))
    for i in exact:
        if 0 < i < n:
            out.append((xs[i], 1 if gs[i + 1] > gs[i - 1] else -1))
    return sorted(out)
