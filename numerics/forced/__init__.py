"""Floor 3 of :mod:`numerics` (after :mod:`numerics.cycles`): true periodic responses of
forced oscillators.

- :mod:`numerics.forced.system`: the forced model compiled once, ``sigma`` free;
- :mod:`numerics.forced.shooting`: the response of fixed period ``2 pi p/nu`` by
  shooting, its Floquet multipliers and amplitudes;
- :mod:`numerics.forced.response`: the frequency-response curve by pseudo-arclength
  continuation in ``sigma`` (stable and unstable responses, folds);
- :mod:`numerics.forced.convergence`: the error of the order-``N`` prediction against
  ``mu`` with fitted slopes;
- :mod:`numerics.forced.locking`: the entrainment (locking) boundary of a forced
  self-excited oscillator, predicted and true;
- :mod:`numerics.forced.figures`: the figures of the docs page.
"""

from numerics.forced.response import NumericResponse, continue_response, numeric_response
from numerics.forced.shooting import ForcedOrbit, periodic_response
from numerics.forced.system import ForcedSystem

__all__ = ["ForcedSystem", "ForcedOrbit", "periodic_response", "NumericResponse",
           "numeric_response", "continue_response"]
