"""Constants of ``F`` that are not rational functions of the parameters, kept exact.

The exact coupled engine computes over Laurent polynomials with rational coefficients in
the amplitudes and the parameters.  A constant such as ``sqrt(2)``, ``pi`` or ``cos(phi)``
(the phase of a slider on a shifted potential, ``sin(k x_i + phi)``: a Frenkel-Kontorova
chain) enters the recursion only through products and sums, never through a divisor (the
divisors are the frequencies'); so each is a generator of the ring of its own, an
independent symbol, and is put back at the end (:func:`opaque_constants`).  Relations
between them (``sqrt(2)**2 = 2``) are applied by sympy when they are put back.  Floats
stay refused: a rational is exact, a float is not.

A phase in the argument of ``sin``/``cos`` of a position is split off first
(:func:`split_phases`): ``sin(c x + d) = sin(c x) cos d + cos(c x) sin d``, so that the
Jacobi-Anger series of :mod:`kbm.algebra.coupled_bessel` applies to ``sin(c x)``, ``cos(c x)``.
"""

from __future__ import annotations

import sympy as sp

__all__ = ["opaque_constants", "split_phases", "linear_argument"]

_TIME = {sp.Symbol("theta"), sp.Symbol("t"), sp.Symbol("nu")}


def linear_argument(arg: sp.Expr, variables: tuple):
    """``(v, c, d)`` with ``arg = c v + d`` for one of ``variables``, ``c`` and ``d`` constant
    (free of the variables and of time), ``c != 0``; ``None`` for any other argument."""
    arg = sp.expand(arg)
    held = [v for v in variables if arg.has(v)]
    if len(held) != 1:
        return None
    (v,) = held
    c = arg.coeff(v)
    d = sp.expand(arg - c * v)
    constant = set(variables) | _TIME
    if c == 0 or c.free_symbols & constant or d.free_symbols & constant:
        return None
    return v, c, d


def split_phases(rows: list[list[sp.Expr]], positions: tuple) -> list[list[sp.Expr]]:
    """``rows`` with every ``sin(c x_l + d)``, ``cos(c x_l + d)`` (``d`` free of the state
    and of time) written as ``sin(c x_l) cos d + cos(c x_l) sin d`` (and likewise); the
    forcing angle's ``cos(k theta + d)``, ``sin(k theta + d)`` too (a forcing with a phase
    ``phi``)."""
    angles = tuple(positions) + (sp.Symbol("theta"),)

    def is_shifted(e) -> bool:
        if not isinstance(e, (sp.sin, sp.cos)):
            return False
        form = linear_argument(e.args[0], angles)
        return form is not None and form[2] != 0

    def split(e):
        xl, c, d = linear_argument(e.args[0], angles)
        if isinstance(e, sp.sin):
            return sp.sin(c * xl) * sp.cos(d) + sp.cos(c * xl) * sp.sin(d)
        return sp.cos(c * xl) * sp.cos(d) - sp.sin(c * xl) * sp.sin(d)

    return [[sp.expand(f.replace(is_shifted, split)) for f in row] for row in rows]


def _atoms(expr: sp.Expr, state: set) -> set:
    """The constant sub-expressions of ``expr`` that are not rational in the parameters:
    applied functions, ``pi``, ``E``, powers with a non-integer exponent (none holding the
    state or time)."""
    out = set()
    for e in sp.preorder_traversal(expr):
        if e.free_symbols & (state | _TIME):
            continue
        if isinstance(e, sp.Function) or isinstance(e, sp.NumberSymbol) or (
                e.is_Pow and not e.exp.is_Integer):
            out.add(e)
    # the outermost only: cos(sqrt(2) phi) is one constant, not two
    return {e for e in out if not any(e != o and o.has(e) for o in out)}


def opaque_constants(rows: list[list[sp.Expr]], state: tuple
                     ) -> tuple[list[list[sp.Expr]], dict[sp.Symbol, sp.Expr]]:
    """``rows`` with each irrational constant of a term's coefficient replaced by a symbol
    ``_K0, _K1, ..`` (in a fixed order), and the map back.

    The arguments of ``sin``/``cos`` of the state are left alone (their constants are the
    Bessel functions' arguments, :mod:`kbm.algebra.coupled_bessel`).
    """
    sset = set(state)
    found: set = set()
    for row in rows:
        for f in row:
            for term in sp.Add.make_args(sp.expand(f)):
                for factor in sp.Mul.make_args(term):
                    if not factor.free_symbols & (sset | _TIME):
                        found |= _atoms(factor, sset)
    if not found:
        return rows, {}
    ordered = sorted(found, key=sp.default_sort_key)
    symbols = {e: sp.Symbol(f"_K{i}") for i, e in enumerate(ordered)}

    def put(f):
        out = []
        for term in sp.Add.make_args(sp.expand(f)):
            out.append(sp.Mul(*[factor.xreplace(symbols)
                                if not factor.free_symbols & (sset | _TIME) else factor
                                for factor in sp.Mul.make_args(term)]))
        return sp.Add(*out)

    return [[put(f) for f in row] for row in rows], {s: e for e, s in symbols.items()}
