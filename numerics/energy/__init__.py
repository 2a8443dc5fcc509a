"""Strongly nonlinear (energy-balance) averaging about the conservative orbits.

The model is split as ``x'' = -g(x) + mu h(x, x')`` (:mod:`kbm.model.conservative`);
the whole conservative force ``g`` (e.g. the slider's ``Omega**2 x + Delta
sin(k x)``) is kept, only ``h`` is averaged (energy balance, energy-angle
averaging) or integrated along the cycle (position scheme).
:func:`predict_cycles` lists every cycle on every period annulus of
``x'' + g(x) = 0``; :func:`map_predictions` the same over a parameter map, with the
``mu``-independent work done once per column.
"""

from kbm._lazy import lazy_names

#: the public names, each imported from its module on first use (PEP 562): the energy
#: method's integrators (``scipy.integrate``) load only where it is used (issue 39)
_LAZY = {
    **dict.fromkeys(("AveragedEnergy", "average"), ".averaging"),
    **dict.fromkeys(("map_predictions", "predict_along_mu"), ".maps"),
    **dict.fromkeys(("BalanceCycle", "balance_cycles", "gamma_function"), ".balance"),
    **dict.fromkeys(("SampledOrbits", "sample_orbits"), ".orbits"),
    **dict.fromkeys(("PositionCycle", "PositionError", "position_cycle"), ".position"),
    **dict.fromkeys(("Annulus", "Equilibrium", "Portrait", "Quadrature", "phase_portrait"),
                    ".portrait"),
    **dict.fromkeys(("EnergyPrediction", "PredictedCycle", "predict_cycles"), ".predict"),
}

__getattr__, __dir__ = lazy_names(__name__, globals(), _LAZY)

__all__ = [
    "predict_cycles", "PredictedCycle", "EnergyPrediction", "map_predictions",
    "predict_along_mu",
    "phase_portrait", "Portrait", "Annulus", "Equilibrium", "Quadrature",
    "balance_cycles", "BalanceCycle", "gamma_function",
    "position_cycle", "PositionCycle", "PositionError",
    "average", "AveragedEnergy", "sample_orbits", "SampledOrbits",
]
