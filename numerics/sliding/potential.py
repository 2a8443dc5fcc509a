"""The sliding potential of the paper's eq. (4) and the quasi-static slip energy.

``U(x, L) = Omega^2 (x - L)^2 / 2 - (Delta/k) cos(k x)``, ``k = 2 pi/lambda``, with
``L = v t`` the stage position.  A stick state is a minimum of ``U(., L)``; it
disappears at a saddle-node point where ``dU/dx = 0 = d^2U/dx^2``:
``cos(k x0) = -Omega^2/(Delta k)`` and ``L0 = x0 + Delta sin(k x0)/Omega^2``.
This exists only when ``Delta k > Omega^2`` (otherwise ``U`` has a single
minimum for every ``L``: smooth sliding, no stick-slip).  In a quasi-static
slip the slider jumps from ``x0`` to a minimum ``x1`` of ``U(., L0)`` further on
and the energy ``Delta W = U(x0, L0) - U(x1, L0)`` is dissipated.

References
----------
M. D'Acunto, eq. (4) and Section 2; the Prandtl-Tomlinson model (Tomlinson 1929).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from kbm.errors import ParameterError

__all__ = ["potential", "SaddleNode", "saddle_node", "slip_energy"]


def _check(Delta: float, lam: float, Omega: float) -> float:
    for name, val in (("Delta", Delta), ("lam", lam), ("Omega", Omega)):
        if not math.isfinite(val):
            raise ParameterError(f"{name} must be finite, got {val}")
    if lam <= 0:
        raise ParameterError(f"the period of the potential lam must be > 0, got {lam}")
    if Omega <= 0:
        raise ParameterError(f"the spring frequency Omega must be > 0, got {Omega}")
    if Delta < 0:
        raise ParameterError(f"the strength of the potential Delta must be >= 0, got {Delta}")
    return 2 * math.pi / lam


def potential(x, L, *, Delta: float, lam: float = 1.0, Omega: float = 1.0):
    """``U(x, L) = Omega^2 (x - L)^2/2 - (Delta lam/2 pi) cos(2 pi x/lam)`` (paper eq. 4)."""
    k = _check(Delta, lam, Omega)
    x = np.asarray(x, dtype=float)
    return Omega**2 * (x - L)**2 / 2 - Delta / k * np.cos(k * x)


@dataclass(frozen=True, eq=False)
class SaddleNode:
    """The loss of the stick state and the quasi-static slip that follows.

    Attributes
    ----------
    x0, L0
        Slider and stage position where the stick state disappears.
    static_force
        Spring force ``Omega^2 (L0 - x0) = Delta sin(k x0)`` at that moment: the
        quasi-static static friction (slightly less than ``Delta``).
    minima
        The next minima ``x1, x2, ...`` of ``U(., L0)`` after ``x0`` (one per well).
    delta_W
        ``U(x0, L0) - U(x_j, L0)`` for each of those minima; ``delta_W[0]`` is the
        one-well slip energy of the paper.
    """

    x0: float
    L0: float
    static_force: float
    minima: tuple[float, ...]
    delta_W: tuple[float, ...]


def saddle_node(Delta: float, lam: float = 1.0, Omega: float = 1.0, *,
                n_wells: int = 4) -> SaddleNode | None:
    """The saddle-node point of eq. (4) and the slip energies to the next ``n_wells`` minima.

    Returns ``None`` when ``Delta k <= Omega^2`` (no stick-slip).

    Examples
    --------
    >>> s = saddle_node(3.0, 1.0, 1.0)
    >>> round(s.static_force, 6), round(s.delta_W[0], 6)
    (2.995775, 2.583491)
    """
    k = _check(Delta, lam, Omega)
    r = Omega**2 / (Delta * k) if Delta > 0 else math.inf
    if r >= 1:
        return None
    x0 = math.acos(-r) / k  # on the rising flank of the well at 0
    L0 = x0 + Delta * math.sin(k * x0) / Omega**2
    force = Omega**2 * (L0 - x0)

    def dU(x):
        return Omega**2 * (x - L0) + Delta * math.sin(k * x)

    minima = []
    lo = x0 + 1e-9 * lam
    step = lam / 64
    x = lo
    while len(minima) < n_wells and x < x0 + (n_wells + 2) * lam + abs(L0):
        a, b = x, x + step
        fa, fb = dU(a), dU(b)
        if fa < 0 <= fb:  # dU goes up through zero: a minimum of U
            minima.append(brentq(dU, a, b, xtol=1e-15, rtol=1e-15))
        x = b
    U0 = float(potential(x0, L0, Delta=Delta, lam=lam, Omega=Omega))
    dW = tuple(U0 - float(potential(m, L0, Delta=Delta, lam=lam, Omega=Omega)) for m in minima)
    return SaddleNode(x0=x0, L0=L0, static_force=force, minima=tuple(minima), delta_W=dW)


def slip_energy(Delta: float, lam: float = 1.0, Omega: float = 1.0) -> float | None:
    """``Delta W`` of a one-well quasi-static slip (``None`` when there is no stick-slip)."""
    s = saddle_node(Delta, lam, Omega, n_wells=1)
    return None if s is None else s.delta_W[0]
