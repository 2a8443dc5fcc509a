"""Numerical dynamics of the models defined in :mod:`kbm`.

Direct integration, limit cycles by shooting with Floquet multipliers,
dissipation per cycle, the paper's sliding (stick-slip) experiments, and the
comparison of KBM predictions with the true dynamics.
"""

from .claims import Claim, check_claims
from .compare import Comparison, Prediction, compare, kbm_prediction, paper_prediction
from .convergence import ConvergenceStudy, convergence_study, predicted_orders
from .cycle import Dissipation, LimitCycle, limit_cycle
from .errata import ErratumEvidence, errata_evidence
from .errors import ConvergenceError, IntegrationError, NoCycleError, NumericsError
from .integrate import integrate
from .potential import SaddleNode, potential, saddle_node, slip_energy
from .sliding import SlideResult, slide
from .stickslip import Slip, StickSlip, analyze
from .sweep import SweepPoint, grid, sweep

__all__ = [
    "integrate", "limit_cycle", "LimitCycle", "Dissipation", "sweep", "grid", "SweepPoint",
    "compare", "Comparison", "Prediction", "kbm_prediction", "paper_prediction",
    "convergence_study", "ConvergenceStudy", "predicted_orders",
    "errata_evidence", "ErratumEvidence",
    "slide", "SlideResult", "analyze", "StickSlip", "Slip",
    "potential", "saddle_node", "SaddleNode", "slip_energy", "check_claims", "Claim",
    "NumericsError", "NoCycleError", "ConvergenceError", "IntegrationError",
]
