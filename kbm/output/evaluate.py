"""Numerical evaluation of KBM expressions: numpy (vectorised) and mpmath (any precision).

Expressions are compiled once with :func:`sympy.lambdify`; Bessel functions
become :func:`scipy.special.jv` or :func:`mpmath.besselj` (:mod:`scipy.special` and
:mod:`sympy` are imported when an expression is compiled, not with this module:
:func:`vectorised` wraps an already lambdified function without either, issue 39).
The infinite sums ``Sum(f(n), (n, lo, oo))`` of the Jacobi-Anger algebra are the only place where
anything is truncated: terms are added in blocks until the largest term of the
last block is below ``tol`` times the largest partial sum (numpy, default
``tol = 1e-15``) or until four consecutive terms are below ``10**-(dps + 3)``
relative (mpmath).  The terms are products of Bessel functions
``J_m(k a)`` with ``m`` growing linearly in ``n``, which decay faster than
``(k a / 2)**m / m!``; a sum that has not met its tolerance after
``max_terms`` terms raises :class:`~kbm.errors.SeriesTruncationError` with the size of
the last terms, instead of returning an unconverged number.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

from typing import TYPE_CHECKING

import numpy as np

from ..errors import SeriesTruncationError

if TYPE_CHECKING:  # mpmath and sympy imported on use (issue 39)
    import mpmath
    import sympy as sp

__all__ = ["numpy_function", "numpy_array_function", "mpmath_function", "vectorised",
           "DEFAULT_TOL"]

#: default relative tolerance of the truncated Bessel sums (numpy)
DEFAULT_TOL = 1e-15


def _outer_sums(expr: sp.Expr) -> tuple[sp.Expr, tuple, list[tuple]]:
    """``expr`` with each Sum node not contained in another Sum replaced by a stand-in
    symbol, the stand-ins, and each such sum as ``(body, n, lo, hi)``: ``Sum(f, L1, ...,
    Lk)`` is the sum over its last limit ``Lk = (n, lo, hi)`` of the body ``Sum(f, L1,
    ...)`` (``hi`` is ``None`` for an infinite sum).  Deterministic order."""
    import sympy as sp

    found: list[sp.Sum] = []

    def walk(e):
        if isinstance(e, sp.Sum):
            if e not in found:
                found.append(e)
            return
        for arg in e.args:
            walk(arg)

    walk(expr)
    holders = tuple(sp.Symbol(f"_kbm_sum{i}") for i in range(len(found)))
    parts = []
    for s in found:
        *rest, (n, lo, hi) = s.limits
        parts.append((sp.Sum(s.function, *rest) if rest else s.function, n, int(lo),
                      None if hi == sp.oo else int(hi)))
    return expr.xreplace(dict(zip(found, holders))), holders, parts


def _numpy_modules() -> list:
    """lambdify's namespaces: Bessel functions from :mod:`scipy.special` (imported here, on
    the first compilation)."""
    import scipy.special

    return [{"besselj": scipy.special.jv}, "scipy", "numpy"]


def numpy_function(expr: sp.Expr, args: Sequence[sp.Symbol], *, tol: float = DEFAULT_TOL,
                   max_terms: int = 5000) -> Callable[..., np.ndarray]:
    """Compile ``expr`` to a vectorised numpy function of ``args``.

    Parameters
    ----------
    expr
        A sympy expression, possibly with ``besselj`` and infinite ``Sum``.
    args
        The symbols, in the order the function takes them; arrays broadcast.
    tol
        Relative truncation tolerance of the infinite sums.
    max_terms
        Term budget of each infinite sum.

    Examples
    --------
    >>> import sympy as sp
    >>> n, z = sp.symbols("n z")
    >>> f = numpy_function(sp.Sum(z**n / sp.factorial(n), (n, 0, sp.oo)), [z])
    >>> float(f(1.0))
    2.718281828459045
    """
    import sympy as sp

    names = tuple(map(str, args))
    args, expr = _named(tuple(args), expr)
    outer, holders, sums = _outer_sums(expr)
    with np.errstate(all="ignore"):
        f_outer = sp.lambdify(args + holders, outer, modules=_numpy_modules())
    inner = [(numpy_function(body, args + (n,), tol=tol, max_terms=max_terms), lo, hi)
             for body, n, lo, hi in sums]
    f = _wrap(f_outer, names, inner, tol, max_terms)
    f.__doc__ = f"numpy function of ({', '.join(names)}) for {expr}"
    #: the lambdified function of the arguments and the sums' values, and whether there are
    #: sums (without them ``vectorised(f.lambdified, names)`` is the same function)
    f.lambdified, f.has_sums = f_outer, bool(inner)
    return f


def numpy_array_function(exprs, args: Sequence, *, cse: bool = False
                         ) -> Callable[..., np.ndarray]:
    """Compile a list (or a list of lists) of expressions to one numpy function of
    ``args``: the one lambdify path for arrays of KBM expressions (a slow flow and its
    Jacobian), with the namespaces of :func:`numpy_function` (``besselj`` as
    :func:`scipy.special.jv`).

    ``args`` may nest (``[state, sigma, mu]``: a sequence of symbols is one argument, as
    :func:`sympy.lambdify` takes it).  Expressions with infinite ``Sum`` are compiled one by
    one with :func:`numpy_function` (its truncation rule); the others in one function
    (``cse``: common subexpressions shared).  The call returns a float array of the shape of
    ``exprs``, for scalar arguments.

    Examples
    --------
    >>> import sympy as sp
    >>> a, s = sp.symbols("a s")
    >>> f = numpy_array_function([sp.besselj(0, a), a * s], [a, s])
    >>> f(0.0, 2.0).tolist()
    [1.0, 0.0]
    """
    import sympy as sp

    rows = [list(r) if isinstance(r, (list, tuple)) else r for r in exprs]
    flat = [e for r in rows for e in (r if isinstance(r, list) else [r])]
    if not any(sp.sympify(e).atoms(sp.Sum) for e in flat):
        with np.errstate(all="ignore"):
            fn = sp.lambdify(list(args), rows, modules=_numpy_modules(), cse=cse)

        def f(*vals):
            with np.errstate(all="ignore"):
                return np.asarray(fn(*vals), dtype=float)
        return f
    syms: list = []
    for arg in args:  # the nested arguments as one flat list of symbols
        syms += list(arg) if isinstance(arg, (list, tuple)) else [arg]
    each = [numpy_function(sp.sympify(e), syms) for e in flat]
    shape = np.shape(np.empty((len(rows), len(rows[0])))) \
        if rows and isinstance(rows[0], list) else (len(rows),)

    def g(*vals):
        flat_vals: list = []
        for v in vals:
            flat_vals += list(np.ravel(v)) if np.ndim(v) else [v]
        return np.array([float(h(*flat_vals)) for h in each], dtype=float).reshape(shape)
    return g


def vectorised(f_outer: Callable, names: Sequence[str]) -> Callable[..., np.ndarray]:
    """The vectorised function :func:`numpy_function` makes of a lambdified expression without
    infinite sums (``f.lambdified`` of one where ``f.has_sums`` is false), from the lambdified
    function itself: the same arithmetic, with neither sympy nor scipy imported (a warm run
    rebuilds ``f_outer`` from its stored source, :mod:`numerics.flow.template_cache`)."""
    return _wrap(f_outer, tuple(names), [], DEFAULT_TOL, 0)


def _wrap(f_outer: Callable, names: tuple[str, ...], inner: list, tol: float,
          max_terms: int) -> Callable[..., np.ndarray]:
    """``f(*vals)``: the arguments as float arrays, the sums added, ``f_outer`` broadcast."""
    def f(*vals):
        if len(vals) != len(names):
            raise TypeError(f"expected {len(names)} arguments ({', '.join(names)}), "
                            f"got {len(vals)}")
        with np.errstate(all="ignore"):
            arrs = [np.asarray(v, dtype=float) for v in vals]
            sums_val = [_np_sum(g, lo, hi, arrs, tol, max_terms) for g, lo, hi in inner]
            out = np.asarray(f_outer(*arrs, *sums_val), dtype=float)
        shape = np.broadcast_shapes(out.shape, *[v.shape for v in arrs])
        return out if out.shape == shape else np.broadcast_to(out, shape).copy()

    return f


def _np_sum(g, lo, hi, arrs, tol, max_terms):
    shape = np.broadcast_shapes(*[np.shape(v) for v in arrs]) if arrs else ()
    expand = (slice(None),) + (None,) * len(shape)
    if hi is not None:
        n = np.arange(lo, hi + 1)[expand]
        return np.sum(np.broadcast_to(g(*arrs, n), (n.shape[0],) + shape), axis=0)
    total = np.zeros(shape)
    biggest = np.zeros(shape)
    block = 24
    start = lo
    used = 0
    while True:
        n = np.arange(start, start + block)[expand]
        terms = np.broadcast_to(g(*arrs, n), (block,) + shape)
        terms = np.where(np.isfinite(terms), terms, np.nan)
        total = total + np.sum(terms, axis=0)
        partial = np.abs(total)
        biggest = np.maximum(biggest, np.max(np.abs(terms), axis=0))
        biggest = np.maximum(biggest, partial)
        tail = np.max(np.abs(terms[-block // 4:]), axis=0)
        used += block
        if np.any(np.isnan(total)):
            raise SeriesTruncationError("an infinite Bessel sum produced NaN (an argument is "
                                        "out of range or not finite)")
        if np.all(tail <= tol * np.maximum(biggest, 1e-300)):
            return total
        if used >= max_terms:
            raise SeriesTruncationError(
                f"an infinite Bessel sum did not converge to rel. tol {tol:g} within "
                f"{max_terms} terms (last terms up to {float(np.max(tail)):.3e}); "
                "the argument k*a is probably too large")
        start += block
        block = min(2 * block, max_terms - used) or 1


def _named(args: tuple, expr):
    """``args`` and ``expr`` with every ``Dummy`` argument (a sum's index) a ``Symbol`` of a
    fixed reserved name, and the sums' stand-ins named likewise by the callers.

    ``sympy.lambdify`` renames all arguments ``Dummy_<counter>`` when one is a ``Dummy`` and
    prints a sum's terms in the string order of the names, so the order of the additions (the
    last bits) depended on sympy's process-wide ``Dummy`` counter, i.e. on what the process
    had computed before (tests/test_errata_order.py: the errata's eq. 10 value for the
    paper's Fig. 3 moved in its 17th digit).  Fixed names make the compiled function a
    function of ``expr`` and ``args`` alone."""
    import sympy as sp

    subs = {s: sp.Symbol(f"_kbm_arg{i}") for i, s in enumerate(args) if isinstance(s, sp.Dummy)}
    if not subs:
        return args, expr
    return tuple(subs.get(s, s) for s in args), expr.xreplace(subs)


def mpmath_function(expr: sp.Expr, args: Sequence[sp.Symbol], *,
                    max_terms: int = 20000) -> Callable[..., mpmath.mpf]:
    """Compile ``expr`` to a scalar mpmath function (working precision ``mpmath.mp.dps``).

    Infinite sums are added term by term until four consecutive terms are below
    ``10**-(mp.dps + 3)`` relative to the largest partial sum.
    """
    import mpmath
    import sympy as sp

    args, expr = _named(tuple(args), expr)
    outer, holders, sums = _outer_sums(expr)
    f_outer = sp.lambdify(args + holders, outer, modules="mpmath")
    inner = [(mpmath_function(body, args + (n,), max_terms=max_terms), lo, hi)
             for body, n, lo, hi in sums]

    def f(*vals):
        vals = [mpmath.mpmathify(v) for v in vals]
        sums_val = [_mp_sum(g, lo, hi, vals, max_terms) for g, lo, hi in inner]
        return f_outer(*vals, *sums_val)

    return f


def _mp_sum(g, lo, hi, vals, max_terms):
    import mpmath

    if hi is not None:
        return mpmath.fsum(g(*vals, n) for n in range(lo, hi + 1))
    eps = mpmath.mpf(10) ** (-(mpmath.mp.dps + 3))
    total = mpmath.mpf(0)
    biggest = mpmath.mpf(0)
    small = 0
    n = lo
    while True:
        term = g(*vals, n)
        total += term
        biggest = max(biggest, abs(total), abs(term))
        small = small + 1 if abs(term) <= eps * biggest else 0
        if small >= 4 and n - lo >= 8:
            return total
        n += 1
        if n - lo > max_terms:
            raise SeriesTruncationError(
                f"an infinite Bessel sum did not converge at {mpmath.mp.dps} digits within "
                f"{max_terms} terms (last term {mpmath.nstr(term, 5)})")
