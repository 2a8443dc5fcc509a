"""The report of ``kbm reproduce``: ``summary.md``, read top to bottom.

Each section opens with its conclusion (one sentence in bold, computed from the results),
then a short table or the figure that shows it (embedded, a link relative to
``summary.md``), and links the full table in ``tables/``.  The long tables (one row per
grid point) stay in ``tables/``; the summary holds counts, slopes and verdicts.

:func:`summary_markdown` builds the text from the results of
:func:`numerics.paper.reproduce.reproduce`; a result that is ``None`` leaves its section
out.
"""

from __future__ import annotations

import math
import re
import statistics
from collections.abc import Sequence
from pathlib import Path

from numerics.paper.validity import VALIDITY_KEYS, short_reason

__all__ = ["summary_markdown", "md_table", "FIGURE_CAPTIONS"]

#: one line per figure of the main job, by file name
FIGURE_CAPTIONS = {
    "fig2_potential.png": "The paper's Fig. 2: the substrate potential.",
    "fig3_phase_portraits.png": "The paper's Fig. 3: phase portraits of the undriven SEDF.",
    "fig4_sliding.png": "The paper's Fig. 4: the SEDF pulled at v = 0.1.",
    "fig5_sedf_vs_cdc.png": "The paper's Fig. 5: SEDF against CDC at v = 0.01.",
    "fig6_kinetic_friction.png": "The paper's Fig. 6: the SEDF's kinetic friction.",
    "sedf_branches_delta.png": "Branches of SEDF limit cycles against Delta (continuation, "
                               "special points).",
    "sedf_branches_beta.png": "Branches of SEDF limit cycles against beta.",
    "kbm_convergence.png": "Errors of the KBM orders against mu (dotted: the predicted "
                           "slopes).",
    "kbm_phase_fig3.png": "The paper's Fig. 3 parameters: KBM cycles and the paper's eqs. "
                          "(5)-(9) against the true cycle.",
    "kbm_phase_small.png": "Small Delta and van der Pol: KBM cycles against the true cycle.",
    "methods_map.png": "Where classical KBM (K1, K2) and the energy method (E1, E2) are "
                       "within 1 % and 1e-3 of the true cycle.",
    "fixed_delta_convergence.png": "Fixed Delta: relative errors against mu, fitted slopes "
                                   "in the legends.",
    "kbm_validity.png": "Relative error of KBM orders 1 and 2 over (mu, Delta).",
    "friction_law_delta1.5.png": "Friction laws at Delta = 1.5.",
    "friction_law_delta3.png": "Friction laws at Delta = 3.",
    "friction_map_v_delta.png": "SEDF against CDC over (v, Delta), beta = 1.",
    "friction_map_v_beta.png": "SEDF against CDC over (v, beta), Delta = 3.",
}

#: the error of a point in the maps: the largest relative error of these
_ERROR_OF = "the largest relative error of the first-harmonic amplitude a, max x and " \
            "the frequency"


def md_table(header: Sequence[str], rows: Sequence[Sequence[str]]) -> str:
    """A markdown table (``|`` in a cell escaped)."""
    out = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    out += ["| " + " | ".join(str(c).replace("|", "\\|") for c in r) + " |" for r in rows]
    return "\n".join(out) + "\n"


def _median(pairs) -> float:
    vals = [v for v, _ in pairs if math.isfinite(v)]
    return statistics.median(vals) if vals else math.nan


def _bold(text: str) -> str:
    return f"**{text}**"


def _figure(name: str, figures: dict[str, str]) -> list[str]:
    """An embedded figure with its caption, when it was written."""
    if name not in figures:
        return []
    caption = FIGURE_CAPTIONS.get(name, name)
    return [f"![{caption}]({figures[name]})", "", f"*{caption}*", ""]


def _link(name: str, what: str = "the full table") -> str:
    return f"{what[0].upper()}{what[1:]}: [tables/{name}](tables/{name})."


