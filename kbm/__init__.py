"""kbm: Krylov-Bogoliubov-Mitropolsky averaging to any order.

The oscillators are ``x'' + omega0**2 x = mu F(x, x')`` (:mod:`kbm.models`); the
averaging writes ``x = a cos(psi) + sum_n mu**n u_n(a, psi)`` with
``da/dt = sum_n mu**n A_n(a)`` and ``dpsi/dt = omega0 + sum_n mu**n B_n(a)``,
no ``u_n`` holding a first harmonic, so ``a`` is the first-harmonic amplitude.
"""

from importlib.metadata import PackageNotFoundError, version as _version

from .errors import (KBMError, ModelError, NonAutonomousError, OrderError, ParameterError,
                     ResolutionError, SeriesTruncationError, UnsupportedTermError)
from .latex import latex  # eager: the name is also a submodule's
from .models import MODELS, Oscillator, custom_model, get_model, model_names
from ._lazy import lazy_names
from .symbols import a, mu, parse, psi, t, x, xdot

#: the public names of the heavier modules, imported on first use (PEP 562): ``import kbm``
#: (and every ``kbm`` command) then costs only what it uses
_LAZY = {
    "derive": ".averaging",
    "AveragedCycle": ".averaged", "AveragedRates": ".averaged",
    "averaged_cycles": ".averaged", "averaged_rates": ".averaged",
    "mpmath_function": ".evaluate", "numpy_function": ".evaluate",
    "NumericExpansion": ".numeric_kbm", "numeric_derive": ".numeric_kbm",
    "ExpansionValues": ".pointwise", "derive_values": ".pointwise",
    "KBMFunctions": ".result", "KBMResult": ".result",
    "NumericCycleSeries": ".numeric_series", "numeric_cycle_series": ".numeric_series",
    "LimitCycleSeries": ".series", "limit_cycle_series": ".series",
    "StochasticAveraging": ".stochastic", "stochastic_average": ".stochastic",
}

__getattr__, __dir__ = lazy_names(__name__, globals(), _LAZY)


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
