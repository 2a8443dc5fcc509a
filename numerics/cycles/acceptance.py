"""The acceptance standard of shooting at its earlier address: it lives in
:mod:`numerics.shooting.acceptance` (one standard for every shooting and continuation)."""

from numerics.shooting.acceptance import *  # noqa: F401,F403
from numerics.shooting.acceptance import __all__  # noqa: F401
