"""The paper's wing: M. D'Acunto, "Friction force for self-excited systems", reproduced.

Sits on top of everything generic in :mod:`numerics`:

- :mod:`numerics.paper.printed`: the paper's eqs. (5)-(9) as printed, as a
  predicted cycle;
- :mod:`numerics.paper.errata`: numerical evidence for each erratum;
- :mod:`numerics.paper.claims`: the paper's claims about the driven sliders
  (eqs. 3, 12), measured with :mod:`numerics.sliding`;
- :mod:`numerics.paper.friction`: the paper's question asked over a whole
  range -- friction laws and maps of SEDF against CDC (:mod:`numerics.sliding`);
- :mod:`numerics.paper.validity`: where classical KBM holds for the SEDF;
- :mod:`numerics.paper.methods`: where classical KBM and the energy method hold
  (:func:`~numerics.paper.methods.methods_map`);
- :mod:`numerics.paper.reproduce`: the main job (:func:`reproduce`);
- :mod:`numerics.paper.figures`: every figure, by name.
"""

from numerics.paper.claims import Claim, check_claims
from numerics.paper.errata import ErratumEvidence, errata_evidence, errata_rows
from numerics.paper.printed import paper_prediction
from numerics.sliding import (SaddleNode, SlideResult, Slip, StickSlip, analyze, potential,
                              saddle_node, slide, slip_energy)

__all__ = ["paper_prediction", "errata_evidence", "errata_rows", "ErratumEvidence", "slide",
           "SlideResult", "analyze", "StickSlip", "Slip", "potential", "saddle_node",
           "SaddleNode", "slip_energy", "check_claims", "Claim"]
