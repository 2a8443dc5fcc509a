"""The private algebra wing of :mod:`kbm`: the exact arithmetic under the KBM recursion.

Nothing here is public API; the engines of :mod:`kbm` use it, and :mod:`numerics` never
imports it.  Every algebra of the one recursion is here, exact and sampled.

- :mod:`~kbm.algebra.base`: the :class:`~kbm.algebra.base.RecursionAlgebra` protocol, the
  vocabulary the one recursion (:mod:`kbm.expansion.recursion`) asks of an algebra, and the
  one-angle :class:`~kbm.algebra.base.FourierAlgebra` protocol;
- :mod:`~kbm.algebra.multi_angle`: finite Fourier series in ``n`` angles with Laurent
  coefficients (the coupled and the forced algebras);
- :mod:`~kbm.algebra.grid_fourier`: what the sampled series share (the sampled algebras
  are :mod:`kbm.algebra.grid`, Chebyshev in the amplitude, and the jets of
  :mod:`kbm.algebra.coupled_jets`, any ``N``);
  :mod:`~kbm.algebra.jet_fourier`: the Jacobi-Anger series of ``sin``, ``cos`` with exact
  Bessel jets in the amplitude (the jets' ``sin(k x)`` for :func:`kbm.derive_values`);
- :mod:`~kbm.algebra.laurent`: Laurent polynomials over Q (the coefficients of
  the polynomial algebra);
- :mod:`~kbm.algebra.poly_fourier`: finite Fourier series with Laurent
  coefficients, and :class:`~kbm.algebra.poly_fourier.PolyAlgebra` (polynomial
  ``F``, any order);
- :mod:`~kbm.algebra.bessel_fourier`: infinite Jacobi-Anger families of
  harmonics, and :class:`~kbm.algebra.bessel_fourier.SymAlgebra` (``F`` with
  ``sin(k x)``, ``cos(k x)``);
- :mod:`~kbm.algebra.lattice`: the integer lattice lines along which a harmonic of
  a double Bessel family is collected (extended Euclid);
- :mod:`~kbm.algebra.lazy_series`: lazy power series in the small parameter and
  the :class:`~kbm.algebra.lazy_series.Builder` that evaluates ``F`` along
  ``x = sum mu**n X_n``;
- the forced algebra: :mod:`~kbm.algebra.forced`, the coupled algebra for one oscillator
  and its forcing angle (series in ``(psi, theta)``) with the forced engine's refusals;
  :mod:`~kbm.algebra.power_series`, truncated power series with sympy coefficients (the
  series reversion of the transition curves);
- the coupled algebra: :mod:`~kbm.algebra.coupled`, ``N``-angle series with the resonance
  structure, and :mod:`~kbm.algebra.coupled_bessel`, ``sin(c x_l)``, ``cos(c x_l)`` at the
  first order (Jacobi-Anger);
- the sampled algebras: :mod:`~kbm.algebra.grid` (one degree of freedom, forced or not) and
  :mod:`~kbm.algebra.coupled_jets` (Taylor jets on a torus grid, any ``N``);
  :mod:`~kbm.algebra.chebyshev` (Chebyshev interpolation in the amplitude) and
  :mod:`~kbm.algebra.smooth` (Taylor tables of a smooth ``F``) are what they sample with;
- :mod:`~kbm.algebra.zfourier`: truncated Fourier series as polynomials in ``exp(i tau)``
  (the limit cycle's series of :mod:`kbm.slowflow`).
"""
