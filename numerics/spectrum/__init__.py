"""Spectra of noisy oscillators (issue 37).

- :mod:`numerics.spectrum.driven`: noise spectra about the stable steady states of forced
  oscillators, averaged (the rotating frame's Ornstein-Uhlenbeck spectrum), Floquet (the
  exact linearisation about the periodic orbit) and simulated;
- :mod:`numerics.spectrum.slips`: phase slips of noisy coupled self-excited oscillators,
  Stratonovich's formula for the reduced Adler equation against simulated slip counts;
- :mod:`numerics.spectrum._sde`: the full noisy system of ``N`` oscillators and its
  ensemble integrator.
"""
