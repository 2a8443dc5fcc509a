"""Strongly nonlinear (energy-balance) averaging about the conservative orbits.

The model is split as ``x'' = -g(x) + mu h(x, x')`` (:mod:`kbm.conservative`);
the whole conservative force ``g`` (e.g. the slider's ``Omega**2 x + Delta
sin(k x)``) is kept, only ``h`` is averaged (energy balance, energy-angle
averaging) or integrated along the cycle (position scheme).
:func:`predict_cycles` lists every cycle on every period annulus of
``x'' + g(x) = 0``; :func:`map_predictions` the same over a parameter map, with the
``mu``-independent work done once per column.
"""

from .averaging import AveragedEnergy, average
from .maps import map_predictions, predict_along_mu
from .balance import BalanceCycle, balance_cycles, gamma_function
from .orbits import SampledOrbits, sample_orbits
from .position import PositionCycle, PositionError, position_cycle
from .portrait import Annulus, Equilibrium, Portrait, Quadrature, phase_portrait
from .predict import EnergyPrediction, PredictedCycle, predict_cycles

__all__ = [
    "predict_cycles", "PredictedCycle", "EnergyPrediction", "map_predictions",
    "predict_along_mu",
    "phase_portrait", "Portrait", "Annulus", "Equilibrium", "Quadrature",
    "balance_cycles", "BalanceCycle", "gamma_function",
    "position_cycle", "PositionCycle", "PositionError",
    "average", "AveragedEnergy", "sample_orbits", "SampledOrbits",
]
