"""Spectra of noisy oscillators: linewidth, phase diffusion and power spectral densities.

The noisy model is the paper's eq. (1) with ``sqrt(2 D) xi(t)`` added (the convention of
:mod:`numerics.noise`).  Modules:

- :mod:`numerics.spectrum.psd`: the one-sided power spectral density of an ensemble of
  sampled trajectories (Welch per trajectory, the band from the spread across them);
- :mod:`numerics.spectrum.phase_diffusion`: the averaged theory of a self-excited
  oscillator evaluated at the stable cycle (amplitude relaxation rate, phase diffusion,
  nonisochronicity, effective linewidth, noise-induced frequency shift, the Lorentzian
  lines of x(t) at the fundamental and its harmonics), from :mod:`kbm.noise.phase_diffusion`;
- :mod:`numerics.spectrum.density`: the stationary density of the averaged amplitude on a
  grid fitted to its width (refused where the noise escapes over an unstable averaged cycle);
- :mod:`numerics.spectrum.linewidth`: the linewidth and mean frequency measured on
  sampled trajectories (phase of the analytic signal, phase-variance growth, a
  Lorentzian fit);
- :mod:`numerics.spectrum.floquet`: the small-noise linewidth of the true cycle from its
  phase response (adjoint Floquet problem), exact in ``mu``;
- :mod:`numerics.spectrum.simulate`: ensembles of the full Langevin equation recording
  x(t) on the executor (one seed per trajectory, ``store``/``resume``);
- :mod:`numerics.spectrum.result`: the report of ``kbm spectrum`` (averaged against
  simulated) and its JSON;
- :mod:`numerics.spectrum.driven`: the linear-response and noise spectra of driven steady
  states (slow-flow Jacobian and Floquet);
- :mod:`numerics.spectrum.adler`: the noisy Adler equation of a locked pair (the averaged
  flow with slaved amplitudes), Stratonovich's slip rate and the mean phase;
- :mod:`numerics.spectrum.slips`: the phase-slip rate of noisy locked pairs, counted by the
  mean phase; both simulate the full noisy system of :mod:`numerics.noise.coupled`.
"""

from .psd import PSD, ensemble_psd

__all__ = ["PSD", "ensemble_psd"]
