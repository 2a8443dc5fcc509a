"""A floor of :mod:`numerics`: approximations of limit cycles, forced responses and
backbones against the true ones.

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
  :func:`branch_diagram`, every numerical branch next to them;
- :mod:`numerics.comparison.response_diagram`: the frequency-response diagram of a forced
  oscillator, the order-``N`` curve next to the true one (``kbm response``), and
  :mod:`numerics.comparison.response_convergence`: its errors against ``mu`` with fitted
  slopes (``kbm response --convergence``);
- :mod:`numerics.comparison.backbone`: backbone curves of conservative coupled oscillators
  in internal resonance, averaged and true.
"""

from kbm._lazy import keep_objects, lazy_names

#: the public names, each imported from its module on first use (PEP 562): ``kbm branch``
#: imports :mod:`numerics.comparison.diagram` without the energy method's integrators
#: (``scipy.integrate``, issue 39)
_LAZY = {
    **dict.fromkeys(("AnalyticCurve", "AnalyticFold", "energy_branch", "kbm_branch"),
                    "numerics.comparison.branches"),
    **dict.fromkeys(("Comparison", "ExtraPrediction", "compare"), "numerics.comparison.comparison"),
    **dict.fromkeys(("ConvergenceStudy", "convergence_study", "fit_slope", "predicted_orders"),
                    "numerics.comparison.convergence"),
    **dict.fromkeys(("BranchDiagram", "branch_diagram"), "numerics.comparison.diagram"),
    **dict.fromkeys(("FixedDeltaConvergence", "FixedDeltaStudy", "fixed_delta_convergence",
                     "fixed_delta_study"), "numerics.comparison.fixed_delta"),
    **dict.fromkeys(("energy_prediction", "kbm_cycles", "predict"), "numerics.comparison.predict"),
    **dict.fromkeys(("ERROR_KEYS", "Prediction", "kbm_prediction", "numeric_value", "reconstruct"),
                    "numerics.comparison.prediction"),
}

__getattr__, __dir__ = lazy_names(__name__, globals(), _LAZY)
keep_objects(__name__, ("predict",))  # the function, not its module

__all__ = ["Comparison", "compare", "ExtraPrediction", "Prediction", "kbm_prediction",
           "numeric_value", "reconstruct", "ERROR_KEYS", "ConvergenceStudy",
           "convergence_study", "fit_slope", "predicted_orders", "predict", "kbm_cycles",
           "energy_prediction", "FixedDeltaStudy", "FixedDeltaConvergence",
           "fixed_delta_study", "fixed_delta_convergence", "AnalyticCurve", "AnalyticFold",
           "kbm_branch", "energy_branch", "BranchDiagram", "branch_diagram"]
