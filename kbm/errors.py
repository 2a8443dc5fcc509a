"""Exceptions of the :mod:`kbm` package.

Every error raised on bad input is a subclass of :class:`KBMError`, and its
message says what to change.  The command line turns them into a one-line
message and a non-zero exit status.
"""

from __future__ import annotations

__all__ = [
    "KBMError",
    "ModelError",
    "UnsupportedTermError",
    "NonFiniteError",
    "InputSizeError",
    "NonAutonomousError",
    "OrderError",
    "CostError",
    "ParameterError",
    "AveragedCycleError",
    "ExpansionError",
    "SeriesTruncationError",
    "ResolutionError",
    "OutputError",
]


class KBMError(Exception):
    """Base class of every error raised by :mod:`kbm` and :mod:`numerics`."""


class ModelError(KBMError, ValueError):
    """The oscillator definition is not of the form ``x'' + w0^2 x = eps F(x, x')``."""


class UnsupportedTermError(ModelError):
    """``F`` holds a term the averaging cannot expand (it is named in the message)."""


class NonFiniteError(ModelError):
    """An expression holds ``oo``, ``zoo`` (a division by zero) or ``nan``."""


class InputSizeError(ModelError):
    """An integer literal or power in the input passes the bounds of reading
    (:data:`kbm.symbols.MAX_DIGITS`, :data:`kbm.symbols.MAX_EXPONENT`)."""


class NonAutonomousError(ModelError):
    """``F`` depends on time ``t`` explicitly, so the averaging does not apply."""


class OrderError(KBMError, ValueError):
    """The requested order of the expansion is not available."""


class CostError(OrderError):
    """The estimated size of a symbolic expansion is beyond the budget: the message gives
    the estimate, the budget and the way out (a lower order, the numeric backend)."""


class ParameterError(KBMError, ValueError):
    """A parameter name is unknown or a value is out of its range."""


class AveragedCycleError(KBMError, ValueError):
    """The averaged equations have no limit cycle of the kind asked for: none isolated,
    several where one was expected, or one that is not hyperbolic."""


class ExpansionError(KBMError, ValueError):
    """A :class:`~kbm.KBMResult` was given coefficients that break the expansion's
    invariants (``order + 1`` entries each, no first harmonic in any ``u_n``)."""


class SeriesTruncationError(KBMError, ArithmeticError):
    """An infinite Bessel sum did not reach its tolerance within the term budget."""


class ResolutionError(KBMError, ArithmeticError):
    """The numeric KBM backend did not reach its tolerance within its grid budget (the
    resolution reached and the tails left are in the message)."""


class OutputError(KBMError, OSError):
    """An output folder or file cannot be written (the path and the reason are in the
    message)."""
