"""Finite temperature on top of the Langevin integrator (:mod:`numerics.noise`) and the
energy-envelope averaging (:mod:`numerics.escape`): the stationary state averaged
against simulated (``kbm noise``) and friction with thermal noise.

Convention: ``x'' + ... = sqrt(2 D) xi(t)``, unit mass, ``kT = D/mu`` for linear damping.
"""

from .averaged import AveragedStationary, averaged_stationary
from .stationary import noise_report

__all__ = ["AveragedStationary", "averaged_stationary", "noise_report"]
