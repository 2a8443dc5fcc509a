"""Coupled oscillators: ``N`` degrees of freedom, internal resonances, KBM to any order.

- :mod:`kbm.coupled.model`: :class:`CoupledOscillators` (one degree of freedom is ``N = 1``);
  its symbols ``x_i, xdot_i, a_i, psi_i`` in :mod:`kbm.coupled.variables`;
- :mod:`kbm.coupled.forms`: its two forms of one degree of freedom, converted both ways;
- :mod:`kbm.coupled.resonance`: declared internal resonances and the slow lattice;
- :mod:`kbm.coupled.engine`: :func:`derive_coupled`, the exact expansion (the one recursion
  :func:`kbm.recursion.kbm_recursion` over :mod:`kbm.coupled.algebra`'s
  :class:`~kbm.coupled.algebra.CoupledAlgebra`);
- :mod:`kbm.coupled.jets` (over :mod:`kbm.coupled.jet_algebra`): the same recursion for any
  smooth ``F`` at one point of the amplitudes, any order;
- :mod:`kbm.coupled.result`: :class:`CoupledKBMResult` (JSON, LaTeX, numpy slow flow);
- :mod:`kbm.coupled.builtins`: ``coupled-vdp``, ``duffing-1-3``, ``quadratic-1-2``, the
  SEDF dimer and chains;
- :mod:`kbm.coupled.numeric`: :func:`numeric_average`, the first order for any smooth ``F``.
"""

from . import forms  # noqa: F401  (attaches from_oscillator, to_oscillator)
from .builtins import COUPLED_MODELS, coupled_model_names, get_coupled_model
from .engine import MAX_DOF_SYMBOLIC, MAX_ORDER, derive_coupled
from .model import CoupledOscillators, amplitudes, coupled_custom, phases, positions, velocities
from .numeric import NumericAverage, numeric_average
from .resonance import InternalResonance, UndeclaredResonanceError
from .result import CoupledKBMResult

__all__ = ["CoupledOscillators", "CoupledKBMResult", "InternalResonance",
           "UndeclaredResonanceError", "derive_coupled", "get_coupled_model",
           "coupled_model_names", "COUPLED_MODELS", "coupled_custom", "MAX_ORDER",
           "MAX_DOF_SYMBOLIC", "positions", "velocities", "amplitudes", "phases",
           "numeric_average", "NumericAverage"]
