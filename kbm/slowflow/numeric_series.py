"""The limit cycle's mu-series in floating point, to high order, and its resummation.

:func:`numeric_cycle_series` runs the Lindstedt recursion of
:mod:`kbm.slowflow.cycle_series` in double precision (numpy) or, with ``digits``, in
mpmath at that precision, so that the series reach orders where the exact
rationals would be too large (van der Pol to ``mu**300`` in ~10 s; Andersen &
Geer 1982 went to ``eps**164`` in floating point, Amore, Boyd & Fernandez 2018 to
859 terms).  The result resums the series with Pade approximants (in ``mu**2``
when the odd coefficients vanish, as for van der Pol) and estimates the radius of
convergence (:mod:`kbm.slowflow.resum`).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from fractions import Fraction

import mpmath
import sympy as sp

from ..errors import OrderError, ParameterError
from .resum import Resummed, Singularity, nearest_singularity, pade_resum

__all__ = ["NumericCycleSeries", "numeric_cycle_series", "MAX_FLOAT_ORDER", "MAX_DIGITS"]

#: highest order in double precision (van der Pol: order 300 in ~10 s, 1000 in 9.4 min CPU,
#: 65 % of it numpy's convolutions of the Cauchy products; a progress callback per order)
MAX_FLOAT_ORDER = 1000
#: highest order with ``digits`` (pure-Python mpmath: the cost grows like order**4)
MAX_MP_ORDER = 200
#: range of ``digits``
MIN_DIGITS, MAX_DIGITS = 5, 1000


@dataclass(frozen=True)
class NumericCycleSeries:
    """Floating-point series ``a* = sum amplitude[n] mu**n``, ``omega* = sum omega[n] mu**n``.

    Attributes
    ----------
    model
        The model's name.
    order
        Highest power of ``mu``.
    omega, amplitude
        The coefficients (floats, or ``mpmath.mpf`` when computed with ``digits``).
    digits
        Decimal digits of the arithmetic (``None``: double precision).
    even
        Whether every odd coefficient vanishes, so that both are series in ``mu**2``
        (then the resummation and the radius are in ``t = mu**2``).
    """

    model: str
    order: int
    omega: tuple
    amplitude: tuple
    digits: int | None
    even: bool

    def coefficients(self, which: str = "omega") -> list:
        """The coefficients of ``omega*`` (or ``a*``) in the series' variable
        (:attr:`variable`): every power of ``mu``, or of ``mu**2`` for an even series (its
        even coefficients only), lowest power first.

        Raises
        ------
        kbm.errors.ParameterError
            If ``which`` is neither ``"omega"`` nor ``"amplitude"``.
        """
        if which not in ("omega", "amplitude"):
            raise ParameterError(f"which must be 'omega' or 'amplitude', got {which!r}")
        c = list(getattr(self, which))
        return c[::2] if self.even else c

    @property
    def variable(self) -> str:
        """``"mu**2"`` for an even series, else ``"mu"``."""
        return "mu**2" if self.even else "mu"

    def partial_sum(self, mu: float, which: str = "omega") -> mpmath.mpf:
        """The truncated series at ``mu`` (diverges beyond the radius of convergence)."""
        c = self.coefficients(which)
        t = mpmath.mpf(mu) ** (2 if self.even else 1)
        return mpmath.polyval(c[::-1], t)

    def pade(self, mu: float, which: str = "omega", **kwargs) -> Resummed:
        """``omega*(mu)`` (or ``a*``) by diagonal Pade approximants in the series' variable
        (:func:`kbm.slowflow.resum.pade_resum`; keyword arguments go there)."""
        t = mpmath.mpf(mu) ** (2 if self.even else 1)
        return pade_resum(self.coefficients(which), t, **kwargs)

    def singularity(self, which: str = "omega", **kwargs) -> Singularity:
        """The nearest singularities in the series' variable
        (:func:`kbm.slowflow.resum.nearest_singularity`)."""
        return nearest_singularity(self.coefficients(which), variable=self.variable, **kwargs)


def numeric_cycle_series(model, order: int, *, digits: int | None = None,
                         root: object | None = None,
                         progress: Callable[[int], object] | None = None
                         ) -> NumericCycleSeries:
    """Floating-point ``mu``-series of the limit-cycle frequency and first-harmonic amplitude.

    Parameters
    ----------
    model
        A model or built-in name; ``F`` a polynomial with rational coefficients,
        ``omega0`` a positive rational (parameters substituted).
    order
        Highest power of ``mu``: ``1 <= order <= 1000`` in double precision,
        ``<= 200`` with ``digits``.
    digits
        Decimal digits of an mpmath computation (``5..1000``); default: double
        precision with numpy (fast).
    root
        The first-order amplitude ``a_0`` if ``A_1`` has several positive roots
        (it may be irrational here).
    progress
        Called with 1 after each power of ``mu`` (a :mod:`tqdm` bar's ``update``;
        :func:`kbm.slowflow.cycle_series.lindstedt_series`).

    Returns
    -------
    NumericCycleSeries

    Raises
    ------
    kbm.errors.OrderError
        For an order out of range, or ``F`` that is not a polynomial with rational
        coefficients.
    kbm.errors.ParameterError
        For ``digits`` out of range (and the errors of :func:`kbm.limit_cycle_series`).

    Examples
    --------
    >>> s = numeric_cycle_series("vdp", 8)
    >>> s.even, s.omega[2], round(s.omega[4] * 3072, 12)
    (True, -0.0625, 17.0)
    """
    from ..algebra.zfourier import arithmetic
    from .cycle_series import lindstedt_series
    from ..backend.sampling import check_order
    from .series import first_order_cycle, lindstedt_terms

    if digits is not None and (not isinstance(digits, int) or isinstance(digits, bool)
                               or not MIN_DIGITS <= digits <= MAX_DIGITS):
        raise ParameterError(f"digits must be an integer from {MIN_DIGITS} to {MAX_DIGITS}, got "
                             f"{digits!r}; leave it out for double precision")
    check_order(order, MAX_FLOAT_ORDER if digits is None else MAX_MP_ORDER,
                "series in double precision" if digits is None
                else "series with digits (pure-Python mpmath)")
    model, _, a0 = first_order_cycle(model, root)
    terms = lindstedt_terms(model)
    if terms is None:
        raise OrderError("floating-point series need F polynomial in x, xdot with rational "
                         f"coefficients and a rational omega0 (got F = {model.F}, omega0 = "
                         f"{model.omega0})")
    w0 = model.omega0
    omega0 = Fraction(int(w0.p), int(w0.q))
    if digits is None:
        ar = arithmetic("float")
        a0_num = float(a0)
        raw = lindstedt_series(terms, omega0, a0_num, order, ar, progress)
        omega = tuple(float(v) for v in raw.omega)
        amp = tuple(float(v) for v in raw.amplitude)
    else:
        prec = int(digits * 3.33) + 20
        with mpmath.workprec(prec):
            ar = arithmetic("mp", prec=prec, use_flint=False)
            a0_num = mpmath.mpf(sp.N(a0, digits + 10)) if not a0.is_Rational \
                else mpmath.mpf(int(a0.p)) / int(a0.q)
            raw = lindstedt_series(terms, omega0, a0_num, order, ar, progress)
            omega = tuple(+v for v in raw.omega)
            amp = tuple(+v for v in raw.amplitude)
    scale = max(abs(v) for v in omega + amp)
    tiny = scale * (mpmath.mpf(10) ** -(digits or 15))
    even = all(abs(v) <= tiny * 1e-3 for v in omega[1::2] + amp[1::2])
    return NumericCycleSeries(model=model.name, order=order, omega=omega, amplitude=amp,
                              digits=digits, even=even)
