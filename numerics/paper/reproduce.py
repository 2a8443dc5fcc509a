"""The main job as a library function: :func:`reproduce`.

Regenerates the derivations (LaTeX, and the PDF when pdflatex is installed),
computes the analytic-versus-numeric tables for the paper's cases and for
small-parameter cases, runs the paper's sliding experiments and checks its
claims, writes every figure, and writes a summary.  ``kbm reproduce`` calls it.
"""

from __future__ import annotations

import shutil
import sys
import time
from pathlib import Path

from kbm.output.derivations import compile_pdf, write_derivations
from kbm.output.files import output_folder
from kbm.output.paper import COMPARISON_CASES

from kbm.output.strict_json import strict_text
from numerics.comparison import compare, convergence_study, energy_prediction
from numerics.comparison.fixed_delta import fixed_delta_convergence
from numerics.paper.claims import check_claims
from numerics.paper.errata import errata_evidence, errata_rows, evidence_table
from numerics.paper.friction import MAIN_JOB_SIZE, friction_study
from numerics.paper.figures import FIGURES, write_figures
from numerics.paper.figures.comparison import validity_figure
from numerics.paper.figures.friction import study_figures
from numerics.paper.figures.methods import fixed_delta_figure, methods_figure
from numerics.paper.methods import methods_map
from numerics.paper.printed import paper_prediction
from numerics.paper.report import md_table, summary_markdown
from numerics.paper.validity import validity_map

__all__ = ["reproduce"]


class _Progress:
    def __init__(self, total: int):
        self.total, self.i, self.t0 = total, 0, time.perf_counter()

    def stage(self, what: str):
        self.i += 1
        self.t = time.perf_counter()
        print(f"[{self.i}/{self.total}] {what} ...", file=sys.stderr, flush=True)

    def done(self, detail: str = ""):
        dt = time.perf_counter() - self.t
        print(f"      done in {dt:.1f} s{': ' + detail if detail else ''}", file=sys.stderr,
              flush=True)


def screen_summary(summary: list[str], claims_md: str) -> str:
    """One screen of the main job's results: the sections written (the file holds them
    whole) and the paper's claims with their verdicts."""
    sections = [line[3:] for line in summary if line.startswith("## ")]
    rows = [line for line in claims_md.splitlines() if line.startswith("|")][2:]
    verdicts = []
    for row in rows:
        cells = [c.strip() for c in row.strip("|").split("|")]
        verdicts.append(f"  {cells[0]}: {cells[-1]}")
    return "\n".join(["", "summary.md holds:", *[f"  - {s}" for s in sections], "",
                      "the paper's claims:", *verdicts])




