"""The result of the coupled KBM recursion: the slow flow of amplitudes and phase combinations.

:class:`CoupledKBMResult` holds, for every degree of freedom ``i`` and order ``n``, the
rates ``A_{i,n}(a, gamma)``, ``B_{i,n}(a, gamma)`` and the corrections
``u_{i,n}(a, psi)`` as sympy expressions; the phase combinations ``gamma_r`` of the
declared internal resonances are named, and their rates follow
(``gamma_r' = sum_l g_{r,l} psi_l'``, slow because ``g_r . omega = 0``).  It renders
plain text, JSON and LaTeX, and lambdifies the slow flow.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace

import numpy as np
import sympy as sp

from ..algebra.multi_angle import MultiAngle
from .result import by_order, lex as _lex
from ..symbols import mu
from ..model.coupled import CoupledOscillators, amplitudes, phases
from .resonance import SlowLattice

__all__ = ["CoupledKBMResult"]


def _slow_expr(f: MultiAngle, lattice: SlowLattice, gammas: tuple) -> sp.Expr:
    parts = []
    for kind, table, fn in (("cos", f.cos, sp.cos), ("sin", f.sin, sp.sin)):
        for h in sorted(table):
            c = lattice.coords(h)
            arg = sp.Add(*[ci * g for ci, g in zip(c, gammas) if ci])
            parts.append(table[h].as_primitive_expr() * (fn(arg) if any(h) else 1))
    return sp.Add(*parts)


def _resonance(r) -> str:
    """``omega1 : omega2 = 1 : 3`` (``nu`` for the forcing), with its detuning
    (:class:`kbm.expansion.resonance.InternalResonance`)."""
    j = "nu" if r.forcing else f"omega{r.j}"
    return (f"omega{r.i} : {j} = {r.p} : {r.q}"
            + (f" ({j} = {sp.sstr(sp.Rational(r.q, r.p))}*omega{r.i} + mu*{r.detuning})"
               if r.detuning else ""))


@dataclass(frozen=True)
class CoupledKBMResult:
    """The KBM expansion of ``N`` coupled oscillators to a given order.

    Attributes
    ----------
    model
        The system (parameters substituted, internal resonances declared).
    order
        The highest power of ``mu`` kept.
    gammas
        ``((gamma_r, g_r . psi), ...)``: the slow phase combinations and their
        definitions; empty without internal resonances.
    A, B, u
        ``A[i][n]``, ``B[i][n]``, ``u[i][n]`` for mode ``i`` (from 0) and order ``n``,
        with ``A[i][0] = 0``, ``B[i][0] = omega_i``, ``u[i][0] = a_i cos(psi_i)``;
        with ``sin``/``cos`` of the state, ``u[i][1]`` holds sums over the harmonic
        index (the Jacobi-Anger series above its cut, :mod:`kbm.algebra.coupled_bessel`).
    """

    model: CoupledOscillators
    order: int
    gammas: tuple
    A: tuple
    B: tuple
    u: tuple

    @classmethod
    def from_series(cls, model: CoupledOscillators, order: int, lattice: SlowLattice,
                    A: list, B: list, U: list) -> "CoupledKBMResult":
        n = model.dof
        psis = phases(n) + ((sp.Symbol("theta"),) if model.forced else ())
        gammas = tuple(sp.Symbol(f"gamma{r}") for r in range(1, len(lattice.generators) + 1))
        defs = tuple((g, sp.Add(*[v * p for v, p in zip(k, psis) if v]))
                     for g, k in zip(gammas, lattice.generators))
        a = amplitudes(n)
        return cls(
            model=model, order=order, gammas=defs,
            A=tuple((sp.Integer(0), *[_slow_expr(f, lattice, gammas) for f in A[i]])
                    for i in range(n)),
            B=tuple((model.omegas[i], *[_slow_expr(f, lattice, gammas) for f in B[i]])
                    for i in range(n)),
            u=tuple((a[i] * sp.cos(psis[i]), *[f.as_expr(psis) for f in U[i]])
                    for i in range(n)))

    @classmethod
    def from_one_degree(cls, model: CoupledOscillators, one) -> "CoupledKBMResult":
        """The expansion of an ``N = 1`` system from the one-degree-of-freedom engine's
        :class:`kbm.expansion.result.KBMResult` ``one`` (``a -> a1``, ``psi -> psi1``): the Bessel
        lattice sums of ``sin``/``cos`` of the position above the first order."""
        (a1,), (psi1,) = amplitudes(1), phases(1)
        sub = {sp.Symbol("a"): a1, sp.Symbol("psi"): psi1}
        return cls(model=model, order=one.order, gammas=(),
                   A=((sp.Integer(0), *[e.xreplace(sub) for e in one.A[1:]]),),
                   B=((model.omegas[0], *[e.xreplace(sub) for e in one.B[1:]]),),
                   u=((a1 * sp.cos(psi1), *[e.xreplace(sub) for e in one.u[1:]]),))

    def substituted(self, substitution: dict, tails: Sequence[sp.Expr] | None = None
                    ) -> "CoupledKBMResult":
        """The expansion with the ring's stand-in symbols put back: the Bessel functions
        ``besselj(n, c a_l)`` of :mod:`kbm.algebra.coupled_bessel` and the constants of
        :mod:`kbm.model.constants`; with ``tails``, each ``u_{i,1}`` is completed by
        ``tails[i]``, the sums over the harmonics above the Jacobi-Anger cut
        (:meth:`kbm.algebra.coupled_bessel.JacobiAnger.tail`)."""
        u = self.u
        if tails is not None:
            u = tuple((row[0], row[1] + tail, *row[2:]) for row, tail in zip(u, tails))

        def put(rows):
            return tuple((row[0], *[e.xreplace(substitution) for e in row[1:]])
                         for row in rows)
        return replace(self, A=put(self.A), B=put(self.B), u=put(u))

    # -- the slow flow ------------------------------------------------------------------
    def gamma_rate(self, r: int, n: int) -> sp.Expr:
        """The coefficient of ``mu**n`` (n >= 1) in ``d gamma_r/dt``."""
        _, comb = self.gammas[r]
        psis = phases(self.model.dof)
        rate = sum((comb.coeff(p) * self.B[i][n] for i, p in enumerate(psis)), sp.Integer(0))
        if n == 1 and self.model.forced and self.model.nu_detuning:
            rate += comb.coeff(sp.Symbol("theta")) * sp.Symbol(self.model.nu_detuning)
        return sp.expand(rate)

    def slow_flow(self, order: int | None = None) -> tuple[sp.Expr, ...]:
        """``(da_1/dt, ..., da_N/dt, dgamma_1/dt, ...)`` to ``order`` (default all), in
        ``a``, ``gamma`` and ``mu``."""
        N = self.order if order is None else order
        n = self.model.dof
        rates = [sum((mu**k * self.A[i][k] for k in range(1, N + 1)), sp.Integer(0))
                 for i in range(n)]
        rates += [sum((mu**k * self.gamma_rate(r, k) for k in range(1, N + 1)), sp.Integer(0))
                  for r in range(len(self.gammas))]
        return tuple(rates)

    def frequencies(self, order: int | None = None) -> tuple[sp.Expr, ...]:
        """``dpsi_i/dt = omega_i + sum mu**n B_{i,n}`` to ``order``."""
        N = self.order if order is None else order
        return tuple(sum((mu**k * self.B[i][k] for k in range(N + 1)), sp.Integer(0))
                     for i in range(self.model.dof))

    def numpy_slow_flow(self, params: dict | None = None, order: int | None = None
                        ) -> Callable[[np.ndarray, float], np.ndarray]:
        """``f(y, mu)`` with ``y = (a_1..a_N, gamma_1..)``: the slow flow as numpy.

        Parameters left symbolic must be given in ``params``.

        Raises
        ------
        kbm.errors.ParameterError
            If a parameter has no value.
        """
        from ..errors import ParameterError

        rates = self.slow_flow(order)
        sub = {sp.Symbol(k): sp.nsimplify(v) if isinstance(v, str) else v
               for k, v in (params or {}).items()}
        rates = [r.subs(sub) for r in rates]
        state = [*amplitudes(self.model.dof), *[g for g, _ in self.gammas]]
        left = sorted({s.name for r in rates for s in r.free_symbols} - {s.name for s in state}
                      - {"mu"})
        if left:
            raise ParameterError(f"give a value to {', '.join(left)} for the numeric slow "
                                 "flow")
        fn = sp.lambdify([state, mu], rates, ["numpy", "scipy"])  # scipy: besselj

        def flow(y, mu_value):
            return np.asarray(fn(list(y), mu_value), dtype=float)

        return flow

    # -- output -----------------------------------------------------------------------
    def to_json(self) -> dict:
        """``model``, ``order``, ``omega0``, ``F``, ``internal``, ``gammas`` and ``A``,
        ``B``, ``u``: per degree of freedom a list indexed by order (entry 0 null), each
        entry a string :func:`kbm.parse` reads back; ``gamma_rates`` likewise per phase
        combination."""
        return {
            "model": self.model.name, "order": self.order, "dof": self.model.dof,
            "omega0": [str(w) for w in self.model.omegas],
            "F": [_lex(f) for f in self.model.rhs],
            "internal": [str(r) for r in self.model.internal],
            "gammas": {str(g): _lex(e) for g, e in self.gammas},
            "exact": True,
            "A": [by_order(Ai) for Ai in self.A],
            "B": [by_order(Bi) for Bi in self.B],
            "gamma_rates": {str(g): [None] + [_lex(self.gamma_rate(r, k))
                                              for k in range(1, self.order + 1)]
                            for r, (g, _) in enumerate(self.gammas)},
            "u": [by_order(ui) for ui in self.u],
        }

    def pretty(self) -> str:
        """A plain-text summary, one line per quantity: the equations, the forcing angle
        ``theta``, the form of the solution (what ``A_i,n``, ``B_i,n`` are), the declared
        resonances and slow phases, then the rates."""
        m, N = self.model, self.order
        lines = [f"KBM expansion of {m.name}: {m.dof} degrees of freedom, order {N}"]
        for i, (w, f) in enumerate(zip(m.omegas, m.rhs), 1):
            w2 = w**2
            hard = m.hards[i - 1] if m.hards else 0
            lines.append(f"  x{i}'' + {'' if w2 == 1 else sp.sstr(w2) + '*'}x{i} = "
                         f"mu*({_lex(f)})" + (f" + {sp.sstr(hard)}*cos(theta)" if hard else ""))
        if m.forced:
            nu = sp.sstr(m.nu0) + (f" + mu*{m.nu_detuning}" if m.nu_detuning else "")
            lines.append(f"  forcing angle theta = nu*t, nu = {nu}")
        def series(name: str) -> str:
            return " + ".join(f"mu{'' if k == 1 else f'^{k}'}*{name}_i,{k}"
                              for k in range(1, N + 1))
        shift = (" + Lambda_i*cos(theta)" if any(k != 0 for k in m.hards) else "")
        lines += [f"the solution: x_i = a_i*cos(psi_i){shift} + {series('u')} "
                  "(u_i,n: --json, --latex)",
                  f"  da_i/dt = {series('A')}",
                  f"  dpsi_i/dt = omega_i + {series('B')}",
                  f"  A_i,n, B_i,n: mode i, the coefficient of mu^n; omega = "
                  f"({', '.join(sp.sstr(w) for w in m.omegas)})"]
        if shift:
            lines.append("  Lambda_i = K_i/(omega_i^2 - nu^2): the response to the hard "
                         "forcing K_i*cos(theta)")
        if m.internal:
            lines.append("resonances: " + ", ".join(_resonance(r) for r in m.internal))
        for g, e in self.gammas:
            lines.append(f"slow phase {g} = {_lex(e)}")
        for i in range(m.dof):
            for k in range(1, N + 1):
                lines.append(f"A_{i + 1},{k} = {_lex(self.A[i][k])}")
            for k in range(1, N + 1):
                lines.append(f"B_{i + 1},{k} = {_lex(self.B[i][k])}")
        for r, (g, _) in enumerate(self.gammas):
            for k in range(1, N + 1):
                lines.append(f"d{g}/dt [mu^{k}] = {_lex(self.gamma_rate(r, k))}")
        return "\n".join(lines)

    def latex(self) -> str:
        """The expansion as a LaTeX ``align*`` block: ``x_i``, the slow flow, and each
        ``A_{i,n}``, ``B_{i,n}``, ``u_{i,n}`` and slow-phase rate, long ones broken into
        lines (:func:`kbm.output.latex.equation_lines`)."""
        from ..output.latex import align_block, latex as to_latex

        m, N = self.model, self.order
        width = 90

        def mus(symbol: str) -> str:
            return " + ".join(rf"\mu^{{{k}}} {symbol.format(k=k)}" for k in range(1, N + 1))

        rows = []
        for i in range(m.dof):
            j = i + 1
            hard = (rf"\Lambda_{{{j}}}\cos\theta + " if m.hards and m.hards[i] != 0 else "")
            rows += [rf"x_{{{j}}} &= a_{{{j}}}\cos\psi_{{{j}}} + {hard}"
                     + mus(f"u_{{{{{j},{{k}}}}}}"),
                     rf"\dot a_{{{j}}} &= " + mus(f"A_{{{{{j},{{k}}}}}}"),
                     rf"\dot\psi_{{{j}}} &= {to_latex(m.omegas[i])} + "
                     + mus(f"B_{{{{{j},{{k}}}}}}")]
        for group in self.latex_groups(width):
            rows += group
        return align_block(rows)

    def latex_groups(self, width: int = 90, *, with_u: bool = True,
                     expand_above: int | None = None) -> list[list[str]]:
        """The ``align`` rows of the expansion in groups: per degree of freedom its
        ``A_{i,n}``, ``B_{i,n}`` (and ``u_{i,n}``), then per slow phase its definition and
        rates; each broken into lines of about ``width`` characters, and an expression whose
        LaTeX is longer than ``expand_above`` expanded first so that it can be broken."""
        from ..output.latex import equation_lines, latex as to_latex

        N = self.order

        def shown(e: sp.Expr) -> sp.Expr:
            long = expand_above is not None and len(to_latex(e)) > expand_above
            return sp.expand(e) if long else e

        groups = []
        for i in range(self.model.dof):
            tables = [("A", self.A), ("B", self.B)] + ([("u", self.u)] if with_u else [])
            groups.append([equation_lines(f"{name}_{{{i + 1},{k}}}",
                                          shown(table[i][k]) if name != "u" else table[i][k],
                                          width)
                           for name, table in tables for k in range(1, N + 1)])
        for r, (g, comb) in enumerate(self.gammas):
            groups.append([f"{to_latex(g)} &= {to_latex(comb)}"]
                          + [equation_lines(rf"\dot{{{to_latex(g)}}}\big|_{{\mu^{{{k}}}}}",
                                            self.gamma_rate(r, k), width)
                             for k in range(1, N + 1)])
        return groups