# ------------------------------------------------------------------------------ sections
def _claims(claims) -> list[str]:
    held = [c.key for c in claims if c.verdict == "holds"]
    head = f"{len(held)} of {len(claims)} claims hold: {', '.join(held) or 'none'}"
    for verdict in sorted({c.verdict for c in claims} - {"holds"}):
        head += f"; {verdict}: " + ", ".join(c.key for c in claims if c.verdict == verdict)
    rows = [[c.key, c.verdict, c.paper] for c in claims]
    return ["## The paper's claims", "", _bold(head + "."), "",
            md_table(["claim", "verdict", "the paper says"], rows),
            _link("claims.md", "the numbers measured for each claim"), ""]


def _errata(evidence) -> list[str]:
    def closer(r):
        if r.corrected_error < r.printed_error:
            return "corrected"
        return "printed" if r.printed_error < r.corrected_error else "equal"
    compared = [r for r in evidence if not r.quantity.startswith("stable")]
    wins = sum(closer(r) == "corrected" for r in compared)
    rows = [[r.equation, r.case, r.quantity, f"{r.printed:.6g}", f"{r.corrected:.6g}",
             f"{r.numeric:.6g}", closer(r)] for r in evidence]
    return ["## Errata (paper eqs. 6-9; eq. 10: the dissipation)", "",
            _bold(f"The corrected formula is closer to the true cycle in {wins} of "
                  f"{len(compared)} comparisons."), "",
            md_table(["eq.", "case", "quantity", "printed", "corrected", "true",
                      "closer to the truth"], rows),
            _link("errata.md", "the same table") + " The derivations: "
            "[derivations/](derivations/).", ""]


def _worst(comp, p) -> float:
    if not p.success:
        return math.nan
    errs = [comp.relative_error(p, k) for k in VALIDITY_KEYS]
    return max((e for e in errs if math.isfinite(e)), default=math.nan)


def _fmt(e: float) -> str:
    return "no cycle" if not math.isfinite(e) else f"{e:.1e}"


def _comparison(cases, figures) -> list[str]:
    labels: list[str] = []
    for _, comp in cases:
        labels += [p.label for p in comp.predictions if p.label not in labels]
    rows, best = [], {}
    for case, comp in cases:
        errs = {p.label: _worst(comp, p) for p in comp.predictions}
        rows.append([case] + [_fmt(errs[lab]) if lab in errs else "-" for lab in labels])
        ok = {k: v for k, v in errs.items() if math.isfinite(v)}
        if ok:
            b = min(ok, key=ok.get)
            best.setdefault(b, []).append(ok[b])
    head = "The best prediction: " + "; ".join(
        f"{b} in {len(e)} of {len(cases)} cases (error at most {max(e):.1e})"
        for b, e in sorted(best.items(), key=lambda t: -len(t[1]))) + "."
    return ["## KBM and the energy method against the true limit cycles", "",
            _bold(head), "",
            f"Each cell: {_ERROR_OF}.", "",
            md_table(["case", *labels], rows), *_figure("kbm_phase_fig3.png", figures),
            *_figure("kbm_phase_small.png", figures),
            _link("comparison.md", "every quantity of every case (harmonics, Floquet "
                  "multiplier, dissipation)"), ""]


def _convergence(studies, figures) -> list[str]:
    rows, dev = [], []
    for s in studies:
        keys = [k for k in _ORDERED_KEYS if any(k == q for _, q in s.slopes)]
        for N in s.orders:
            rows.append([s.model, str(N)] + [f"{s.slopes[(N, k)]:.2f} ({s.predicted[(N, k)]})"
                                             for k in keys])
            dev += [(abs(s.slopes[(N, k)] - s.predicted[(N, k)]), f"{s.model} order {N}, {k}")
                    for k in keys]
        header = ["model", "order", *keys]
    worst = max(dev, key=lambda t: t[0], default=(math.nan, ""))
    return ["## Convergence orders of KBM", "",
            _bold(f"The fitted slopes of log|error| against log mu match the orders the "
                  f"theory predicts: median deviation {_median(dev):.2f}, largest "
                  f"{worst[0]:.2f} ({worst[1]})."), "",
            "Fitted slope (predicted order); mu = 0.025, 0.05, 0.1; the SEDF at fixed "
            "delta = Delta/mu = 2.", "",
            md_table(header, rows), *_figure("kbm_convergence.png", figures),
            _link("convergence.md"), ""]


_ORDERED_KEYS = ("amplitude", "amplitude_max", "frequency", "harmonic3", "floquet_exponent",
                 "dissipation")


