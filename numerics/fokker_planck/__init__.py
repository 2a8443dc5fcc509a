"""Fokker-Planck (Kramers) equation of the one-degree-of-freedom models at rest."""

from .kramers import KramersSolution, kramers_operator, stationary_kramers, velocity_terms

__all__ = ["KramersSolution", "kramers_operator", "stationary_kramers", "velocity_terms"]
