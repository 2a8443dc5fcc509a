"""kbm: Krylov-Bogoliubov-Mitropolsky averaging to any order.

The oscillators are ``x'' + omega0**2 x = mu F(x, x')`` (:mod:`kbm.model.builtins`); the
averaging writes ``x = a cos(psi) + sum_n mu**n u_n(a, psi)`` with
``da/dt = sum_n mu**n A_n(a)`` and ``dpsi/dt = omega0 + sum_n mu**n B_n(a)``,
no ``u_n`` holding a first harmonic, so ``a`` is the first-harmonic amplitude.
"""

from .errors import (KBMError, ModelError, NonAutonomousError, OrderError, ParameterError,
                     ResolutionError, SeriesTruncationError, UnsupportedTermError)
from ._lazy import lazy_names

#: the public names, imported from their modules on first use (PEP 562): ``import kbm``
#: (and every ``kbm`` command) then costs only what it uses; sympy is imported by the first
#: name that needs it (``kbm --version`` and ``kbm --help`` import none)
_LAZY = {
    "latex": ".output.latex",
    **dict.fromkeys(("MODELS", "Oscillator", "custom_model", "get_model", "model_names"),
                    ".model.builtins"),
    **dict.fromkeys(("a", "mu", "parse", "psi", "t", "x", "xdot"), ".symbols"),
    "__version__": "._version",
    "derive": ".expansion.one_dof",
    "AveragedCycle": ".slowflow.averaged", "AveragedRates": ".slowflow.averaged",
    "averaged_cycles": ".slowflow.averaged", "averaged_rates": ".slowflow.averaged",
    "mpmath_function": ".output.evaluate", "numpy_function": ".output.evaluate",
    "NumericExpansion": ".backend.one_dof", "numeric_derive": ".backend.one_dof",
    "ExpansionValues": ".backend.pointwise", "derive_values": ".backend.pointwise",
    "KBMFunctions": ".expansion.result", "KBMResult": ".expansion.result",
    "NumericCycleSeries": ".slowflow.numeric_series",
    "numeric_cycle_series": ".slowflow.numeric_series",
    "LimitCycleSeries": ".slowflow.series", "limit_cycle_series": ".slowflow.series",
    "StochasticAveraging": ".noise.stochastic", "stochastic_average": ".noise.stochastic",
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
