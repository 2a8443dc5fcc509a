"""kbm: Krylov-Bogoliubov-Mitropolsky averaging to any order.

The oscillators are ``x'' + omega0**2 x = mu F(x, x')`` (:mod:`kbm.models`); the
averaging writes ``x = a cos(psi) + sum_n mu**n u_n(a, psi)`` with
``da/dt = sum_n mu**n A_n(a)`` and ``dpsi/dt = omega0 + sum_n mu**n B_n(a)``,
no ``u_n`` holding a first harmonic, so ``a`` is the first-harmonic amplitude.
"""

from .errors import (KBMError, ModelError, NonAutonomousError, OrderError, ParameterError,
                     ResolutionError, SeriesTruncationError, UnsupportedTermError)
from ._lazy import keep_objects, lazy_names

#: the public names, imported from their modules on first use (PEP 562): ``import kbm``
#: (and every ``kbm`` command) then costs only what it uses; sympy is imported by the first
#: name that needs it (``kbm --version`` and ``kbm --help`` import none)
_LAZY = {
    "latex": ".latex",
    **dict.fromkeys(("MODELS", "Oscillator", "custom_model", "get_model", "model_names"),
                    ".models"),
    **dict.fromkeys(("a", "mu", "parse", "psi", "t", "x", "xdot"), ".symbols"),
    "__version__": "._version",
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

#: ``kbm.latex`` is the function, also once the module of the same name is imported
keep_objects(__name__, ("latex",))

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
