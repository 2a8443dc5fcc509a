"""Noise: stochastic averaging of a noisy self-excited oscillator.

- :mod:`~kbm.noise.stochastic`: first-order stochastic averaging of amplitude and phase
  (:func:`kbm.stochastic_average`);
- :mod:`~kbm.noise.stochastic_order2`: the stationary amplitude density to ``O(mu^2)``;
- :mod:`~kbm.noise.phase_diffusion`: phase diffusion and linewidth;
- :mod:`~kbm.noise.phase_response`: the phase response through the KBM transform of any
  order (the small-noise linewidth ``D <Z_v^2>``).
"""
