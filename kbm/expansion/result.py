"""The result of a KBM derivation: an immutable record of sympy expressions."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from functools import cached_property

import sympy as sp

from ..output import evaluate
from ..errors import ExpansionError, OrderError, ParameterError
from ..output.latex import align_block, equation_lines, latex
from ..model.builtins import Oscillator
from ..symbols import a, mu, psi

__all__ = ["KBMResult", "KBMFunctions", "lex", "by_order"]


@dataclass(frozen=True)
class KBMFunctions:
    """Compiled numerical functions of a :class:`KBMResult`.

    Every function takes its variables first and then the remaining model
    parameters, positionally, in the order of :attr:`params`:

    - ``A[n](a, *params)``, ``B[n](a, *params)``, ``u[n](a, psi, *params)``;
    - ``amplitude_rate(a, mu, *params, order=None)`` = ``sum_{n<=order} mu**n A_n``;
    - ``phase_rate(a, mu, *params, order=None)`` = ``omega0 + sum mu**n B_n``;
    - ``displacement(a, psi, mu, *params, order=None)`` = ``a cos psi + sum mu**n u_n``.

    With ``backend="numpy"`` they broadcast over arrays; with ``"mpmath"`` they
    take scalars and compute at ``mpmath.mp.dps`` digits.
    """

    backend: str
    order: int
    params: tuple[str, ...]
    A: tuple[Callable, ...]
    B: tuple[Callable, ...]
    u: tuple[Callable, ...]

    def amplitude_rate(self, a, mu, *params, order: int | None = None):
        N = self.order if order is None else order
        return _series_sum([self.A[n](a, *params) for n in range(1, N + 1)], mu, 1)

    def phase_rate(self, a, mu, *params, order: int | None = None):
        N = self.order if order is None else order
        return _series_sum([self.B[n](a, *params) for n in range(0, N + 1)], mu, 0)

    def displacement(self, a, psi, mu, *params, order: int | None = None):
        N = self.order if order is None else order
        return _series_sum([self.u[n](a, psi, *params) for n in range(0, N + 1)], mu, 0)


def lex(e: sp.Expr) -> str:
    """``e`` as the JSON and plain text of the results print it (``sstr``, lexicographic
    order): :func:`kbm.parse` reads it back."""
    return sp.sstr(e, order="lex")


def by_order(seq) -> list:
    """The entries of a per-order tuple as :func:`lex` strings, entry 0 ``None``."""
    return [None] + [lex(e) for e in seq[1:]]


def _series_sum(values, mu, first):
    total = 0
    for n, v in enumerate(values, start=first):
        total = total + mu**n * v
    return total


@dataclass(frozen=True)
class KBMResult:
    """KBM expansion ``x = sum mu**n u[n]``, ``a' = sum mu**n A[n]``, ``psi' = sum mu**n B[n]``.

    Attributes
    ----------
    model
        The oscillator (with any substituted parameter values).
    order
        The highest power of ``mu`` kept.
    A, B, u
        Tuples indexed by order ``0..order``: ``A[0] = 0``, ``B[0] = omega0``,
        ``u[0] = a cos(psi)``.  ``A[n]``, ``B[n]`` depend on ``a`` (and
        parameters); ``u[n]`` on ``a`` and ``psi`` and holds no first harmonic,
        so ``a`` is the first-harmonic amplitude of ``x``.
    exact
        ``True`` when everything is exact rational algebra (polynomial ``F``);
        ``False`` when infinite Bessel sums appear (they are exact as written
        and truncated only on numerical evaluation).
    """

    model: Oscillator
    order: int
    A: tuple[sp.Expr, ...]
    B: tuple[sp.Expr, ...]
    u: tuple[sp.Expr, ...]
    exact: bool = True

    def __post_init__(self) -> None:
        for name in ("A", "B", "u"):
            seq = getattr(self, name)
            if len(seq) != self.order + 1:
                raise ExpansionError(f"{name} must have order + 1 = {self.order + 1} entries")
        for n, un in enumerate(self.u[1:], start=1):
            if _first_harmonic_present(un):
                raise ExpansionError(f"u[{n}] contains a first harmonic, against the "
                                     "convention")

    # -- sums over orders ---------------------------------------------------------------
    def amplitude_rate(self, order: int | None = None) -> sp.Expr:
        """``da/dt = sum_{n=1}^{order} mu**n A_n(a)``."""
        N = self.resolve_order(order)
        return sp.Add(*[mu**n * self.A[n] for n in range(1, N + 1)])

    def phase_rate(self, order: int | None = None) -> sp.Expr:
        """``dpsi/dt = omega0 + sum_{n=1}^{order} mu**n B_n(a)``."""
        N = self.resolve_order(order)
        return sp.Add(*[mu**n * self.B[n] for n in range(0, N + 1)])

    def displacement(self, order: int | None = None) -> sp.Expr:
        """``x(a, psi) = a cos(psi) + sum_{n=1}^{order} mu**n u_n(a, psi)``."""
        N = self.resolve_order(order)
        return sp.Add(*[mu**n * self.u[n] for n in range(0, N + 1)])

    @property
    def params(self) -> tuple[str, ...]:
        """Names of the parameters left symbolic in the result (sorted)."""
        syms = set()
        for seq in (self.A, self.B, self.u):
            for e in seq:
                syms |= sp.sympify(e).free_symbols
        return tuple(sorted(s.name for s in syms if s not in (a, psi, mu)))

    def functions(self, backend: str = "numpy", *, tol: float | None = None) -> KBMFunctions:
        """Compile every ``A_n``, ``B_n``, ``u_n`` (see :class:`KBMFunctions`).

        Parameters
        ----------
        backend
            ``"numpy"`` (vectorised; Bessel functions from :mod:`scipy.special`)
            or ``"mpmath"`` (arbitrary precision, scalars).
        tol
            Relative truncation tolerance of infinite Bessel sums (numpy only;
            default :data:`kbm.output.evaluate.DEFAULT_TOL`).

        Compiled on the first call and kept on this result (an attribute outside its fields:
        no process-wide cache), so the studies that compare one derivation at many parameter
        values compile it once.
        """
        if backend not in ("numpy", "mpmath"):
            raise ParameterError(f"unknown backend {backend!r}; use 'numpy' or 'mpmath'")
        return self._computed_once(("functions", backend, tol),
                                  lambda: _compile(self, backend, tol))

    # -- values computed once from this result ------------------------------------------
    @cached_property
    def _computed(self) -> dict:
        """The values computed from this result so far (:meth:`_computed_once`): an
        attribute of the instance, outside the dataclass fields, so it enters neither
        ``==``, ``hash``, ``repr``, :meth:`to_json` nor a pickle (:meth:`__getstate__`)."""
        return {}

    def _computed_once(self, key: tuple, build: Callable[[], object]) -> object:
        """``build()`` on the first call with ``key``, the same object on every later one.

        For values that are functions of this (immutable) result alone, such as its compiled
        functions (:meth:`functions`), its averaged rates (:func:`kbm.averaged_rates`) and the
        paper's corrected formulas (:func:`kbm.output.paper.corrected`): they live and die with the
        result, and a later call gets the value a fresh ``build()`` gives.  ``key`` names the
        value and the arguments it was built with; the value must be immutable.
        """
        store = self._computed
        if key not in store:
            store[key] = build()
        return store[key]

    def __getstate__(self) -> dict:
        """The fields only: the values of :meth:`_computed_once` (lambdified functions, not
        picklable) are computed again after unpickling."""
        return {k: v for k, v in self.__dict__.items() if k != "_computed"}

    # -- output -------------------------------------------------------------------------
    def to_json(self) -> dict:
        """``model``, ``order``, ``A``, ``B``, ``u`` (lists indexed by order, entry 0 null).

        Every entry is a string that :func:`kbm.parse` (or ``sympy.sympify`` with
        :data:`kbm.symbols.PARSE_LOCALS`) reads back to the same expression.
        """
        return {"model": self.model.name, "order": self.order, "omega0": str(self.model.omega0),
                "F": lex(self.model.F), "exact": self.exact,
                "A": by_order(self.A), "B": by_order(self.B), "u": by_order(self.u)}

    def pretty(self) -> str:
        """A plain-text summary, one line per quantity."""
        w2 = self.model.omega0**2
        x = "x" if w2 == 1 else f"{sp.sstr(w2)}*x"
        lines = [f"KBM expansion of {self.model.name}: x'' + {x} = mu*({self.model.F}), "
                 f"order {self.order}"]
        lines += [f"{name}_{n} = {lex(seq[n])}" for name, seq in (("A", self.A), ("B", self.B),
                                                                  ("u", self.u))
                  for n in range(1, self.order + 1)]
        return "\n".join(lines)

    def latex(self, width: int = 90) -> str:
        """The expansion as a LaTeX ``align*`` block (paper notation, broken lines)."""
        eqs = [r"x &= a\cos\psi" + "".join(rf" + \mu^{{{n}}} u_{{{n}}}(a,\psi)"
                                              for n in range(1, self.order + 1))]
        eqs.append(r"\dot a &= " + " + ".join(rf"\mu^{{{n}}} A_{{{n}}}(a)"
                                               for n in range(1, self.order + 1)))
        eqs.append(r"\dot\psi &= " + latex(self.B[0]) + "".join(
            rf" + \mu^{{{n}}} B_{{{n}}}(a)" for n in range(1, self.order + 1)))
        for group in self.latex_groups(width):
            eqs += group
        return align_block(eqs)

    def latex_groups(self, width: int = 90, subs: Mapping | None = None,
                     orders_u: int | None = None) -> list[list[str]]:
        """The ``align`` rows of the ``A_n(a)``, of the ``B_n(a)`` and of the ``u_n(a, psi)``
        (to ``orders_u``, default all), each broken into lines of about ``width`` characters
        and with the values ``subs`` put in (as
        :meth:`kbm.expansion.coupled_result.CoupledKBMResult.latex_groups`)."""
        subs = dict(subs or {})
        return [[equation_lines(f"{name}_{{{n}}}{arg}", seq[n].subs(subs) if subs else seq[n],
                                width) for n in range(1, top + 1)]
                for name, arg, seq, top in (("A", "(a)", self.A, self.order),
                                            ("B", "(a)", self.B, self.order),
                                            ("u", "(a,\\psi)", self.u, orders_u or self.order))]

    def _repr_latex_(self) -> str:
        return "$\\displaystyle " + self.latex().replace("align*", "aligned") + "$"

    def resolve_order(self, order: int | None) -> int:
        """The truncation order to use: ``order`` checked against ``0..self.order``, or
        :attr:`order` for ``None``.

        Raises
        ------
        kbm.errors.OrderError
            If ``order`` is outside ``0..self.order``.
        """
        if order is None:
            return self.order
        if not 0 <= order <= self.order:
            raise OrderError(f"order {order} is outside 0..{self.order} of this result")
        return order


def _first_harmonic_present(expr: sp.Expr) -> bool:
    """Whether a finite (non-Sum) cos(psi) or sin(psi) term is present.

    Expanding never makes a ``cos`` or ``sin`` of ``+-psi`` that was not there (up to
    the expansion of its argument), so the costly expansion of a large ``u_n`` is done
    only when such a factor occurs somewhere in ``expr``.
    """
    trig = sp.sympify(expr).atoms(sp.cos, sp.sin)
    if not any(sp.expand(f.args[0]) in (psi, -psi) for f in trig):
        return False
    expr = sp.expand(expr)
    for term in sp.Add.make_args(expr):
        if isinstance(term, sp.Sum):
            continue
        for f in sp.Mul.make_args(term):
            if isinstance(f, (sp.cos, sp.sin)) and f.args[0] in (psi, -psi):
                return True
    return False


def _compile(result: KBMResult, backend: str, tol: float | None) -> KBMFunctions:
    """The functions of :meth:`KBMResult.functions`, compiled afresh."""
    pars = tuple(sp.Symbol(p) for p in result.params)
    if backend == "numpy":
        def comp(e, args):
            return evaluate.numpy_function(sp.sympify(e), args,
                                           tol=tol or evaluate.DEFAULT_TOL)
    else:
        def comp(e, args):
            return evaluate.mpmath_function(sp.sympify(e), args)
    return KBMFunctions(
        backend=backend, order=result.order, params=result.params,
        A=tuple(comp(e, (a, *pars)) for e in result.A),
        B=tuple(comp(e, (a, *pars)) for e in result.B),
        u=tuple(comp(e, (a, psi, *pars)) for e in result.u),
    )
