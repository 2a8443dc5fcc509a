"""What the sampled algebras share: values on a grid with their ring operations.

:class:`Samples` is the base of every sampled series: the grid algebra's
:class:`kbm.algebra.grid.SampledSeries` (Chebyshev points in the amplitude: the numeric
backends of one degree of freedom, forced or not) and the jets of
:class:`kbm.algebra.coupled_jets.JetSeries` (Taylor coefficients at given amplitudes: ``N``
modes, forced or not, and one mode at a batch of amplitudes for :func:`kbm.derive_values`).
"""

from __future__ import annotations

import numpy as np

__all__ = ["Samples"]


class Samples:
    """Values on a grid, ``values is None`` the exact zero, with the ring operations that act
    value by value: the base of every sampled series (the forced grid's
    :class:`kbm.algebra.grid.SampledSeries`, the jets'
    :class:`kbm.algebra.coupled_jets.JetSeries`).  Each gives its product; one that carries
    more than its values (a degree, a cap) gives :meth:`_new` and, when a sum is not the sum
    of the values, :meth:`_plus`."""

    __slots__ = ("values",)

    def __init__(self, values: np.ndarray | None):
        self.values = values

    def is_zero(self) -> bool:
        return self.values is None

    def _new(self, values: np.ndarray | None):
        """A series of the same kind with other values."""
        return type(self)(values)

    def _plus(self, other):
        """The sum of two non-zero series."""
        return self._new(self.values + other.values)

    def __add__(self, other):
        if other.values is None:
            return self
        if self.values is None:
            return other
        return self._plus(other)

    def __neg__(self):
        return self if self.values is None else self._new(-self.values)

    def __sub__(self, other):
        return self + (-other)

    def scale_q(self, q):
        return self if self.values is None else self._new(self.values * float(q))
