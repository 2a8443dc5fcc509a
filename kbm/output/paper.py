"""The paper's second-order KBM formulas, eqs. (5)-(9), exactly as printed, and their errata.

D'Acunto writes the second KBM approximation of the SEDF (eq. 3 with ``v = 0``,
``Omega = 1``, ``k = 2 pi/lam``) as

- eq. (5): ``x = a cos psi + mu f(a, psi) + mu^2 g(a, psi)``;
- eq. (6): ``psi = [1 - mu^2 (1 - beta a^2/4)(1/3 - beta a^2/4)] t + psi_0``;
- eq. (7): ``a' = mu [a/2 (1 - beta a^2/4) + (Delta/mu) J_1(k a)] +
  mu^2 [k Delta^2/(2 mu) J_0(k a) J_1(k a)]``;
- eq. (8): ``f = -(beta a^3/32) sin 3 psi +
  (Delta/mu) sum_{n != 1} (-1)^n J_{2n+1}(k a) cos((2n+1) psi)``;
- eq. (9): ``g = -(k Delta^2/mu) J_0(k a) J_1(k a) -
  2 a (1 - beta a^2/4)(1/3 - beta a^2/4) cos psi``.

This module holds these expressions in one place, in the symbols ``mu``,
``beta``, ``Delta``, ``k``, ``a``, ``psi`` (physical parameters; the scaled
``delta = Delta/mu`` of :mod:`kbm.model.builtins` appears as ``Delta/mu``).  The
summation range of eq. (8), printed ``n != 1``, is read as ``n = 0, 2, 3, ...``
(the Jacobi-Anger range ``n >= 0`` without ``n = 1``).

:data:`ERRATA` compares each formula with the engine's derivation
(:func:`kbm.derive` of ``sedf`` to order 2, computed when a row's
:attr:`Erratum.corrected` is first read, not copied here).  What differs:

- eq. (6): the first-order frequency shift ``mu B_1 = Delta J_1(k a)/a`` of the
  periodic potential is missing, and so are the ``Delta^2`` terms of ``B_2``; the
  printed ``mu^2`` term ``-(1 - beta a^2/4)(1/3 - beta a^2/4)`` is not the van der Pol
  ``B_2 = -(1 - beta a^2 + 7 beta^2 a^4/32)/8``: it vanishes on the cycle
  ``beta a^2 = 4``, where the true ``B_2 = -1/16``.
- eq. (7): the conservative force ``Delta sin(k x)`` does no work over a cycle, so
  it has no first-order term in ``a'``; the printed ``Delta J_1(k a)`` belongs
  (divided by ``a``) to the phase equation.  The true ``A_2`` is linear in
  ``Delta/mu`` and proportional to ``beta``-dependent damping terms
  (self-excitation times potential), not ``k Delta^2 J_0 J_1``.
- eq. (8): each harmonic ``(2n+1)`` of the potential force is divided by
  ``omega0^2 (1 - (2n+1)^2) = -4 n (n+1)``: the factor ``1/(2 n (n+1))`` is missing;
  the ``n = 0`` term is a first harmonic, which the convention (``a`` is the
  first-harmonic amplitude) excludes, and the ``n = 1`` (third) harmonic, which
  is the largest, is left out.
- eq. (9): ``g`` holds a constant and a first harmonic; the true ``u_2`` has
  neither (no constant because ``F`` is odd in ``x``, no first harmonic by the
  convention); its terms are third and higher harmonics.

References
----------
M. D'Acunto, "Friction force for self-excited systems", eqs. (3), (5)-(9).
Bogoliubov, N. N. and Mitropolsky, Y. A., *Asymptotic Methods in the Theory of
Non-Linear Oscillations* (1961), ch. 1, sec. 2.

Examples
--------
>>> from kbm.output import paper
>>> paper.phase_rate()
-mu**2*(-a**2*beta/4 + 1/3)*(-a**2*beta/4 + 1) + 1
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from functools import lru_cache
from types import MappingProxyType

import sympy as sp

from ..symbols import a, mu, psi

__all__ = ["mu", "beta", "Delta", "k", "a", "psi", "n", "phase_rate", "amplitude_rate",
           "f", "g", "displacement", "Erratum", "ERRATA", "corrected", "engine_expansion",
           "FIXED", "fig3", "FIG4", "FIG5", "POINTS", "ERRATA_CASES", "COMPARISON_CASES"]

beta, Delta, k = sp.symbols("beta Delta k")
#: summation index of eq. (8)
n = sp.Symbol("n", integer=True, nonnegative=True)

J = sp.besselj


def phase_rate() -> sp.Expr:
    """``dpsi/dt`` of eq. (6) as printed: ``1 - mu^2 (1 - beta a^2/4)(1/3 - beta a^2/4)``."""
    return 1 - mu**2 * (1 - beta * a**2 / 4) * (sp.Rational(1, 3) - beta * a**2 / 4)


def amplitude_rate() -> sp.Expr:
    """``da/dt`` of eq. (7) as printed.

    ``mu [a/2 (1 - beta a^2/4) + (Delta/mu) J_1(k a)] + mu^2 [k Delta^2/(2 mu) J_0 J_1]``.
    """
    return (mu * (a / 2 * (1 - beta * a**2 / 4) + Delta / mu * J(1, k * a))
            + mu**2 * (k * Delta**2 / (2 * mu) * J(0, k * a) * J(1, k * a)))


def f() -> sp.Expr:
    """``f(a, psi)`` of eq. (8) as printed, the sum over ``n = 0, 2, 3, ...``."""
    term = (-1)**n * J(2 * n + 1, k * a) * sp.cos((2 * n + 1) * psi)
    s = term.subs(n, 0) + sp.Sum(term, (n, 2, sp.oo))
    return -beta * a**3 / 32 * sp.sin(3 * psi) + Delta / mu * s


def g() -> sp.Expr:
    """``g(a, psi)`` of eq. (9) as printed."""
    return (-k * Delta**2 / mu * J(0, k * a) * J(1, k * a)
            - 2 * a * (1 - beta * a**2 / 4) * (sp.Rational(1, 3) - beta * a**2 / 4) * sp.cos(psi))


def displacement() -> sp.Expr:
    """``x`` of eq. (5) with eqs. (8), (9): ``a cos psi + mu f + mu^2 g``."""
    return a * sp.cos(psi) + mu * f() + mu**2 * g()


# ----------------------------------------------------------------------------- errata
@lru_cache(maxsize=1)
def engine_expansion():
    """The engine's order-2 expansion of the built-in ``sedf`` (:func:`kbm.derive`): the
    corrections below and the errata's comparisons share it.

    Pure-function memo of a constant of this module, computed on first use (it takes about a
    second): the function has no argument, :func:`kbm.derive` of the fixed built-in model is
    a pure function and the result is frozen, so the memo holds one immutable value and
    cannot change a result (``tests/test_memo_purity.py``).  What is computed from it (the corrected expressions, its
    compiled functions) is kept on the returned :class:`~kbm.expansion.result.KBMResult` itself.
    """
    from ..expansion.one_dof import derive

    return derive("sedf", 2)


def _engine() -> Mapping[str, sp.Expr]:
    """The engine's order-2 sedf expansion in the paper's variables (Omega = 1): computed once
    and kept on :func:`engine_expansion`'s result."""
    res = engine_expansion()
    return res._computed_once(("paper variables",), lambda: _in_paper_variables(res))


