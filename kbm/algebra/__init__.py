"""The private algebra wing of :mod:`kbm`: the exact arithmetic under the KBM recursion.

Nothing here is public API; the engines of :mod:`kbm` use it, and :mod:`numerics` never
imports it.

- :mod:`~kbm.algebra.base`: the :class:`~kbm.algebra.base.RecursionAlgebra` protocol, the
  vocabulary the one recursion (:mod:`kbm.recursion`) asks of an algebra, and the one-angle
  :class:`~kbm.algebra.base.FourierAlgebra` protocol;
- :mod:`~kbm.algebra.multi_angle`: finite Fourier series in ``n`` angles with Laurent
  coefficients (the coupled and the forced algebras);
- :mod:`~kbm.algebra.grid_fourier`: what the sampled series share (the sampled algebras
  are :mod:`kbm.forced.grid`, Chebyshev in the amplitude, and the jets of
  :mod:`kbm.coupled.jet_algebra`, any ``N``);
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
  ``x = sum mu**n X_n``.
"""
