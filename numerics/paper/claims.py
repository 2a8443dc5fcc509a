"""The paper's quantitative claims of section 3, each measured and given a verdict.

Every claim is a :class:`Claim` with the paper's words, the numbers measured
by :func:`numerics.slide` / :func:`numerics.analyze` at the paper's parameters
(``mu = 0.1``, ``Omega = 1``, ``lambda = 1``), and a verdict:
``"holds"``, ``"does not hold"`` or ``"partly"``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from kbm.output.paper import FIG5

from numerics.sliding.potential import saddle_node
from numerics.sliding.reference import slide
from numerics.sliding.stickslip import analyze

__all__ = ["Claim", "check_claims"]


@dataclass(frozen=True, eq=False)
class Claim:
    """One claim of the paper, measured."""

    key: str
    paper: str
    measured: str
    verdict: str
    numbers: dict

    def row(self) -> list[str]:
        return [self.key, self.paper, self.measured, self.verdict]


def _oscillations_after_first_slip(res, a) -> int:
    """Sign changes of x' during the first real slip (a jump that crosses a well)."""
    jumps = [s for s in a.slips if s.wells != 0]
    if not jumps:
        return 0
    s = jumps[0]
    m = (res.t >= s.t_start) & (res.t <= s.t_end)
    v = res.xdot[m]
    return int(np.sum(np.sign(v[:-1]) * np.sign(v[1:]) < 0))


def check_claims(t_end: float = 1500.0) -> list[Claim]:
    """Measure each quantitative statement of the paper's section 3 (a few seconds)."""
    sedf = slide("sedf", FIG5, t_end=t_end)
    cdc = slide("cdc", {k: v for k, v in FIG5.items() if k != "beta"}, t_end=t_end)
    a_s, a_c = analyze(sedf), analyze(cdc)
    out: list[Claim] = []

    # 1. peak friction ratio (Fig. 5)
    first_s = next((s for s in a_s.slips if s.wells != 0), None)
    first_c = next((s for s in a_c.slips if s.wells != 0), None)
    ratio = a_c.peak_force / a_s.peak_force
    out.append(Claim(
        "peak friction (Fig. 5)",
        "the peak of kinetic friction of SEDF is about 5 times smaller than the CDC peak",
        f"peak spring force: CDC {a_c.peak_force:.4g}, SEDF {a_s.peak_force:.4g} "
        f"(ratio {ratio:.3g}) over t <= {t_end:g}",
        "does not hold" if ratio < 2 else ("holds" if ratio > 3.5 else "partly"),
        {"peak_cdc": a_c.peak_force, "peak_sedf": a_s.peak_force, "ratio": ratio}))

    # 2. single jump vs oscillation before stabilisation
    osc_s = _oscillations_after_first_slip(sedf, a_s)
    osc_c = _oscillations_after_first_slip(cdc, a_c)
    wells_s = first_s.wells if first_s else 0
    wells_c = first_c.wells if first_c else 0
    stuck_s = float(np.mean(np.abs(sedf.xdot) <= 5 * FIG5["v"]))
    stuck_c = float(np.mean(np.abs(cdc.xdot) <= 5 * FIG5["v"]))
    out.append(Claim(
        "first slip (Fig. 5)",
        "the slip of the SEDF is a single jump, the CDC oscillates before stabilising",
        f"first slip crossing wells: SEDF {wells_s} well(s) with {osc_s} velocity reversals; "
        f"CDC {wells_c} well(s) with {osc_c} velocity reversals; fraction of time stuck "
        f"(|x'| <= 5 v): SEDF {stuck_s:.2f}, CDC {stuck_c:.2f}",
        "holds" if osc_s < osc_c else "does not hold",
        {"reversals_sedf": osc_s, "reversals_cdc": osc_c, "wells_sedf": wells_s,
         "wells_cdc": wells_c, "stuck_sedf": stuck_s, "stuck_cdc": stuck_c}))

    # 3. stick condition |x - v t| <= Delta/Omega^2
    Om, D = FIG5["Omega"], FIG5["Delta"]
    bound = D / Om**2
    stick = np.abs(cdc.xdot) <= 5 * FIG5["v"]
    dev = np.abs(cdc.x - FIG5["v"] * cdc.t)[stick]
    max_dev = float(np.max(dev)) if dev.size else float("nan")
    out.append(Claim(
        "stick condition",
        "for |x - v t| > Delta/Omega^2 it is impossible to have stick solutions",
        f"largest |x - v t| while |x'| <= 5 v (CDC): {max_dev:.4g}; Delta/Omega^2 = "
        f"{bound:.4g} (a true equilibrium needs Omega^2 |x - v t| = Delta |sin k x| <= Delta; "
        f"the small excess is the onset of the slip)",
        "holds" if max_dev <= bound * 1.01 else "does not hold",
        {"max_stick_extension": max_dev, "bound": bound}))

    # 4. static friction equal to Delta
    sn = saddle_node(D, FIG5["lam"], Om)
    stat = [s.peak_force for s in a_c.slips if s.wells != 0]
    out.append(Claim(
        "static friction",
        "the static friction force is generally equal to the strength of the potential Delta",
        f"spring force at slip onset (CDC): {', '.join(f'{s:.4g}' for s in stat[:4])}; "
        f"quasi-static saddle node Delta sin(k x0) = {sn.static_force:.6g}; Delta = {D:g}",
        "holds" if stat and all(abs(s - D) < 0.02 * D for s in stat) else "partly",
        {"static_cdc": stat, "quasi_static": sn.static_force, "Delta": D}))

    # 5. SEDF dissipates less than CDC
    out.append(Claim(
        "dissipation",
        "the SEDF dissipation energy during the sliding motion is less than the CDC's",
        f"Gamma over t <= {t_end:g}: SEDF {a_s.gamma:.4g} (beta Gamma+ {a_s.gamma_plus:.4g}, "
        f"Gamma- {a_s.gamma_minus:.4g}), CDC {a_c.gamma:.4g}; work of the spring: SEDF "
        f"{sedf.work[-1]:.4g}, CDC {cdc.work[-1]:.4g}",
        "holds" if a_s.gamma < a_c.gamma else "does not hold",
        {"gamma_sedf": a_s.gamma, "gamma_cdc": a_c.gamma}))

    # 6. divergence outside |x| <= 1/sqrt(beta)
    xs = sedf.x
    inside = np.abs(xs) <= 1 / math.sqrt(FIG5["beta"])
    F = sedf.force
    mean_in = float(np.mean(F[inside])) if inside.any() else float("nan")
    late = sedf.t > 0.75 * t_end
    mean_late = float(np.mean(F[late]))
    x_late = float(np.mean(np.abs(xs[late])))
    grows = mean_late > 1.5 * mean_in
    out.append(Claim(
        "divergence (Fig. 6)",
        "outside the self-excitation range |x| <= 1/sqrt(beta) the friction diverges",
        f"mean spring force while |x| <= 1/sqrt(beta): {mean_in:.4g}; in the last quarter "
        f"(mean |x| = {x_late:.3g}): {mean_late:.4g}",
        "holds" if grows else "does not hold",
        {"mean_inside": mean_in, "mean_late": mean_late, "x_late": x_late}))
    return out
