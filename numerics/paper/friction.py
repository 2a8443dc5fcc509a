"""The paper's physical question over whole ranges: does self-excitation lower friction?

The paper compares the SEDF (eq. 3) with the CDC (eq. 12) at a few points (Figs. 4-6).
:func:`friction_study` asks the question over the stage velocity, the potential strength and
the excitability (:mod:`numerics.sliding`):

- the friction laws ``F_bar(v)`` of the three sliders at the paper's ``Delta = 1.5`` and ``3``
  (``mu = 0.1``, ``beta = 1``, ``lam = 1``, ``Omega = 1``);
- the maps SEDF/CDC over ``(v, Delta)`` at ``beta = 1`` and over ``(v, beta)`` at
  ``Delta = 3``, with the stage-attached SEDF (the paper's own SEDF has no steady state:
  its damping ``mu beta x^2`` grows with the distance slid, :mod:`kbm.model.builtins`).

:meth:`FrictionStudy.table` is the table of ``kbm reproduce`` (``tables/friction.md``).
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass

import numpy as np

from numerics.sliding.maps import FrictionMap, SliderComparison, compare_sliders, friction_law

__all__ = ["FrictionStudy", "friction_study", "SLIDERS_COMPARED", "MAIN_JOB_SIZE",
           "LAW_PARAMS", "LAW_V", "MAP_V", "MAP_DELTA", "MAP_BETA"]

#: the docs' friction laws: the paper's mu, lam, Omega, beta = 1 and its two Delta
LAW_PARAMS = {"mu": 0.1, "lam": 1.0, "Omega": 1.0, "beta": 1.0}
LAW_V = np.geomspace(1e-3, 3.0, 24)
#: the docs' maps
MAP_V = np.geomspace(3e-3, 3.0, 32)
MAP_DELTA = np.linspace(0.25, 4.0, 32)
MAP_BETA = np.geomspace(0.05, 5.0, 32)

#: the sliders of the friction laws: the stage-attached SEDF, the CDC, the paper's SEDF
SLIDERS_COMPARED = ("sedf_comoving", "cdc", "sedf")


@dataclass(frozen=True, eq=False)
class FrictionStudy:
    """Friction laws (by ``Delta``) and the two maps of SEDF against CDC (their figures:
    :func:`numerics.paper.figures.friction.study_figures`)."""

    laws: dict[float, tuple[FrictionMap, ...]]
    v_delta: SliderComparison
    v_beta: SliderComparison

    def table(self) -> str:
        """Markdown: the regimes and mean forces of the laws, and the maps' verdicts."""
        lines = ["| Delta | slider | regimes over v | mean force at v = 1e-3 / 0.1 / 1 | "
                 "steady points |", "|---|---|---|---|---|"]
        for d, maps in self.laws.items():
            for m in maps:
                reg = Counter(p.regime or "failed" for p in m.points)
                v = m.axes["v"]
                F = m.field("mean_force")
                at = " / ".join(_force_text(F[int(np.argmin(abs(np.log(v / x))))])
                                for x in (1e-3, 0.1, 1.0))
                lines.append(f"| {d:g} | {m.model} | "
                             + ", ".join(f"{k} {n}" for k, n in sorted(reg.items()))
                             + f" | {at} | {sum(p.steady for p in m.points)}/{len(m.points)} |")
        lines += ["", "| map | points compared | steady | SEDF lower friction and dissipation "
                  "| force ratio SEDF/CDC min .. max |", "|---|---|---|---|---|"]
        for axes, fixed, s in self.verdicts():
            lines.append(f"| {axes}, {fixed} | {s['compared']}/{s['points']} | {s['steady']} | "
                         f"{s['first_better']} ({s['first_better_steady']} steady) | "
                         f"{s['force_ratio_min']:.3g} .. {s['force_ratio_max']:.3g} |")
        return "\n".join(lines) + "\n"

    def verdicts(self) -> list[tuple[str, str, dict]]:
        """Per map of SEDF against CDC: its axes, what is fixed, and its
        :meth:`~numerics.sliding.maps.SliderComparison.summary`."""
        return [("(v, Delta)", "beta = 1", self.v_delta.summary()),
                ("(v, beta)", "Delta = 3", self.v_beta.summary())]

    def to_json(self) -> dict:
        return {"laws": {f"{d:g}": [m.to_json() for m in maps] for d, maps in self.laws.items()},
                "v_delta": self.v_delta.to_json(), "v_beta": self.v_beta.to_json()}


#: the study's size in ``kbm reproduce`` and ``kbm figures`` (8 x 8 maps, 12 velocities per
#: law); the docs' figures use ``size=32, laws=24`` (``kbm figures --friction-size 32``)
MAIN_JOB_SIZE = {"size": 8, "laws": 12}


def friction_study(size: int = 32, laws: int = 24, progress: bool = False,
                   **kwargs) -> FrictionStudy:
    """The friction laws at ``Delta = 1.5, 3`` (``laws`` velocities from 1e-3 to 3) and the two
    maps on ``size x size`` grids (every ``32 // size``-th point of the docs' grids), on all
    cores (:func:`numerics.sliding.friction_map`), with tqdm bars when ``progress``."""
    step = max(1, len(MAP_V) // size)
    v = LAW_V if laws >= len(LAW_V) else np.geomspace(LAW_V[0], LAW_V[-1], laws)
    out = {}
    for d in (1.5, 3.0):
        params = {**LAW_PARAMS, "Delta": d}
        out[d] = tuple(friction_law(m, params, v, progress=progress, **kwargs)
                       for m in SLIDERS_COMPARED)
    base = {k: val for k, val in LAW_PARAMS.items() if k != "beta"}
    vd = compare_sliders({**base, "beta": 1.0}, {"v": MAP_V[::step], "Delta": MAP_DELTA[::step]},
                         progress=progress, **kwargs)
    vb = compare_sliders({**base, "Delta": 3.0}, {"v": MAP_V[::step], "beta": MAP_BETA[::step]},
                         progress=progress, **kwargs)
    return FrictionStudy(laws=out, v_delta=vd, v_beta=vb)


def _force_text(F: float) -> str:
    """A mean force, or why there is none (a runaway has no steady sliding state)."""
    return f"{F:.3g}" if np.isfinite(F) else "none (runaway)"
