"""Numerical dynamics of the models defined in :mod:`kbm`.

Direct integration, limit cycles by shooting with Floquet multipliers,
dissipation per cycle, the paper's sliding (stick-slip) experiments, and the
comparison of KBM predictions with the true dynamics.
"""

from .cycle import Dissipation, LimitCycle, limit_cycle
from .errors import ConvergenceError, IntegrationError, NoCycleError, NumericsError
from .sweep import SweepPoint, grid, sweep
from .compare import Comparison, Prediction, compare, kbm_prediction, paper_prediction
from .convergence import ConvergenceStudy, convergence_study, predicted_orders
from .errata import ErratumEvidence, errata_evidence
from .claims import Claim, check_claims
from .potential import SaddleNode, potential, saddle_node, slip_energy
from .sliding import SlideResult, slide
from .stickslip import Slip, StickSlip, analyze
from .integrate import integrate