def _fixed_delta(conv, figures) -> list[str]:
    rows, energy_dev, kbm = [], [], []
    rows_of = list(conv.studies[0].rows) if conv.studies else []
    for s in conv.studies:
        cells = []
        for r in rows_of:
            sl, p = s.slopes[(r, "frequency")], s.predicted[(r, "frequency")]
            cells.append(f"{sl:.2f}" + (f" ({p})" if p is not None else ""))
            if p is not None and math.isfinite(sl):
                energy_dev.append((abs(sl - p), f"{r} at Delta = {s.Delta:g}, "
                                                f"beta = {s.beta:g}"))
            elif p is None and math.isfinite(sl):
                kbm.append(abs(sl))
        rows.append([f"{s.Delta:g}", f"{s.beta:g}", *cells])
    worst = max(energy_dev, key=lambda t: t[0], default=(math.nan, ""))
    head = (f"At fixed Delta the energy method converges at its predicted orders (median "
            f"|slope - order| {_median(energy_dev):.2f}; largest {worst[0]:.2f}, {worst[1]}); "
            f"classical KBM does not (|slope| at most {max(kbm, default=math.nan):.2f}), "
            "because delta = Delta/mu grows as mu falls.")
    return ["## The energy method at fixed Delta", "", _bold(head), "",
            "Fitted slope of the frequency's error against mu (predicted order):", "",
            md_table(["Delta", "beta", *rows_of], rows),
            *_figure("fixed_delta_convergence.png", figures),
            _link("fixed_delta.md", "the slopes of every quantity"), ""]


def _no_cycle(points) -> list[str]:
    """The points without a true cycle, grouped by the reason."""
    by_reason: dict[str, list[str]] = {}
    for p in points:
        if not p.success:
            pr = p.params
            by_reason.setdefault(short_reason(p.message), []).append(
                f"({pr['mu']:g}, {pr['Delta']:g}, {pr['beta']:g})")
    if not by_reason:
        return []
    return ["No true cycle at (mu, Delta, beta) = "
            + "; at ".join(f"{', '.join(where)}: {why}" for why, where in by_reason.items())
            + ".", ""]


def _methods(mm, figures) -> list[str]:
    from numerics.paper.methods import METHODS

    summ = mm.summary()
    rows = [[b, str(row["true cycles"])]
            + [f"{row[f'{m} within 0.01']} / {row[f'{m} within 0.001']}" for m in METHODS]
            for b, row in summ.items()]
    n = sum(r["true cycles"] for r in summ.values())
    within = {m: sum(r[f"{m} within 0.01"] for r in summ.values()) for m in METHODS}
    ranked = sorted(METHODS, key=lambda m: -within[m])
    head = (f"Of {n} true cycles, {ranked[0]} is within 1 % at {within[ranked[0]]}; then "
            + ", ".join(f"{m} at {within[m]}" for m in ranked[1:])
            + ": the energy method keeps Delta in the conservative orbit, classical KBM "
            "expands in it.")
    return ["## Where each method is within 1 % and 1e-3 of the true cycle", "",
            _bold(head), "",
            f"True cycles, and for each method the points within 1 % / within 1e-3 "
            f"({_ERROR_OF}):", "",
            md_table(["beta", "true cycles", *METHODS], rows), *_no_cycle(mm.points),
            *_figure("methods_map.png", figures),
            _link("methods.md", "the error of every method at every point"), ""]


def _validity(vm, figures) -> list[str]:
    rows = []
    for b in vm.axes["beta"]:
        pts = [p for p in vm.points if p.params["beta"] == b and p.success]
        rows.append([f"{b:g}", str(len(pts))]
                    + [f"{sum(p.error(N) <= 1e-2 for p in pts)} / "
                       f"{sum(p.error(N) <= 1e-3 for p in pts)}" for N in vm.orders])
    ok = [p for p in vm.points if p.success]
    counts = ", ".join(f"order {N} at {sum(p.error(N) <= 1e-2 for p in ok)}" for N in vm.orders)
    top = []
    for N in vm.orders:
        ds = [p.params["Delta"] for p in ok if p.params["mu"] == 0.1 and p.error(N) <= 1e-2]
        top.append(f"order {N} up to Delta = {max(ds):g}" if ds else f"order {N} nowhere")
    head = (f"Of {len(ok)} true cycles classical KBM is within 1 % at {counts}; at the "
            f"paper's mu = 0.1, {', '.join(top)}.")
    return ["## Validity map of classical KBM", "", _bold(head), "",
            "The KBM columns of the section above, on the documentation's grid.", "",
            md_table(["beta", "true cycles", *[f"KBM order {N}: within 1 % / 1e-3"
                                                for N in vm.orders]], rows),
            *_no_cycle(vm.points), *_figure("kbm_validity.png", figures),
            _link("validity.md", "every point"), ""]


