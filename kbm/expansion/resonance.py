"""Internal resonances of coupled oscillators and the lattice of slow harmonics.

A resonance ``omega_i : omega_j = p : q`` (``q omega_i = p omega_j``) makes the phase
combination ``gamma = p psi_j - q psi_i`` slow; the declared resonances generate the
lattice of *slow* harmonics ``k`` (``k . omega = 0``) that the averaged equations keep
(Nayfeh & Mook, *Nonlinear Oscillations*, 1979, secs. 6.5-6.6).  A harmonic whose
frequency ``k . omega`` vanishes (or nearly does) but which is not in the declared
lattice is an undeclared resonance: :class:`UndeclaredResonanceError` names it.
"""

from __future__ import annotations

import itertools
import re
from dataclasses import dataclass
from fractions import Fraction
from functools import lru_cache
from math import gcd

import numpy as np
import sympy as sp

from ..errors import ModelError

__all__ = ["InternalResonance", "SlowLattice", "UndeclaredResonanceError"]

_SYNTAX = re.compile(r"^\s*(\d+)\s*:\s*(\d+)\s*(?:@\s*(\d+)\s*,\s*(\d+|F)\s*)?$")


class UndeclaredResonanceError(ModelError):
    """A harmonic of the expansion is (nearly) resonant but its resonance was not declared;
    the message names it and the declaration that would treat it."""


