"""Floor 3 of :mod:`numerics`: approximations of limit cycles against the true ones.

- :mod:`numerics.comparison.prediction`: what an approximation predicts
  (:class:`Prediction`, :func:`kbm_prediction`) and the true values
  (:func:`numeric_value`);
- :mod:`numerics.comparison.predict`: every cycle an analysis predicts
  (:func:`predict`: the energy balance about the conservative orbit, or classical
  KBM), and the energy method as a row of :func:`compare`;
- :mod:`numerics.comparison.comparison`: :func:`compare`, :class:`Comparison`;
- :mod:`numerics.comparison.convergence`: errors against ``mu`` with fitted slopes;
- :mod:`numerics.comparison.fixed_delta`: the same at fixed physical ``Delta``, energy
  method next to classical KBM;
- :mod:`numerics.comparison.branches`: analytic branches of cycles over a parameter
  (KBM roots and energy balance, with folds); :mod:`numerics.comparison.diagram`:
  :func:`branch_diagram`, every numerical branch next to them.
"""

from numerics.comparison.branches import AnalyticCurve, AnalyticFold, energy_branch, kbm_branch
from numerics.comparison.comparison import Comparison, ExtraPrediction, compare
from numerics.comparison.convergence import (ConvergenceStudy, convergence_study, fit_slope,
                                             predicted_orders)
from numerics.comparison.diagram import BranchDiagram, branch_diagram
from numerics.comparison.fixed_delta import (FixedDeltaConvergence, FixedDeltaStudy,
                                             fixed_delta_convergence, fixed_delta_study)
from numerics.comparison.predict import energy_prediction, kbm_cycles, predict
from numerics.comparison.prediction import (ERROR_KEYS, Prediction, kbm_prediction,
                                            numeric_value, reconstruct)

__all__ = ["Comparison", "compare", "ExtraPrediction", "Prediction", "kbm_prediction",
           "numeric_value", "reconstruct", "ERROR_KEYS", "ConvergenceStudy",
           "convergence_study", "fit_slope", "predicted_orders", "predict", "kbm_cycles",
           "energy_prediction", "FixedDeltaStudy", "FixedDeltaConvergence",
           "fixed_delta_study", "fixed_delta_convergence", "AnalyticCurve", "AnalyticFold",
           "kbm_branch", "energy_branch", "BranchDiagram", "branch_diagram"]
