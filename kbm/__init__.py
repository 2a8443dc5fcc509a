"""kbm: Krylov-Bogoliubov-Mitropolsky averaging to any order.

The oscillators are ``x'' + omega0**2 x = mu F(x, x')`` (:mod:`kbm.models`); the
averaging writes ``x = a cos(psi) + sum_n mu**n u_n(a, psi)`` with
``da/dt = sum_n mu**n A_n(a)`` and ``dpsi/dt = omega0 + sum_n mu**n B_n(a)``,
no ``u_n`` holding a first harmonic, so ``a`` is the first-harmonic amplitude.
"""

from .errors import (KBMError, ModelError, NonAutonomousError, OrderError, ParameterError,
                     UnsupportedTermError)
from .models import MODELS, Oscillator, custom_model, get_model, model_names
from .symbols import a, mu, parse, psi, t, x, xdot

__all__ = [
    "KBMError", "ModelError", "NonAutonomousError", "OrderError", "ParameterError",
    "UnsupportedTermError",
    "MODELS", "Oscillator", "custom_model", "get_model", "model_names",
    "a", "mu", "parse", "psi", "t", "x", "xdot",
]

__version__ = "0.1.0"
