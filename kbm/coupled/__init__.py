"""Coupled oscillators: ``N`` degrees of freedom, internal resonances, KBM to any order.

- :mod:`kbm.coupled.model`: :class:`CoupledOscillators`, the one model type of the package
  (one degree of freedom is ``N = 1``: :class:`kbm.models.Oscillator` and
  :class:`kbm.forced.ForcedOscillator` are its cases); its symbols ``x_i, xdot_i, a_i,
  psi_i`` in :mod:`kbm.coupled.variables`;
- :mod:`kbm.coupled.resonance`: declared internal resonances and the slow lattice;
- :mod:`kbm.coupled.engine`: :func:`derive_coupled`, the exact expansion (the one recursion
  :func:`kbm.recursion.kbm_recursion` over :mod:`kbm.coupled.algebra`'s
  :class:`~kbm.coupled.algebra.CoupledAlgebra`);
- :mod:`kbm.coupled.jets` (over :mod:`kbm.coupled.jet_algebra`): the same recursion for any
  smooth ``F`` at one point of the amplitudes, any order;
- :mod:`kbm.coupled.result`: :class:`CoupledKBMResult` (JSON, LaTeX, numpy slow flow);
- :mod:`kbm.coupled.builtins`: ``coupled-vdp``, ``duffing-1-3``, ``quadratic-1-2``, the
  SEDF dimer and chains, and :func:`coupled_custom`, a user's system;
- :mod:`kbm.coupled.numeric`: :func:`numeric_average`, the first order for any smooth ``F``.

The names are imported from their modules on first use (PEP 562): the one model type's
module is imported by every model, without the engines.
"""

from .._lazy import lazy_names

_LAZY = {
    **dict.fromkeys(("COUPLED_MODELS", "coupled_model_names", "get_coupled_model",
                     "coupled_custom"), ".builtins"),
    **dict.fromkeys(("MAX_DOF_SYMBOLIC", "MAX_ORDER", "derive_coupled"), ".engine"),
    **dict.fromkeys(("CoupledOscillators", "amplitudes", "phases", "positions",
                     "velocities"), ".model"),
    **dict.fromkeys(("NumericAverage", "numeric_average"), ".numeric"),
    **dict.fromkeys(("InternalResonance", "UndeclaredResonanceError"), ".resonance"),
    "CoupledKBMResult": ".result",
}

__getattr__, __dir__ = lazy_names(__name__, globals(), _LAZY)

__all__ = ["CoupledOscillators", "CoupledKBMResult", "InternalResonance",
           "UndeclaredResonanceError", "derive_coupled", "get_coupled_model",
           "coupled_model_names", "COUPLED_MODELS", "coupled_custom", "MAX_ORDER",
           "MAX_DOF_SYMBOLIC", "positions", "velocities", "amplitudes", "phases",
           "numeric_average", "NumericAverage"]
