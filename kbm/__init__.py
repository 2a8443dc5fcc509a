"""kbm: Krylov-Bogoliubov-Mitropolsky averaging to any order.

The oscillators are ``x'' + omega0**2 x = mu F(x, x')`` (:mod:`kbm.models`); the
averaging writes ``x = a cos(psi) + sum_n mu**n u_n(a, psi)`` with
``da/dt = sum_n mu**n A_n(a)`` and ``dpsi/dt = omega0 + sum_n mu**n B_n(a)``,
no ``u_n`` holding a first harmonic, so ``a`` is the first-harmonic amplitude.
"""

from importlib.metadata import PackageNotFoundError, version as _version

from .errors import (KBMError, ModelError, NonAutonomousError, OrderError, ParameterError,
                     ResolutionError, SeriesTruncationError, UnsupportedTermError)
from .averaging import derive
from .averaged import AveragedCycle, AveragedRates, averaged_cycles, averaged_rates
from .evaluate import mpmath_function, numpy_function
from .latex import latex
from .numeric_kbm import NumericExpansion, numeric_derive
from .pointwise import ExpansionValues, derive_values
from .models import MODELS, Oscillator, custom_model, get_model, model_names
from .result import KBMFunctions, KBMResult
from .numeric_series import NumericCycleSeries, numeric_cycle_series
from .series import LimitCycleSeries, limit_cycle_series
from .stochastic import StochasticAveraging, stochastic_average
from .symbols import a, mu, parse, psi, t, x, xdot

__all__ = [
    "KBMError", "ModelError", "NonAutonomousError", "OrderError", "ParameterError",
    "UnsupportedTermError",
    "SeriesTruncationError", "ResolutionError",
    "derive", "derive_values", "ExpansionValues", "numeric_derive", "NumericExpansion", "KBMResult", "KBMFunctions", "numpy_function", "mpmath_function", "latex",
    "AveragedCycle", "AveragedRates", "LimitCycleSeries", "averaged_cycles", "averaged_rates",
    "limit_cycle_series", "NumericCycleSeries", "numeric_cycle_series",
    "StochasticAveraging", "stochastic_average",
    "MODELS", "Oscillator", "custom_model", "get_model", "model_names",
    "a", "mu", "parse", "psi", "t", "x", "xdot",
]

try:  # the version lives in pyproject.toml only
    __version__ = _version("kbm")
except PackageNotFoundError:  # pragma: no cover - running from a tree that is not installed
    __version__ = "0+unknown"
