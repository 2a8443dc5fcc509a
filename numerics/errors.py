"""Exceptions of :mod:`numerics`: subclasses of :class:`kbm.errors.KBMError`.

Each message holds the numbers that show what went wrong (amplitudes, times,
residuals), so that a failed computation is information, not a mystery.
"""

from __future__ import annotations

from kbm.errors import KBMError, ParameterError

__all__ = ["NumericsError", "NoCycleError", "ConvergenceError", "IntegrationError",
           "BudgetError"]


class NumericsError(KBMError):
    """Base class of the numerical errors."""


class NoCycleError(NumericsError):
    """The trajectory does not settle on a periodic orbit (it grows without bound or decays
    to rest); the message gives the amplitudes and times observed."""


class ConvergenceError(NumericsError):
    """Newton's method on the return map did not converge (residuals in the message)."""


class IntegrationError(NumericsError):
    """The integrator failed (step size underflow, non-finite state)."""


class BudgetError(ParameterError):
    """A solve above its cost budget, refused before it starts (``kbm escape
    --fp-budget``): the message gives the sizes, their cost and the budget to give."""
