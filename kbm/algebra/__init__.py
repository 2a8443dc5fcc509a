"""The private algebra wing of :mod:`kbm`: the exact arithmetic under the KBM recursion.

Nothing here is public API; :mod:`kbm.averaging` and :mod:`kbm.series` are its
only users, and :mod:`numerics` never imports it.

- :mod:`~kbm.algebra.base`: the :class:`~kbm.algebra.base.FourierAlgebra`
  protocol, the vocabulary the recursion asks of an algebra;
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
