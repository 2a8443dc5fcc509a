"""``summary.md`` of ``kbm reproduce`` is a report (issue 40 item 4): each section opens with
its conclusion, the tables are short, no code block of a hundred rows, the figures are
embedded by links relative to ``summary.md`` that exist, and the long tables are linked in
``tables/``.  The conclusions are counted again here from the same points (an independent
count, not the report's code)."""

from __future__ import annotations

import re

import numpy as np
import pytest

from numerics.comparison import compare, energy_prediction
from numerics.comparison.fixed_delta import FixedDeltaConvergence, FixedDeltaStudy
from numerics.paper.claims import Claim
from numerics.paper.errata import ErratumEvidence
from numerics.paper.methods import METHODS, MethodsMap, MethodsPoint
from numerics.paper.report import summary_markdown
from numerics.paper.validity import ValidityMap, ValidityPoint, short_reason

#: the message of the sweep at (mu, Delta, beta) = (0.5, 3, 1) in the main job (issue 40:
#: about 450 characters repeating one sentence three times)
SWEEP_MESSAGE = (
    "transient from x = 2.08993: no limit cycle: the motion settles to rest at x = 1.89143 "
    "(an equilibrium of the potential; x varies by 6.66e-16 over T = 1.867); start elsewhere "
    "(x_start) to look for a cycle; transient from x = 2: no limit cycle: the motion settles "
    "to rest at x = 1.89143 (an equilibrium of the potential; x varies by 2.22e-15 over T = "
    "0.9506); start elsewhere (x_start) to look for a cycle; transient from x = 4: no limit "
    "cycle: the motion decays to rest (max x fell from 4 to 1.89 by t = 25258.4)")

MUS, DELTAS = (0.01, 0.1), (0.1, 1.5, 3.0)


def test_short_reason_says_each_reason_once():
    short = short_reason(SWEEP_MESSAGE)
    assert short == ("the motion settles to rest at x = 1.89143 or the motion decays to rest "
                     "(from x = 2.08993, 2, 4)")
    assert short_reason("Newton did not converge") == "Newton did not converge"


def _methods_map() -> MethodsMap:
    """A 2 x 3 grid at beta = 1: the errors grow with Delta/mu for classical KBM, and stay
    small for the energy method; no true cycle at (0.1, 3)."""
    pts = []
    for m in MUS:
        for D in DELTAS:
            if (m, D) == (0.1, 3.0):
                pts.append(MethodsPoint({"mu": m, "Delta": D, "beta": 1.0}, False,
                                        SWEEP_MESSAGE, np.nan, np.nan,
                                        dict.fromkeys(METHODS, np.nan)))
                continue
            k = 1e-2 * D / m / 10
            errs = {"KBM order 1": k, "KBM order 2": k / 3, "energy order 1": m * 1e-2,
                    "energy order 2": m**2 * 1e-2}
            pts.append(MethodsPoint({"mu": m, "Delta": D, "beta": 1.0}, True, "", 2.0, 1.0,
                                    errs))
    return MethodsMap(axes={"mu": MUS, "Delta": DELTAS, "beta": (1.0,)}, points=tuple(pts))


def _validity_map(mm: MethodsMap) -> ValidityMap:
    pts = tuple(ValidityPoint(p.params, p.success, p.message, p.amplitude, p.frequency,
                              {N: {"max": p.errors[f"KBM order {N}"]} for N in (1, 2)})
                for p in mm.points)
    return ValidityMap((1, 2), mm.axes, pts)