def _in_paper_variables(res) -> Mapping[str, sp.Expr]:
    """The right-hand sides of eqs. (6)-(9) from the order-2 ``res`` (``delta = Delta/mu``,
    ``Omega = 1``)."""
    subs = {sp.Symbol("Omega"): 1, sp.Symbol("delta"): Delta / mu, sp.Symbol("k"): k,
            sp.Symbol("beta"): beta}

    def p(e):
        return sp.sympify(e).subs(subs)

    return MappingProxyType({
        "6": 1 + mu * p(res.B[1]) + mu**2 * p(res.B[2]),
        "7": mu * p(res.A[1]) + mu**2 * p(res.A[2]),
        "8": p(res.u[1]),
        "9": p(res.u[2]),
    })


def corrected(equation: str) -> sp.Expr:
    """The engine's expression for what the paper's eq. ``equation`` (6, 7, 8 or 9) states."""
    return _engine()[str(equation)]


@dataclass(frozen=True)
class Erratum:
    """One printed formula of the paper next to the engine's derivation.

    Attributes
    ----------
    equation
        The paper's equation number (``"6"`` ... ``"9"``).
    quantity
        What it gives (``"dpsi/dt"``, ``"da/dt"``, ``"u_1 = f"``, ``"u_2 = g"``).
    printed
        The formula as printed (sympy).
    difference
        What differs, in words.
    evidence
        The measured quantity that shows it (a key of :func:`numerics.errata_evidence`).
    evidence_equations
        The equations whose numerical evidence rows belong to this erratum (default:
        its own equation; eq. (9)'s waveform also shows in eq. (10)'s dissipation).
    difference_tex
        ``difference`` typeset for LaTeX (the derivations' errata section).
    """

    equation: str
    quantity: str
    printed: sp.Expr
    difference: str
    evidence: str
    evidence_equations: tuple[str, ...] = ()
    difference_tex: str = ""

    @property
    def corrected(self) -> sp.Expr:
        """The engine's expression (derived on first use, in the paper's variables)."""
        return corrected(self.equation)