def reproduce(out: str | Path = "out", *, pdf: bool = True) -> Path:
    """The main job: errata evidence, derivations (and PDF), KBM versus the true cycles,
    convergence orders, the validity map, the sliding experiments and claims, every
    figure, and a summary.

    Progress goes to standard error, one line per stage, with the time each took.

    Parameters
    ----------
    out
        Output folder: ``derivations/``, ``tables/``, ``figures/``, ``summary.md``.
    pdf
        Run pdflatex on the derivations when it is installed.

    Returns
    -------
    pathlib.Path
        The summary file (its text is also printed).

    Raises
    ------
    kbm.errors.OutputError
        If ``out`` is a file or cannot be written to (before any computation).
    """
    out = output_folder(out, "out")
    output_folder(out / "tables", "out")
    prog = _Progress(10)
    pdf_path = None

    prog.stage("errata: the paper's eqs. (6)-(9) against the engine and the true cycles")
    evidence = errata_evidence()
    rows = [[r.equation, r.case, r.quantity, f"{r.printed:.6g}", f"{r.corrected:.6g}",
             f"{r.numeric:.6g}",
             "corrected" if r.corrected_error < r.printed_error else
             ("printed" if r.printed_error < r.corrected_error else "equal")]
            for r in evidence]
    errata_md = md_table(["eq.", "case", "quantity", "printed", "corrected", "true",
                           "closer to the truth"], rows)
    (out / "tables" / "errata.md").write_text(errata_md)
    (out / "tables" / "errata.txt").write_text(evidence_table(evidence) + "\n")
    wins = sum(r[-1] == "corrected" for r in rows if not r[2].startswith("stable"))
    total = sum(1 for r in rows if not r[2].startswith("stable"))
    prog.done(f"{wins}/{total} comparisons favour the corrected formulas")

    prog.stage("derivations: LaTeX from the engine (and the PDF)")
    paths = write_derivations(out / "derivations", errata_rows(evidence))
    detail = f"{len(paths)} files in {out / 'derivations'}"
    if pdf and shutil.which("pdflatex"):
        pdf_path = compile_pdf(out / "derivations" / "main.tex")
        detail += f"; PDF {pdf_path}"
    elif pdf:
        detail += "; pdflatex not installed, no PDF (Debian: texlive-latex-base)"
    prog.done(detail)

    prog.stage("KBM versus the true limit cycles")
    comp_md, comp_json, cases = [], [], []
    for label, model, params in COMPARISON_CASES:
        extra = [paper_prediction] if model == "sedf" else []
        c = compare(model, params, orders=(1, 2) if model == "sedf" else (1, 2, 3, 4),
                    extra=extra + [energy_prediction(1), energy_prediction(2)])
        comp_md += [f"### {label}", "", "```", c.table(), "```", ""]
        comp_json.append({"case": label, **c.to_json()})
        cases.append((label, c))
    (out / "tables" / "comparison.md").write_text("\n".join(comp_md))
    (out / "tables" / "comparison.json").write_text(strict_text(comp_json))
    prog.done(f"{len(COMPARISON_CASES)} cases")

    prog.stage("convergence orders of the KBM errors")
    conv = [convergence_study("vdp", [0.025, 0.05, 0.1], orders=(1, 2, 3)),
            convergence_study("sedf", [0.025, 0.05, 0.1], orders=(1, 2),
                              fixed={"delta": 2, "beta": 1, "k": "2*pi"})]
    conv_text = "\n\n".join("```\n" + c.table() + "\n```" for c in conv)
    (out / "tables" / "convergence.md").write_text(conv_text + "\n")
    prog.done()

    prog.stage("averaging about the conservative orbit at fixed Delta: errors against mu")
    fixed = fixed_delta_convergence()
    (out / "tables" / "fixed_delta.md").write_text("```\n" + fixed.table() + "\n```\n")
    (out / "tables" / "fixed_delta.json").write_text(strict_text(fixed.to_json()))
    prog.done(f"{len(fixed.studies)} (Delta, beta) cases")

    prog.stage("where classical KBM and the energy method hold (sweep on all cores)")
    mm = methods_map(progress=False)
    (out / "tables" / "methods.md").write_text("```\n" + mm.table() + "\n```\n")
    (out / "tables" / "methods.json").write_text(strict_text(mm.to_json()))
    prog.done()

    prog.stage("validity map of KBM orders 1 and 2 for the SEDF (sweep on all cores)")
    vm = validity_map(progress=False)
    (out / "tables" / "validity.md").write_text("```\n" + vm.table() + "\n```\n")
    (out / "tables" / "validity.json").write_text(strict_text(vm.to_json()))
    prog.done()

    prog.stage("the paper's sliding experiments and claims (SEDF versus CDC)")
    claims = check_claims()
    claims_md = md_table(["claim", "the paper says", "measured", "verdict"],
                          [c.row() for c in claims])
    (out / "tables" / "claims.md").write_text(claims_md)
    prog.done(", ".join(f"{c.key}: {c.verdict}" for c in claims))

    prog.stage("friction laws and maps: does self-excitation lower friction? (all cores)")
    study = friction_study(**MAIN_JOB_SIZE)
    (out / "tables" / "friction.md").write_text(study.table())
    (out / "tables" / "friction.json").write_text(strict_text(study.to_json()))
    prog.done()

    prog.stage("figures")
    reused = ("validity_map", "methods_map", "fixed_delta_convergence", "friction")
    figs = write_figures(out / "figures", [n for n in FIGURES if n not in reused],
                         progress=lambda n: print(f"      {n}", file=sys.stderr, flush=True))
    # the figures of the maps and studies computed above, without computing them again
    figs += methods_figure(out / "figures", mmap=mm)
    figs += fixed_delta_figure(out / "figures", conv=fixed)
    figs += validity_figure(out / "figures", vmap=vm)
    figs += study_figures(study, out / "figures")
    prog.done(f"{len(figs)} files in {out / 'figures'}")

    text = summary_markdown(out, figs, claims=claims, errata=evidence, cases=cases,
                            convergence=conv, fixed=fixed, methods=mm, validity=vm,
                            friction=study, pdf=pdf_path)
    summary = text.splitlines()
    (out / "summary.md").write_text(text)
    print(screen_summary(summary, claims_md))
    print(f"\nwritten: {out}/summary.md, {out}/tables/, {out}/figures/, {out}/derivations/ "
          f"(total {time.perf_counter() - prog.t0:.0f} s)")
    return out / "summary.md"

