"""Numerical dynamics of the models defined in :mod:`kbm`.

Built in floors, each importing only the ones below it (``tests/test_floors.py``); the
base holds the errors, the memo helper and :mod:`numerics.executor` (any sweep on a local
process pool, an executor or a Dask cluster):

1. :mod:`numerics.flow` — the model turned into numbers and trajectories (one degree of
   freedom, the ``2N`` flow of coupled oscillators, a forced model over its period);
2. :mod:`numerics.shooting` — the one shooting and continuation code for ``2N``-dimensional
   flows, with one acceptance standard (autonomous and forced orbits, branches, folds and
   other special points);
3. :mod:`numerics.noise` — Langevin integration of the noisy models, ensembles;
4. :mod:`numerics.energy` — the strongly nonlinear (energy-balance) averaging about the
   conservative orbits, numerical by nature, on top of the flow;
5. :mod:`numerics.cycles` — true limit cycles of one degree of freedom on that code
   (every predicted cycle, homoclinic ends, high precision, sweeps);
6. :mod:`numerics.locking` — frequency locking (coupled and forced), averaged against true;
7. :mod:`numerics.comparison` — approximations against the true cycles, responses and
   backbones;
8. :mod:`numerics.sliding` — the pulled sliders: driven runs (scipy and compiled),
   stick-slip, steady sliding states, friction laws and maps, chains of sliders;
9. :mod:`numerics.fokker_planck`, :mod:`numerics.escape`, :mod:`numerics.thermal`,
   :mod:`numerics.spectrum` — the Kramers equation, escape rates, finite temperature,
   spectra;
10. :mod:`numerics.bifurcation` — diagrams in two parameters;
11. :mod:`numerics.paper` — the reproduction of D'Acunto's paper, and every figure;
12. :mod:`numerics.cli` — the ``kbm`` command line (on top of :mod:`kbm` and all of these),
    with its one parameter and option layer, :mod:`numerics.cli.params`.
"""

import os as _os
import sys as _sys

import kbm as _kbm


# A folder ``kbm`` without ``__init__.py`` (a clone of the project) on an entry of
# ``sys.path`` is taken for a namespace package where the package itself is reached only
# through an import hook (setuptools' editable installs by a finder).  The entry is most
# often ``sys.path[0]``: the folder of the script that runs (``python ../snippet.py`` from
# elsewhere) or, for ``python -c``, ``-m`` and the prompt, the current folder.


def _shadow_where(entry: str) -> str:
    """Which folder of ``sys.path`` ``entry`` is, in the user's words."""
    here = _os.getcwd()
    path = _os.path.abspath(entry or here)
    first = _os.path.abspath(_sys.path[0] or here) if _sys.path else None
    script = _sys.argv[0] if _sys.argv and _sys.argv[0] not in ("", "-c", "-m") else ""
    if path == first and script and _os.path.isfile(script):
        return f"the folder of the script {script!r} ({path}, Python's first import folder)"
    if path == here:
        return f"Python's current folder ({path})"
    return f"the folder {path} on sys.path"


def _shadow_message(folders: list[str]) -> str:
    """What found the folder(s) ``folders`` instead of the package, and the ways out."""
    places = []
    for folder in folders:
        parent = _os.path.dirname(_os.path.abspath(folder))
        entry = next((e for e in _sys.path if _os.path.abspath(e or _os.getcwd()) == parent),
                     parent)
        places.append(_shadow_where(entry))
    return (f"'import kbm' found the folder {', '.join(map(str, folders))}, not the kbm "
            f"package: {'; '.join(places)} holds a folder named 'kbm' (the clone of the "
            "project?). Reinstall the clone with 'python -m pip install -e CLONE' (it puts "
            "the clone on Python's path, where the package wins over the bare folder), or "
            "move the script or run Python from another folder.")


if getattr(_kbm, "__file__", None) is None:  # a bare folder 'kbm' shadows the package
    raise ImportError(_shadow_message(list(_kbm.__path__)))

from numerics._memo import clear_caches  # noqa: E402
from numerics.errors import (ConvergenceError, IntegrationError, NoCycleError,  # noqa: E402
                             NumericsError)

from kbm._lazy import lazy_names  # noqa: E402

#: the public names, each imported from its module on first use (PEP 562): ``import
#: numerics`` (and the ``kbm`` command line on top of it) costs only what is used
_LAZY = {
    **dict.fromkeys(("Comparison", "ConvergenceStudy", "Prediction", "compare",
                     "convergence_study", "energy_prediction", "kbm_prediction", "predict",
                     "predicted_orders"), "numerics.comparison"),
    **dict.fromkeys(("Dissipation", "LimitCycle", "SweepPoint", "grid", "limit_cycle",
                     "limit_cycles", "sweep"), "numerics.cycles"),
    **dict.fromkeys(("Method", "integrate"), "numerics.flow"),
    "langevin_system": "numerics.noise",
    "stationary_ensemble": "numerics.noise.ensemble",
    **dict.fromkeys(("Claim", "ErratumEvidence", "SaddleNode", "SlideResult", "Slip",
                     "StickSlip", "analyze", "check_claims", "errata_evidence",
                     "paper_prediction", "potential", "saddle_node", "slide", "slip_energy"),
                    "numerics.paper"),
    "noise_report": "numerics.thermal",
    "thermal_friction_map": "numerics.thermal.friction",
}

__getattr__, __dir__ = lazy_names(__name__, globals(), _LAZY)

__all__ = [
    "integrate", "Method", "limit_cycle", "limit_cycles", "LimitCycle", "Dissipation", "sweep",
    "grid", "SweepPoint", "compare", "Comparison", "Prediction", "kbm_prediction",
    "paper_prediction", "predict", "energy_prediction",
    "convergence_study", "ConvergenceStudy", "predicted_orders",
    "errata_evidence", "ErratumEvidence",
    "slide", "SlideResult", "analyze", "StickSlip", "Slip",
    "potential", "saddle_node", "SaddleNode", "slip_energy", "check_claims", "Claim",
    "NumericsError", "NoCycleError", "ConvergenceError", "IntegrationError", "clear_caches",
    "langevin_system", "stationary_ensemble", "noise_report", "thermal_friction_map",
]