ERRATA: tuple[Erratum, ...] = (
    Erratum("6", r"\dot\psi", phase_rate(),
            "first-order shift Delta J_1(k a)/a of the potential missing (mu B_1); Delta^2 "
            "terms of B_2 missing; the printed mu^2 term vanishes on beta a^2 = 4, the true "
            "van der Pol part of B_2 there is -1/16",
            "frequency",
            difference_tex=r"the first-order shift $\Delta J_1(ka)/a$ of the potential is "
            r"missing ($\mu B_1$), and so are the $\Delta^2$ terms of $B_2$; the printed "
            r"$\mu^2$ term vanishes on $\beta a^2 = 4$, where the true van der Pol part of "
            r"$B_2$ is $-1/16$"),
    Erratum("7", r"\dot a", amplitude_rate(),
            "Delta J_1(k a) is a frequency shift (conservative force, no work per cycle), not "
            "an amplitude rate; the true A_2 is linear in Delta/mu with beta-dependent "
            "coefficients, not k Delta^2 J_0 J_1/(2 mu)",
            "amplitude",
            difference_tex=r"$\Delta J_1(ka)$ is a frequency shift (a conservative force "
            r"does no work per cycle), not an amplitude rate; the true $A_2$ is linear in "
            r"$\Delta/\mu$ with $\beta$-dependent coefficients, not "
            r"$k\Delta^2 J_0 J_1/(2\mu)$"),
    Erratum("8", "f = u_1", f(),
            "factor 1/(2n(n+1)) missing in each potential harmonic; the n = 0 (first-harmonic) "
            "term must not be there and the n = 1 (third-harmonic) term must",
            "harmonic3",
            difference_tex=r"each potential harmonic lacks the factor $1/(2n(n+1))$; the "
            r"$n = 0$ (first-harmonic) term must not be there and the $n = 1$ "
            r"(third-harmonic) term must"),
    Erratum("9", "g = u_2", g(),
            "u_2 has neither a constant nor a first harmonic; its terms are third and "
            "higher harmonics",
            "mean", ("9", "10"),
            difference_tex=r"$u_2$ has neither a constant nor a first harmonic; its terms "
            r"are third and higher harmonics"),
)


# ----------------------------------------------------------------------------- parameter sets
#: the paper's fixed parameters (section 3): mu = 0.1, Omega = 1, lambda = 1
FIXED = {"mu": 0.1, "Omega": 1.0, "lam": 1.0}

def fig3(beta: float) -> dict[str, float]:
    """The parameters of the paper's Fig. 3 (undriven SEDF, ``Delta = 1.5``) at ``beta``."""
    return {"mu": 0.1, "Delta": 1.5, "beta": float(beta), "lam": 1.0}


#: Fig. 4: SEDF, Delta = 3, beta = 1, pulled at v = 0.1
FIG4 = {"mu": 0.1, "Delta": 3.0, "beta": 1.0, "v": 0.1, "lam": 1.0, "Omega": 1.0}

#: Fig. 5 (and 6): SEDF and CDC, Delta = 3, beta = 1, v = 0.01
FIG5 = {"mu": 0.1, "Delta": 3.0, "beta": 1.0, "v": 0.01, "lam": 1.0, "Omega": 1.0}

#: the paper's undriven parameters in the (mu, Delta) plane (Figs. 3-6)
POINTS = ((0.1, 1.5), (0.1, 3.0))

#: the errata evidence cases: where the expansion is valid, and the paper's Fig. 3
ERRATA_CASES = (
    ("small Delta/mu", {"mu": 0.05, "Delta": 0.1, "beta": 1.0, "lam": 1.0}),
    ("paper Fig. 3", {"mu": 0.1, "Delta": 1.5, "beta": 1.0, "lam": 1.0}),
)

#: the comparison cases of the main job: (label, model, parameters)
COMPARISON_CASES = (
    ("van der Pol, mu = 0.1", "vdp", {"mu": 0.1}),
    ("van der Pol, mu = 1", "vdp", {"mu": 1}),
    ("SEDF small Delta/mu (mu = 0.05, Delta = 0.1, beta = 1)", "sedf",
     {"mu": 0.05, "Delta": 0.1, "beta": 1, "lam": 1}),
    ("SEDF paper Fig. 3 (mu = 0.1, Delta = 1.5, beta = 1)", "sedf", fig3(1)),
    ("SEDF paper Fig. 3 (mu = 0.1, Delta = 1.5, beta = 0.25)", "sedf", fig3(0.25)),
)
