"""Terms of ``F`` that are not smooth, and the smooth replacement to name for each.

Every KBM route expands ``F`` in Taylor series about ``x_0 = a cos(psi)``, so ``F`` must
be differentiable as often as the order asks.  A step, a kink or a spike (``sign``,
``Abs``, ``Heaviside``, ``Min``/``Max``, ``Piecewise``, ``floor``, ``DiracDelta``) is
refused with the smooth function that approximates it, e.g. Coulomb friction
``-sign(xdot)`` by ``-tanh(xdot/eps)``.
"""

from __future__ import annotations

import sympy as sp

__all__ = ["non_smooth_term", "smooth_replacement", "non_smooth_message"]

_REPLACEMENTS = (
    (sp.sign, "sign(u) -> tanh(u/eps), e.g. -tanh(xdot/0.01) for Coulomb friction"),
    (sp.Abs, "Abs(u) -> sqrt(u**2 + eps**2) (or u*tanh(u/eps)), e.g. sqrt(xdot**2 + 0.01**2)"),
    (sp.Heaviside, "Heaviside(u) -> (1 + tanh(u/eps))/2"),
    (sp.DiracDelta, "DiracDelta(u) -> exp(-(u/eps)**2)/(eps*sqrt(pi))"),
    (sp.Max, "Max(u, w) -> (u + w + sqrt((u - w)**2 + eps**2))/2"),
    (sp.Min, "Min(u, w) -> (u + w - sqrt((u - w)**2 + eps**2))/2"),
    (sp.Piecewise, "Piecewise((f, u > 0), (g, True)) -> g + (f - g)*(1 + tanh(u/eps))/2"),
    (sp.floor, "floor(u) -> a smooth staircase, each step (1 + tanh((u - n)/eps))/2"),
    (sp.ceiling, "ceiling(u) -> a smooth staircase, each step (1 + tanh((u - n)/eps))/2"),
)


def non_smooth_term(expr: sp.Expr) -> sp.Expr | None:
    """The first (in a deterministic order) non-smooth sub-expression of ``expr``, or None."""
    found = [e for e in sp.preorder_traversal(expr)
             if isinstance(e, tuple(f for f, _ in _REPLACEMENTS))]
    return found[0] if found else None


def smooth_replacement(term: sp.Expr) -> str:
    """The smooth function to use instead of ``term`` (a one-line recipe)."""
    for f, text in _REPLACEMENTS:
        if isinstance(term, f):
            return text
    raise ValueError(f"{term} is not one of the non-smooth terms")  # pragma: no cover


def non_smooth_message(term: sp.Expr) -> str:
    """The error message for a non-smooth ``term`` of ``F``."""
    return (f"the term {term} of F is not smooth, but the KBM expansion differentiates F; "
            f"replace it by a smooth approximation: {smooth_replacement(term)}, with eps "
            "small against the amplitudes of interest (the smoother, the cheaper)")
