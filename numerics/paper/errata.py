"""Numerical evidence for the errata of the paper's eqs. (6)-(9) (:data:`kbm.output.paper.ERRATA`).

For each erratum, the quantity it affects is computed three ways at the same
parameters: from the formula as printed, from the engine's corrected formula
(:func:`kbm.output.paper.corrected`, derived at call time), and from the true limit
cycle (:func:`numerics.limit_cycle`).  Formulas that are functions of ``a`` are
evaluated at the *true* first-harmonic amplitude, so that each row isolates one
equation:

- eq. (6): ``dpsi/dt`` at ``a`` vs the true frequency ``2 pi/T``;
- eq. (7): the root ``a*`` of the amplitude equation (closest to the true ``a``)
  vs the true first-harmonic amplitude, and the sign of its slope (stability);
- eq. (8): the third-harmonic amplitude of ``mu f + mu^2 g`` (printed) or
  ``mu u_1 + mu^2 u_2`` (corrected) vs that of the true cycle;
- eq. (9): the mean of ``mu^2 g`` (printed) or ``mu^2 u_2`` (corrected) vs the mean of
  the true ``x``;
- eq. (10) over eqs. (5)-(9): the dissipation ``Gamma`` per cycle over the orbit
  the paper's formulas reconstruct, over the order-2 KBM orbit, and over the true
  cycle (0 to integration accuracy), relative to ``Gamma_-``.

:data:`kbm.output.paper.ERRATA_CASES`: a case where the expansion is valid (``mu = 0.05, Delta = 0.1``,
``Delta/mu = 2``) and the paper's Fig. 3 case (``mu = 0.1, Delta = 1.5``).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import sympy as sp

from kbm.output.paper import ERRATA_CASES
from kbm.output.strict_json import Rendered

__all__ = ["ErratumEvidence", "errata_evidence", "errata_rows", "evidence_table"]


@dataclass(frozen=True)
class ErratumEvidence(Rendered):
    """One quantity of one erratum at one case: printed, corrected and true values.

    Attributes
    ----------
    equation
        The paper's equation (``"6"`` ... ``"9"``, or ``"10"`` for ``Gamma``).
    quantity
        What is compared.
    case, params
        Case name and its physical parameters.
    printed, corrected, numeric
        The value from the formula as printed, from the engine, and from the true cycle.
    success, message
        Whether the true cycle converged, and how.
    """

    equation: str
    quantity: str
    case: str
    params: Mapping[str, float]
    printed: float
    corrected: float
    numeric: float
    success: bool = True
    message: str = ""

    layout = ("equation", "quantity", "case", "params", "printed", "corrected", "numeric",
              "printed_error", "corrected_error", "success", "message")
    mappings_as_given = True

    @property
    def printed_error(self) -> float:
        return abs(self.printed - self.numeric)

    @property
    def corrected_error(self) -> float:
        return abs(self.corrected - self.numeric)


def _harmonic(values: np.ndarray, m: int) -> float:
    c = np.fft.rfft(values) / values.size
    return float(abs(c[0])) if m == 0 else float(2 * abs(c[m]))


def _root(fun, target: float, a_max: float = 20.0, n: int = 20000) -> tuple[float, float]:
    from scipy.optimize import brentq

    grid = np.linspace(a_max / n, a_max, n)
    g = fun(grid) / grid
    idx = np.nonzero(np.sign(g[:-1]) * np.sign(g[1:]) < 0)[0]
    roots = [brentq(lambda s: float(fun(s)) / s, grid[i], grid[i + 1], xtol=1e-15) for i in idx]
    if not roots:
        return float("nan"), float("nan")
    r = min(roots, key=lambda s: abs(s - target))
    h = 1e-6 * max(1.0, r)
    return r, float((fun(r + h) - fun(r - h)) / (2 * h))


def errata_evidence(cases: Sequence[tuple[str, Mapping[str, float]]] = ERRATA_CASES,
                    *, n_samples: int = 1024) -> list[ErratumEvidence]:
    """Printed vs corrected vs true values for each erratum of :data:`kbm.output.paper.ERRATA`.

    Parameters
    ----------
    cases
        ``(name, physical sedf parameters)`` pairs (``mu``, ``Delta``, ``beta``, ``lam``;
        ``Omega = 1`` as in the paper).

    Returns
    -------
    list of ErratumEvidence
        For each case: rows for eqs. 6, 7 (amplitude and stability), 8, 9 and 10.

    Examples
    --------
    >>> ev = errata_evidence(ERRATA_CASES[:1])
    >>> row = next(r for r in ev if r.equation == "6")
    >>> row.corrected_error < row.printed_error
    True
    """
    from kbm.output import paper
    from kbm.output.evaluate import numpy_function

    from numerics.comparison import compare
    from numerics.paper.printed import paper_prediction

    syms = [paper.mu, paper.beta, paper.Delta, paper.k]
    out: list[ErratumEvidence] = []
    psi = np.linspace(0.0, 2 * np.pi, n_samples, endpoint=False)
    for name, params in cases:
        comp = compare("sedf", params, orders=(2,), extra=[paper_prediction],
                       result=paper.engine_expansion())  # the expansion eqs. 6-9 correct
        cyc = comp.numeric
        pv = [float(params["mu"]), float(params["beta"]), float(params["Delta"]),
              2 * np.pi / float(params.get("lam", 1.0))]
        m = pv[0]
        a_true = cyc.amplitude_first_harmonic

        def fn(expr, with_psi=False):
            args = [paper.a, paper.psi, *syms] if with_psi else [paper.a, *syms]
            return numpy_function(sp.sympify(expr), args)

        def row(eq, q, pr, co, nu):
            out.append(ErratumEvidence(eq, q, name, dict(params), float(pr), float(co),
                                       float(nu), cyc.success, cyc.message))

        # eq. 6
        row("6", "frequency dpsi/dt at the true a", fn(paper.phase_rate())(a_true, *pv),
            fn(paper.corrected("6"))(a_true, *pv), cyc.frequency)
        # eq. 7
        pr_rate, co_rate = fn(paper.amplitude_rate()), fn(paper.corrected("7"))
        r_p, s_p = _root(lambda s: pr_rate(s, *pv), a_true)
        r_c, s_c = _root(lambda s: co_rate(s, *pv), a_true)
        row("7", "amplitude a* (root of da/dt)", r_p, r_c, a_true)
        row("7", "stable (1) / unstable (0)", float(s_p < 0), float(s_c < 0), float(cyc.stable))
        # eq. 8 (with eq. 9, which adds no third harmonic in either version)
        g_p = m**2 * fn(paper.g(), True)(a_true, psi, *pv) * np.ones_like(psi)
        g_c = m**2 * fn(paper.corrected("9"), True)(a_true, psi, *pv) * np.ones_like(psi)
        f_p = m * fn(paper.f(), True)(a_true, psi, *pv) + g_p
        f_c = m * fn(paper.corrected("8"), True)(a_true, psi, *pv) + g_c
        row("8", "third harmonic of mu u_1 + mu^2 u_2 at the true a", _harmonic(f_p, 3),
            _harmonic(f_c, 3), 2 * abs(cyc.harmonics[3]))
        # eq. 9
        row("9", "mean of x (mu^2 u_2 at the true a)", float(np.mean(g_p)),
            float(np.mean(g_c)), float(cyc.harmonics[0].real))
        # eq. 10 over the reconstructed orbits
        pp = next(p for p in comp.predictions if p.source == "paper")
        pk = next(p for p in comp.predictions if p.source == "kbm" and p.order == 2)
        gm = cyc.dissipation.gamma_minus
        row("10", "Gamma/Gamma_- over the reconstructed cycle",
            pp.dissipation / gm if pp.success else np.nan,
            pk.dissipation / gm if pk.success else np.nan, cyc.dissipation.total / gm)
    return out


def evidence_table(rows: Sequence[ErratumEvidence]) -> str:
    """A plain-text table of :func:`errata_evidence`."""
    lines = [f"{'case':<16}{'eq.':<5}{'quantity':<52}{'printed':>14}{'corrected':>14}"
             f"{'numerical':>14}"]
    for r in rows:
        lines.append(f"{r.case:<16}{r.equation:<5}{r.quantity:<52}{r.printed:>14.6g}"
                     f"{r.corrected:>14.6g}{r.numeric:>14.6g}")
    return "\n".join(lines)


def errata_rows(evidence: Sequence[ErratumEvidence] | None = None) -> list:
    """The errata of :data:`kbm.output.paper.ERRATA` with their numerical evidence, as the rows of
    the errata table of :func:`kbm.output.derivations.write_derivations`.

    Each erratum collects the evidence rows of the equations it names
    (:attr:`kbm.output.paper.Erratum.evidence_equations`, default its own).
    """
    from kbm.output.errata_tex import ErratumRow
    from kbm.output.paper import ERRATA

    evidence = errata_evidence() if evidence is None else evidence
    rows = []
    for e in ERRATA:
        eqs = e.evidence_equations or (e.equation,)
        ev = tuple((r.equation, r.case, r.quantity, r.printed, r.corrected, r.numeric)
                   for r in evidence if r.equation in eqs)
        rows.append(ErratumRow(e.equation, e.quantity, e.printed,
                               e.difference_tex or e.difference, ev))
    return rows
