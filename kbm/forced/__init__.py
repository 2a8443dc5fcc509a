"""Forced and parametrically excited oscillators: KBM near a resonance, to any order.

- :mod:`kbm.forced.model`: :class:`ForcedOscillator` (``F`` 2 pi-periodic in
  ``theta = nu t``, checked by :mod:`kbm.forced.checks`) and :class:`Resonance`;
- :mod:`kbm.forced.builtins`: the built-in forced models;
- :mod:`kbm.forced.two_angle`: exact Fourier series in the two angles ``(psi, theta)`` (the
  multi-angle series with ``n = 2``), :mod:`kbm.forced.resonant` their algebra;
- :mod:`kbm.forced.engine`: :func:`derive_forced`, the one recursion
  (:func:`kbm.recursion.kbm_recursion`, ``N = 1`` with the forcing angle; exact, polynomial
  ``F``);
- :mod:`kbm.forced.grid`, :mod:`kbm.forced.backend`: the same recursion on samples, the grid
  algebra and the one numeric backend of one degree of freedom (its cases: the autonomous
  :func:`kbm.numeric_derive`, without the forcing angle, and the forced one);
- :mod:`kbm.forced.numeric`, :mod:`kbm.forced.numeric_result`: :func:`numeric_derive_forced`
  (any smooth ``F``: the slider's ``sin(k x + theta)``) and its result, and
  :func:`forced_expansion`, which picks the engine;
- :mod:`kbm.forced.result`: :class:`ForcedKBMResult` and the numerical :class:`SlowFlow`;
- :mod:`kbm.forced.steady`: fixed points of the slow flow, their stability, the
  frequency-response curve, folds and backbone;
- :mod:`kbm.forced.resultant`: every fixed point of a polynomial slow flow by resultants
  (the exact check of the scan);
- :mod:`kbm.forced.tongues`: transition curves (instability tongues) as series, for
  tongues opening at any order;
- :mod:`kbm.forced.arclength`: the pseudo-arclength continuation shared with
  :mod:`numerics.shooting`.
"""

from .engine import MAX_ORDER, SmallDivisorError, derive_forced
from .builtins import FORCED_MODELS, forced_model_names, get_forced_model
from .model import (LAMBDA, ForcedOscillator, NonPeriodicError, Resonance, add_forcing, nu,
                    phi, sigma, theta)
from .result import ForcedKBMResult, SlowFlow
from .._lazy import lazy_names

#: the numeric backend's names, imported on first use (PEP 562): it builds on the
#: one-degree-of-freedom engine, which a forced or coupled model alone does not need
_LAZY = dict.fromkeys(("NumericForcedExpansion", "forced_expansion", "numeric_derive_forced"),
                      ".numeric")

__getattr__, __dir__ = lazy_names(__name__, globals(), _LAZY)

__all__ = ["derive_forced", "SmallDivisorError", "MAX_ORDER", "ForcedOscillator", "Resonance",
           "NonPeriodicError", "add_forcing", "get_forced_model", "forced_model_names",
           "FORCED_MODELS", "ForcedKBMResult", "SlowFlow", "numeric_derive_forced",
           "forced_expansion", "NumericForcedExpansion", "theta", "phi", "sigma", "nu",
           "LAMBDA"]