def _fixed() -> FixedDeltaConvergence:
    eps = (0.2, 0.1, 0.05)
    rows = ("energy order 1", "KBM order 1")
    keys = ("frequency",)
    e = np.array(eps)
    errors = {("energy order 1", "frequency"): e**2, ("KBM order 1", "frequency"): 0 * e + .1}
    slopes = {("energy order 1", "frequency"): 2.01, ("KBM order 1", "frequency"): -0.02}
    predicted = {("energy order 1", "frequency"): 2, ("KBM order 1", "frequency"): None}
    s = FixedDeltaStudy(1.5, 1.0, eps, rows, keys, errors, errors, slopes, predicted,
                        ("", "", ""), 1e-9)
    return FixedDeltaConvergence((s,))


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    out = tmp_path_factory.mktemp("out")
    (out / "figures").mkdir()
    names = ["methods_map.png", "kbm_validity.png", "fixed_delta_convergence.png",
             "kbm_phase_fig3.png", "fig2_potential.png", "fig6_kinetic_friction.png"]
    figs = []
    for n in names:
        (out / "figures" / n).write_bytes(b"\x89PNG\r\n\x1a\n")
        figs.append(out / "figures" / n)
    claims = [Claim("peak friction (Fig. 5)", "about 5 times smaller", "ratio 0.978",
                    "does not hold", {}),
              Claim("stick condition", "no stick for |x - v t| > Delta", "3.005",
                    "holds", {})]
    errata = [ErratumEvidence("7", "amplitude a*", "paper Fig. 3", {}, 2.13, 2.07, 2.04),
              ErratumEvidence("6", "frequency", "paper Fig. 3", {}, 0.9997, 0.9123, 0.9045)]
    cases = [("van der Pol, mu = 0.1",
              compare("vdp", {"mu": 0.1}, orders=(1, 2), extra=[energy_prediction(1)]))]
    mm = _methods_map()
    text = summary_markdown(out, figs, claims=claims, errata=errata, cases=cases,
                            fixed=_fixed(), methods=mm, validity=_validity_map(mm))
    return out, text, figs, mm, cases


def test_every_section_opens_with_its_conclusion_and_no_line_is_a_dump(report):
    _, text, *_ = report
    lines = text.splitlines()
    assert "```" not in text  # no code block: tables are markdown, the long ones in tables/
    assert max(len(ln) for ln in lines) <= 300, max(lines, key=len)
    heads = [i for i, ln in enumerate(lines) if ln.startswith("## ")]
    assert len(heads) >= 6
    for i in heads:
        first = next(ln for ln in lines[i + 1:] if ln.strip())
        if "figures" not in lines[i]:
            assert first.startswith("**") and first.endswith("**"), (lines[i], first)
    # each table short
    rows = 0
    for ln in lines + [""]:
        rows = rows + 1 if ln.startswith("|") else 0
        assert rows <= 22
    assert text.count("settles to rest") == 2  # once per map, not three times per point


def test_figures_are_embedded_relative_to_the_summary_and_exist(report):
    out, text, figs, *_ = report
    links = re.findall(r"!\[[^\]]*\]\(([^)]+)\)", text)
    assert sorted(links) == sorted(f"figures/{p.name}" for p in figs)  # each exactly once
    for link in links:
        assert (out / link).is_file()
    for table in re.findall(r"\]\((tables/[^)]+)\)", text):
        assert table.endswith((".md", ".json"))


def test_the_conclusions_count_the_points(report):
    """The counts in the methods section, recounted from the points: a method is within 1 %
    where its error is <= 1e-2 on a point with a true cycle."""
    _, text, _, mm, cases = report
    ok = [p for p in mm.points if p.success]
    for m in METHODS:
        n = sum(p.errors[m] <= 1e-2 for p in ok)
        assert f"{m} at {n}" in text or f"{m} is within 1 % at {n}" in text, m
    assert f"Of {len(ok)} true cycles" in text
    assert "No true cycle at (mu, Delta, beta) = (0.1, 3, 1)" in text
    comp = cases[0][1]
    worst = {p.label: max(comp.relative_error(p, k) for k in ("amplitude", "amplitude_max",
                                                              "frequency"))
             for p in comp.predictions}
    best = min(worst, key=worst.get)
    assert f"The best prediction: {best} in 1 of 1 cases (error at most {worst[best]:.1e})" \
        in text
    assert "1 of 2 claims hold: stick condition" in text
    assert "closer to the true cycle in 2 of 2 comparisons" in text
