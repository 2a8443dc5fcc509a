"""scipy's DOP853 Butcher tableau without importing :mod:`scipy.integrate` (issue 39).

``scipy.integrate._ivp.dop853_coefficients`` is a file of numpy arrays, but importing it
runs ``scipy/integrate/__init__.py``, which imports every integrator, quadrature and
boundary-value solver (about half a second).  The compiled stepper
(:mod:`numerics.flow._dop853_stepper`) needs only the arrays: the same file is executed
here on its own, so the tableau is scipy's, value for value (Hairer, Norsett and Wanner,
*Solving Ordinary Differential Equations I*, 2nd ed., Springer 1993, sec. II.10).  When
:mod:`scipy.integrate` is already imported, its module is used as it is.
"""

from __future__ import annotations

import importlib
import importlib.util
import sys
from pathlib import Path
from types import ModuleType

_NAME = "scipy.integrate._ivp.dop853_coefficients"


def dop853_coefficients() -> ModuleType:
    """scipy's module ``dop853_coefficients`` (``N_STAGES``, ``A``, ``B``, ``C``, ``E3``,
    ``E5``, ...), executed from its file unless it is imported already."""
    if _NAME in sys.modules:
        return sys.modules[_NAME]
    spec = importlib.util.find_spec("scipy")
    path = Path(spec.origin).parent / "integrate" / "_ivp" / "dop853_coefficients.py"
    if not path.is_file():  # a layout without the file: the ordinary import
        return importlib.import_module(_NAME)
    mod_spec = importlib.util.spec_from_file_location("numerics.flow._dop853_scipy", path)
    mod = importlib.util.module_from_spec(mod_spec)
    mod_spec.loader.exec_module(mod)
    return mod
