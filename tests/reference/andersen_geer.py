"""Published numbers on the van der Pol limit cycle ``x'' + x = eps (1 - x^2) x'``.

C. M. Andersen and J. F. Geer, "Power series expansions for the frequency and period of
the limit cycle of the van der Pol equation", SIAM J. Appl. Math. 42 (1982) 678-693:
the frequency ``nu(eps)`` computed to ``eps**24`` in rational arithmetic (MACSYMA) and to
``eps**164`` in floating point; its nearest singularities in the complex ``eps**2``-plane
are branch points at radius ``R ~= 3.42`` (paper's abstract, read from the publication's
abstract page).

The coefficients below are the ones that could be checked against a source found:

- ``eps**2 .. eps**6``: ``-1/16, 17/3072, 35/884736`` as Andersen & Geer's, quoted in
  this project's tests since issue 2 and in issue 13;
- ``eps**8``: ``-678899/5096079360``, quoted in issue 13 as the continuation of
  Andersen & Geer's series; no public copy of the paper's table was found to confirm it
  (nor the terms ``eps**10 .. eps**24``).  The tests therefore check the series through
  ``eps**24`` against two independent computations as well (the KBM averaged route and
  ``lindstedt_fraction.py``).
"""

from fractions import Fraction

#: coefficients of eps**n of omega* (odd n vanish)
OMEGA_VDP = {
    0: Fraction(1),
    2: Fraction(-1, 16),
    4: Fraction(17, 3072),
    6: Fraction(35, 884736),
    8: Fraction(-678899, 5096079360),
}

#: |eps**2| of the nearest branch points of omega*(eps**2)
RADIUS_MU2 = 3.42