@dataclass(frozen=True)
class InternalResonance:
    """``omega_i : omega_j = p : q`` between the modes ``i`` and ``j`` (counted from 1).

    ``detuning``: the name of ``sigma`` in ``omega_j = (q/p) omega_i + mu sigma``, or
    ``None`` when the frequencies are exactly in the ratio (a detuning may then be written
    in ``F``).
    """

    i: int
    j: int
    p: int
    q: int
    detuning: str | None = None
    forcing: bool = False

    @classmethod
    def parse(cls, text: str, dof: int, detuning: str | None = None, *,
              forced: bool = False) -> "InternalResonance":
        """Read ``"P:Q"`` (modes 1 and 2) or ``"P:Q@I,J"``; ``J = F`` is the forcing angle of
        a forced system (``"1:1@2,F"``: ``omega_2 : nu = 1 : 1``).

        Raises
        ------
        kbm.errors.ModelError
            For other text, modes out of range or equal, or a zero ratio.
        """
        m = _SYNTAX.match(str(text))
        if not m:
            raise ModelError(f"cannot read the internal resonance {text!r}: write P:Q for "
                             "omega_1 : omega_2 = P : Q (e.g. 1:3), or P:Q@I,J for modes I "
                             "and J")
        p, q = int(m.group(1)), int(m.group(2))
        if m.group(4) == "F":
            if not forced:
                raise ModelError(f"the resonance {text!r} names the forcing (F), but the system "
                                 "has no forcing frequency nu0")
            i, j = int(m.group(3)), dof + 1
            dof = dof + 1
        else:
            i, j = (int(m.group(3)), int(m.group(4))) if m.group(3) else (1, 2)
        if p == 0 or q == 0:
            raise ModelError(f"the internal resonance {text!r} has a zero in its ratio; "
                             "P and Q are positive integers")
        if not (1 <= i <= dof and 1 <= j <= dof) or i == j:
            raise ModelError(f"the internal resonance {text!r} needs two different modes "
                             f"among 1..{dof}" + (" (a system of one degree of freedom has "
                                                  "no internal resonance)" if dof == 1 else ""))
        g = gcd(p, q)
        return cls(i, j, p // g, q // g, detuning, m.group(4) == "F")

    def check(self, omega: tuple) -> None:
        """Raise :class:`~kbm.errors.ModelError` unless ``omega_i : omega_j = p : q``."""
        wi, wj = omega[self.i - 1], omega[self.j - 1]
        name_j = "nu0" if self.forcing else f"omega{self.j}"
        if wi * self.q != wj * self.p:
            raise ModelError(
                f"omega{self.i} = {wi} and {name_j} = {wj} are not in the declared ratio "
                f"{self.p}:{self.q}: give the frequencies of the exact resonance and the "
                f"detuning separately (in F as -2*omega{self.j}*sigma*x{self.j}, or as the "
                f"resonance's detuning)")

    def vector(self, dof: int) -> tuple[int, ...]:
        """The slow harmonic ``k`` of ``gamma = p psi_j - q psi_i``."""
        k = [0] * dof
        k[self.j - 1] += self.p
        k[self.i - 1] -= self.q
        return tuple(k)

    def __str__(self) -> str:
        pair = f"@{self.i},F" if self.forcing else \
            "" if (self.i, self.j) == (1, 2) else f"@{self.i},{self.j}"
        return f"{self.p}:{self.q}{pair}" + (f" (detuning {self.detuning})"
                                              if self.detuning else "")


class SlowLattice:
    """The integer combinations of the declared resonances' vectors.

    ``coords(k)`` gives the integer coordinates of ``k`` in the generators, or ``None``.
    """

    def __init__(self, dof: int, resonances: tuple[InternalResonance, ...]):
        self.dof = dof
        self.generators = tuple(r.vector(dof) for r in resonances)
        if self.generators and not _independent(self.generators):
            raise ModelError(f"the declared internal resonances "
                             f"{', '.join(map(str, resonances))} are not independent: "
                             "declare each once")

    def coords(self, k: tuple[int, ...]) -> tuple[int, ...] | None:
        """Integer ``c`` with ``k = sum_r c_r g_r``, or ``None``."""
        return _coords(self.generators, k)


@lru_cache(maxsize=256)
def _independent(generators: tuple) -> bool:
    """Whether the lattice's generators are linearly independent.

    Pure-function memo (every expansion builds its lattice): the key is a tuple of integer
    tuples, the value a ``bool`` computed from it alone."""
    return sp.Matrix([list(g) for g in generators]).T.rank() == len(generators)


@lru_cache(maxsize=1 << 14)
def _coords(generators: tuple, k: tuple) -> tuple[int, ...] | None:
    """:meth:`SlowLattice.coords`.

    Pure-function memo (the same harmonics are classified by every order and expansion; the
    Gauss-Jordan solve is slow): the key is tuples of integers, the value a tuple of
    integers or ``None`` computed from them alone."""
    if not any(k):
        return (0,) * len(generators)
    if not generators:
        return None
    M = sp.Matrix([list(g) for g in generators]).T
    try:
        sol, params = M.gauss_jordan_solve(sp.Matrix(list(k)))
    except ValueError:
        return None
    if not params.shape[0] and all(v.is_Integer for v in sol):
        return tuple(int(v) for v in sol)
    return None


def frequency(k: tuple[int, ...], omega: tuple) -> Fraction:
    """``k . omega`` as an exact fraction."""
    return sum((Fraction(int(w.p), int(w.q)) * v for v, w in zip(k, omega)), Fraction(0))


def describe(k: tuple[int, ...], forced: bool = False) -> str:
    """``k . omega`` written out, e.g. ``3*omega1 - omega2`` (the last angle of a forced
    system is ``nu``)."""
    parts = []
    for idx, v in enumerate(k, 1):
        if v:
            mag = "" if abs(v) == 1 else f"{abs(v)}*"
            name = "nu" if forced and idx == len(k) else f"omega{idx}"
            parts.append(("-" if v < 0 else "+") + f" {mag}{name}")
    s = " ".join(parts)
    return s[2:] if s.startswith("+ ") else "-" + s[2:]


def declaration(k: tuple[int, ...], forced: bool = False) -> str | None:
    """The ``--internal`` text of a two-mode resonance vector, or ``None``."""
    nz = [(i, v) for i, v in enumerate(k, 1) if v]
    if len(nz) != 2:
        return None
    (i, vi), (j, vj) = nz
    if vi * vj > 0:
        return None
    # vi omega_i + vj omega_j = 0  ->  omega_i : omega_j = |vj| : |vi|
    p, q = abs(vj), abs(vi)
    g = gcd(p, q)
    p, q = p // g, q // g
    if forced and j == len(k):
        return f"{p}:{q}@{i},F"
    return f"{p}:{q}" if (i, j) == (1, 2) else f"{p}:{q}@{i},{j}"


def resonant_harmonic(h: tuple[int, ...], i: int, n: int, omega: tuple, lattice: SlowLattice,
                      tol: float, forced: bool = False) -> tuple[tuple[int, ...], int] | None:
    """Whether the harmonic ``h`` of ``R_{i,n}`` (mode ``i``'s equation at order ``n``) is
    resonant: ``(k, s)`` with ``h . psi = s (psi_i + k . psi)`` and ``k`` on the slow lattice
    of the declared resonances, or ``None`` when its frequency is more than ``tol`` times
    ``omega_i`` away from ``+-omega_i``.

    Raises
    ------
    UndeclaredResonanceError
        For a harmonic at (or within ``tol`` of) ``+-omega_i`` whose ``k`` is not declared:
        the resonance is named with the ``--internal`` that declares it.
    """
    f = frequency(h, omega)
    wi = Fraction(int(omega[i].p), int(omega[i].q))
    s = 1 if f > 0 else -1
    gap = abs(abs(f) - wi) / wi
    if gap > tol:
        return None
    hs = tuple(s * v for v in h)
    k = tuple(v - (1 if l == i else 0) for l, v in enumerate(hs))
    if gap == 0 and lattice.coords(k) is not None:
        return k, s
    what = "exactly" if gap == 0 else f"within {float(gap):.3g} omega{i + 1} of"
    decl = declaration(k, forced)
    hint = (f"declare it: internal=['{decl}'], with the frequencies "
            f"in the exact ratio and any detuning written in F"
            if decl else "a combination resonance of more than two modes, which kbm "
                         "does not average yet; change the frequencies")
    raise UndeclaredResonanceError(
        f"the frequencies omega = ({', '.join(map(str, omega))}) satisfy "
        f"{describe(k, forced)} = {float(frequency(k, omega)):.6g}, {what} an "
        f"internal resonance that was not declared: the harmonic psi{i + 1} + "
        f"({', '.join(map(str, k))}).psi of R_{i + 1},{n} has a "
        f"{'vanishing' if gap == 0 else 'small'} divisor and the non-resonant averaging "
        f"breaks down; {hint}")


def lattice_on_grid(gens: tuple[tuple[int, ...], ...], D: int, M: int):
    """The wavevectors ``q = sum n_r g_r`` that fit on the grid, with their ``n``."""
    out = []
    lim = M // 2 - 2
    if not gens:
        return [(np.zeros(D, dtype=int), np.zeros(0))]
    span = max(1, lim // max(1, min(max(abs(v) for v in g) for g in gens)))
    for n in itertools.product(range(-span, span + 1), repeat=len(gens)):
        q = np.zeros(D, dtype=int)
        for nr, g in zip(n, gens):
            q += nr * np.asarray(g, dtype=int)
        if np.max(np.abs(q)) <= lim:
            out.append((q, np.asarray(n, dtype=float)))
    return out


def slow_point(dof: int, phases: int, amplitudes, gammas) -> tuple[np.ndarray, np.ndarray]:
    """The amplitudes and slow phases of a point of the slow flow as arrays, checked: ``dof``
    positive finite amplitudes and ``phases`` finite phases (one per declared resonance).

    Raises
    ------
    kbm.errors.ParameterError
        For a count that does not match, or an amplitude that is not positive and finite.
    """
    from ..errors import ParameterError

    a = np.asarray(amplitudes, dtype=float)
    g = np.asarray(gammas, dtype=float)
    if a.shape != (dof,) or not np.all(np.isfinite(a)) or np.any(a <= 0):
        raise ParameterError(f"give {dof} positive amplitudes a1..a{dof}, got {list(a)}")
    if g.shape != (phases,) or not np.all(np.isfinite(g)):
        raise ParameterError(f"give {phases} slow phases (one per declared resonance), got "
                             f"{list(g)}")
    return a, g
