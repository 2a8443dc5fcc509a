"""The driven sliders and their friction: a floor of :mod:`numerics` above the comparison.

- :mod:`numerics.sliding.potential`: the sliding potential (paper eq. 4), the
  saddle-node of the stick state and the quasi-static slip energy;
- :mod:`numerics.sliding.reference`: a driven run through :func:`scipy.integrate.solve_ivp`
  with dense output (:func:`slide`), and :mod:`numerics.sliding.stickslip`: its slip
  events located on the dense output (:func:`analyze`); the cost of a run with an explicit
  method and its refusal in :mod:`numerics.sliding.stiffness`, from the damping's
  ``dD/dx'`` that :mod:`numerics.sliding.damping` derives from the model;
- :mod:`numerics.sliding.driven`: the same equations compiled (numba DOP853), run
  block after block with the impulse, work and dissipation integrals;
- :mod:`numerics.sliding.friction`: the steady sliding state of one parameter set and
  its friction measures (:func:`friction_point`), friction laws over the stage velocity
  (:func:`friction_law`); the window's measures in :mod:`numerics.sliding.window`, the
  settings and the point in :mod:`numerics.sliding.friction_records`; the stage-attached
  SEDF's stick-slip cycle in long double, where double precision cannot resolve it, in
  :mod:`numerics.sliding.extended`;
- :mod:`numerics.sliding.maps`: friction maps over two parameters on any executor
  (:func:`friction_map`), SEDF against CDC;
- :mod:`numerics.sliding.chain_friction`: the friction laws of pulled chains of sliders
  (``sedf-dimer``, ``sedf-chain-N``) on the flow of :mod:`numerics.flow.coupled_flow`.
"""

from numerics.sliding.driven import DrivenSystem, driven_system
from numerics.sliding.potential import SaddleNode, potential, saddle_node, slip_energy
from numerics.sliding.reference import SlideResult, slide
from numerics.sliding.stickslip import Slip, StickSlip, analyze

__all__ = ["potential", "saddle_node", "SaddleNode", "slip_energy", "slide", "SlideResult",
           "analyze", "StickSlip", "Slip", "driven_system", "DrivenSystem"]
