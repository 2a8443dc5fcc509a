"""Noise on the strongly nonlinear side: energy-envelope stochastic averaging, escape
rates from the well at the origin (averaged MFPT, Kramers, Mel'nikov-Meshkov, the turnover
of a well with two exits: :mod:`numerics.escape.turnover`) (the phase
diffusion of noisy limit cycles: :mod:`numerics.spectrum.phase_diffusion`).

Convention: ``x'' + ... = sqrt(2 D) xi(t)``, unit mass, ``<xi(t) xi(t')> = delta(t - t')``;
for linear damping ``mu`` the temperature is ``kT = D/mu``.
"""

from .envelope import EnergyEnvelope, boltzmann_moment, energy_envelope
from ._annulus import AnnulusEnvelope
from .rate import EscapeRate, averaged_escape, central_well, kramers_low_friction, separatrix_action
from .turnover import melnikov_meshkov_factor
from .turnover import spatial_diffusion_factor, turnover_rate, two_exit_factor

__all__ = [
    "energy_envelope", "EnergyEnvelope", "AnnulusEnvelope", "boltzmann_moment",
    "averaged_escape", "EscapeRate", "central_well", "kramers_low_friction",
    "melnikov_meshkov_factor", "separatrix_action", "spatial_diffusion_factor",
    "two_exit_factor", "turnover_rate",
]