def _friction(study, figures) -> list[str]:
    parts = [f"over {axes} at {fixed} the SEDF has the lower friction and dissipation at "
             f"{s['first_better']} of {s['compared']} points compared "
             f"({s['first_better_steady']} of them steady)" for axes, fixed, s in study.verdicts()]
    head = "Does self-excitation lower friction? " + "; ".join(parts) + "."
    head = head.replace("? over", "? Over")
    out = ["## Friction laws and maps (SEDF against CDC)", "", _bold(head), "",
           "Maps of 8 x 8 points here (32 x 32 in the docs).", "", study.table()]
    for name in ("friction_law_delta1.5.png", "friction_law_delta3.png",
                 "friction_map_v_delta.png", "friction_map_v_beta.png"):
        out += _figure(name, figures)
    return out + [_link("friction.md", "the same tables") + " Every point: "
                  "[tables/friction.json](tables/friction.json).", ""]


def _relative(path, out: Path) -> str:
    """``path`` relative to the folder ``out`` (as written in markdown), or as given."""
    p, o = Path(path).resolve(), out.resolve()
    return p.relative_to(o).as_posix() if p.is_relative_to(o) else str(path)


def summary_markdown(out: Path, figures: Sequence[Path] = (), *, claims=None,
                     errata=None, cases=None, convergence=None, fixed=None, methods=None,
                     validity=None, friction=None, pdf: Path | None = None) -> str:
    """The text of ``summary.md`` in the folder ``out``.

    Parameters
    ----------
    out
        The folder of ``summary.md``: figure links are relative to it.
    figures
        The figure files written (PNG ones are embedded: in their section, the others at
        the end).
    claims, errata, cases, convergence, fixed, methods, validity, friction
        The results (:func:`numerics.paper.claims.check_claims`,
        :func:`numerics.paper.errata.errata_evidence`, ``[(label, Comparison)]``,
        convergence studies, :class:`~numerics.comparison.fixed_delta.FixedDeltaConvergence`,
        :class:`~numerics.paper.methods.MethodsMap`,
        :class:`~numerics.paper.validity.ValidityMap`,
        :class:`~numerics.paper.friction.FrictionStudy`); ``None`` leaves a section out.
    pdf
        The derivations' PDF, when compiled.
    """
    out = Path(out)
    rel = {Path(p).name: _relative(p, out) for p in figures if Path(p).suffix == ".png"}
    pdf_link = f" (PDF: [{Path(pdf).name}]({_relative(pdf, out)}))" if pdf else ""
    lines = ["# kbm reproduce: the paper's sliders against their true cycles", "",
             "Each section opens with its conclusion, then a short table or a figure. The full "
             "tables are in [tables/](tables/), the figures in [figures/](figures/), the "
             f"LaTeX derivations in [derivations/](derivations/){pdf_link}.", ""]
    for result, section in ((claims, _claims), (errata, _errata)):
        lines += section(result) if result is not None else []
    for result, section in ((cases, _comparison), (convergence, _convergence),
                            (fixed, _fixed_delta), (methods, _methods), (validity, _validity),
                            (friction, _friction)):
        lines += section(result, rel) if result is not None else []
    shown = {m.group(1) for m in re.finditer(r"\]\(([^)]+\.png)\)", "\n".join(lines))}
    rest = [n for n, r in rel.items() if r not in shown]
    if rest:
        lines += ["## The paper's figures and the other figures", ""]
        for n in sorted(rest):
            lines += _figure(n, rel)
    return "\n".join(lines).rstrip() + "\n"
