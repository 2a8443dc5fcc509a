"""The errata section of the derivations (``derivations/errata.tex``), typeset.

:class:`ErratumRow` holds one erratum of :data:`kbm.output.paper.ERRATA` with its numerical
evidence (computed by :mod:`numerics.paper.errata`); :func:`errata_tex` prints the
section: the formula as printed, what differs (LaTeX text), and the evidence tables,
with the plain-text cases and quantities of the evidence typeset.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import sympy as sp

from .latex import align_block, equation_lines

__all__ = ["ErratumRow", "errata_tex"]


def _align(lines: Sequence[str]) -> str:
    return align_block(lines) + "\n"


@dataclass(frozen=True)
class ErratumRow:
    """One erratum, ready to print: the printed formula, what differs, the evidence.

    ``evidence`` holds ``(equation, case, quantity, printed, corrected, numerical)``
    tuples (the numerical value from the true limit cycle; ``equation`` is the paper's
    equation the quantity tests, e.g. ``"10"`` for the dissipation).
    """

    equation: str
    quantity: str
    printed: sp.Expr
    difference: str  # LaTeX text (math in $...$)
    evidence: tuple[tuple[str, str, str, float, float, float], ...]


def _num(v: float) -> str:
    """Numbers of the evidence tables: 4 significant digits, noise-level values as 0."""

    if v != v:
        return "--"
    if abs(v) < 1e-9:
        return "0"
    s = f"{v:.4g}"
    if "e" in s:
        m, e = s.split("e")
        return f"${m}\\times 10^{{{int(e)}}}$"
    return s


def _tex_text(s: str) -> str:
    return s.replace("_", r"\_").replace("^", r"\^{}").replace("&", r"\&")


#: the evidence's plain-text cases and quantities (numerics.paper.errata), typeset
_TEXT_TEX = {
    "small Delta/mu": r"small $\Delta/\mu$",
    "paper Fig. 3": r"paper Fig.~3",
    "frequency dpsi/dt at the true a": r"frequency $\dot\psi$ at the true $a$",
    "amplitude a* (root of da/dt)": r"amplitude $a^*$ (root of $\dot a$)",
    "stable (1) / unstable (0)": r"stable (1) / unstable (0)",
    "third harmonic of mu u_1 + mu^2 u_2 at the true a":
        r"third harmonic of $\mu u_1 + \mu^2 u_2$ at the true $a$",
    "mean of x (mu^2 u_2 at the true a)": r"mean of $x$ ($\mu^2 u_2$ at the true $a$)",
    "Gamma/Gamma_- over the reconstructed cycle":
        r"$\Gamma/\Gamma_-$ over the reconstructed cycle",
}


def _tex(s: str) -> str:
    """A case or quantity of the evidence typeset (plain text escaped if not known)."""
    return _TEXT_TEX.get(s, _tex_text(s))


_CORRECTED_REF = {"6": r"$\dot\psi = 1 + \mu B_1 + \mu^2 B_2$ of Section~1",
                  "7": r"$\dot a = \mu A_1 + \mu^2 A_2$ of Section~1",
                  "8": r"$f = u_1$ of Section~1", "9": r"$g = u_2$ of Section~1"}


def errata_tex(rows: Sequence[ErratumRow], width: int = 62) -> str:
    """The LaTeX of the errata section: each printed formula, what differs, the evidence."""
    out = [r"\section{Errata to the paper's eqs.~(6)--(9)}",
           r"""For each equation: the formula as printed in the paper, what differs from the
engine's derivation (Section~1), and the numerical evidence (for eq.~(9) also the
dissipation of eq.~(10) over the reconstructed cycle): the quantity the equation
predicts, from the printed formula, from the corrected one, and from the true limit cycle of
eq.~(3) (shooting, \texttt{kbm cycle}).  Functions of $a$ are evaluated at the true
first-harmonic amplitude.  Two cases: \emph{small $\Delta/\mu$} ($\mu=0.05$, $\Delta=0.1$,
$\beta=1$, $\lambda=1$), where the expansion is valid, and the paper's Fig.~3 case
($\mu=0.1$, $\Delta=1.5$, $\beta=1$, $\lambda=1$)."""]
    verdicts = []
    for r in rows:
        out.append(rf"\subsection*{{Eq.~({r.equation}): ${r.quantity}$}}")
        out.append("As printed:")
        lhs = {"6": r"\dot\psi", "7": r"\dot a", "8": "f(a,\\psi)", "9": "g(a,\\psi)"}[
            r.equation]
        out.append(_align([equation_lines(lhs, r.printed, width)]))
        out.append(f"Corrected: {_CORRECTED_REF.get(r.equation, 'Section 1')}. "
                   f"What differs: {r.difference}.")
        out.append(r"\begin{center}\small\begin{tabular}{lp{6.2cm}rrr}\toprule")
        out.append(r"case & quantity & printed & corrected & true \\ \midrule")
        for eqn, case, q, pr, co, nu in r.evidence:
            out.append(f"{_tex(case)} & {_tex(q)} & {_num(pr)} & {_num(co)} & "
                       f"{_num(nu)} \\\\")
            if q.startswith("stable"):
                continue
            ep, ec = abs(pr - nu), abs(co - nu)
            verdicts.append((eqn, case, q, ep, ec))
        out.append(r"\bottomrule\end{tabular}\end{center}")
    out.append(r"\subsection*{Verdicts}")
    out.append(r"\begin{center}\small\begin{tabular}{llp{5cm}rrl}\toprule")
    out.append(r"eq. & case & quantity & $|$printed$-$true$|$ & $|$corrected$-$true$|$ & "
               r"closer \\ \midrule")
    for eq, case, q, ep, ec in verdicts:
        closer = "corrected" if ec < ep else ("printed" if ep < ec else "equal")
        out.append(f"({eq}) & {_tex(case)} & {_tex(q)} & {_num(ep)} & {_num(ec)} & "
                   f"{closer} \\\\")
    out.append(r"\bottomrule\end{tabular}\end{center}")
    return "\n".join(out) + "\n"
