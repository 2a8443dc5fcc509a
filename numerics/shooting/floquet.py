"""Floquet multipliers of a planar autonomous cycle that stay right at any stiffness.

For ``y' = f(y)`` in the plane the monodromy matrix ``Phi(T)`` has
``det Phi(T) = exp(oint div f dt)`` (Liouville) and one multiplier equal to 1
(the flow direction).  The other multiplier is therefore
``exp(oint div f dt) / m_trivial``: one exponential of an integral that the
integrator accumulates to relative accuracy, while the eigenvalues of the
computed ``Phi(T)`` carry an absolute error of about ``rtol * |Phi|`` (vdp at
``mu = 5``: the eigenvalue is ``-8e-15``, the true multiplier ``7.7e-38``).
The eigenvalues remain useful as a check of the trivial multiplier.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["floquet_multipliers", "nontrivial_multiplier"]


def nontrivial_multiplier(div_integral: float, trivial: complex | float = 1.0) -> float:
    """The non-trivial multiplier ``exp(div_integral) / trivial`` (Liouville's formula).

    Parameters
    ----------
    div_integral : float
        ``oint div f dt`` over one period.
    trivial : complex or float
        The trivial multiplier (1 exactly for a periodic orbit; pass the computed one to
        keep ``m_trivial * m = det Phi(T)``); only its real part is used.

    Returns
    -------
    float
        The multiplier (``0.0`` when the exponential underflows).

    Raises
    ------
    ValueError
        If ``div_integral`` is not finite or ``trivial`` is not close to a positive number.

    Examples
    --------
    >>> round(nontrivial_multiplier(-2.0), 12)
    0.135335283237
    """
    d = float(div_integral)
    m1 = complex(trivial).real
    if not math.isfinite(d):
        raise ValueError(f"oint div f dt = {d} is not finite; integrate the cycle again")
    if not m1 > 0:
        raise ValueError(f"trivial multiplier {trivial} is not positive: the orbit is not a "
                         "closed cycle of a planar autonomous flow")
    return math.exp(d) / m1 if d < 709.0 else math.inf


def floquet_multipliers(phi: np.ndarray, div_integral: float) -> tuple[complex, complex]:
    """``(trivial, non-trivial)``: the eigenvalue of ``phi`` closest to 1 and Liouville's.

    Parameters
    ----------
    phi : numpy.ndarray
        The 2x2 monodromy matrix ``Phi(T)``.
    div_integral : float
        ``oint div f dt``.

    Returns
    -------
    tuple of complex
        The trivial multiplier (an eigenvalue of ``phi``, a check: it should be 1) and
        the non-trivial one from :func:`nontrivial_multiplier`.
    """
    eig = np.linalg.eigvals(np.asarray(phi, dtype=float))
    trivial = complex(eig[int(np.argmin(np.abs(eig - 1.0)))])
    return trivial, complex(nontrivial_multiplier(div_integral, trivial))
