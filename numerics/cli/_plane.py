"""The two ``--vary`` axes of a forced or coupled ``kbm diagram`` in the model's own names.

The computations of :mod:`numerics.bifurcation` run in the model's own (scaled) parameters
(``delta``, ``k`` of ``sedf-dimer``); the command line takes the physical names as well
(``Delta``, ``lam``: ``delta = Delta/mu``, ``k = 2 pi/lam``, the model's ``physical``
map), for ``-p`` and for ``--vary`` alike.  :class:`Plane` turns a physical axis into its
scaled one (the range mapped, in increasing order) and the points found back into the
names and values the user gave.  A scaled parameter that would depend on both axes, or on
the ``mu`` axis through a physical value held fixed (``-p Delta=0.5 --vary mu=...``: the
scaled ``delta = Delta/mu`` changes along the axis), is refused with what to give instead.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field

from kbm.errors import ParameterError

__all__ = ["Plane"]


def _identity(x: float) -> float:
    return float(x)


@dataclass(frozen=True)
class Plane:
    """The user's axes ``user`` over ``user_ranges``, computed as ``axes`` over
    ``ranges``; ``back[i]`` maps a value of ``axes[i]`` to one of ``user[i]``."""

    user: tuple[str, str]
    user_ranges: Mapping[str, tuple[float, float]]
    axes: tuple[str, str]
    ranges: Mapping[str, tuple[float, float]]
    back: tuple[Callable[[float], float], Callable[[float], float]] = field(
        default=(_identity, _identity))

    @classmethod
    def of(cls, model, params: Mapping[str, object], axes: Sequence[str],
           ranges: Mapping[str, tuple[float, float]]) -> "Plane":
        """The plane of ``axes`` (as given) for ``model`` with ``-p`` values ``params``.

        Raises
        ------
        kbm.errors.ParameterError
            For a scaled parameter that would depend on both axes or on the ``mu`` axis
            through a fixed physical value, a missing value of a physical map's input, or
            a range on which the scaled value is not finite.
        """
        import sympy as sp

        physical = dict(getattr(model, "physical", {}) or {})
        defaults = dict(getattr(model, "defaults", {}) or {})
        axes = tuple(axes)
        new_axes, new_ranges, back = list(axes), dict(ranges), [_identity, _identity]
        for scaled, expr in physical.items():
            expr = sp.sympify(expr)
            inputs = {s.name for s in expr.free_symbols}
            on = sorted(inputs & set(axes))
            if not on or scaled in params or scaled in axes:
                continue
            rule = f"{scaled} = {sp.sstr(expr)}"
            if len(on) > 1 or on == ["mu"]:
                fixed = sorted(inputs - set(axes))
                raise ParameterError(
                    f"{rule} would change along the --vary {' and '.join(on)} "
                    f"ax{'es' if len(on) > 1 else 'is'}: a diagram "
                    f"varies two of the model's parameters; give the scaled -p {scaled}=VALUE "
                    + (f"instead of -p {', '.join(fixed)}" if fixed else "")
                    + (f" or vary {scaled} itself (--vary {scaled}=FROM:TO)"
                       if len(on) > 1 else ""))
            name = on[0]
            i = axes.index(name)
            if new_axes[i] != name:
                raise ParameterError(f"--vary {name} sets more than one of the model's "
                                     f"parameters; vary {scaled} instead")
            subs = {}
            for other in sorted(inputs - {name}):
                value = params.get(other, defaults.get(other))
                if value is None:
                    raise ParameterError(f"{rule} needs a value of {other}: give -p "
                                         f"{other}=VALUE")
                subs[sp.Symbol(other)] = sp.nsimplify(value) if isinstance(value, str) \
                    else sp.sympify(value)
            sym, image = sp.Symbol(name), sp.Symbol(scaled)
            one = expr.subs(subs)
            solved = sp.solve(sp.Eq(image, one), sym)
            if len(solved) != 1:
                raise ParameterError(f"--vary {name}: {rule} cannot be turned back into "
                                     f"{name}; vary {scaled} instead")
            forward = sp.lambdify(sym, one, "math")
            inverse = sp.lambdify(image, solved[0], "math")
            lo, hi = ranges[name]
            try:
                ends = sorted((float(forward(lo)), float(forward(hi))))
            except (ZeroDivisionError, ValueError, OverflowError):
                ends = [math.nan, math.nan]
            if not all(math.isfinite(e) for e in ends):
                raise ParameterError(f"--vary {name}={lo:g}:{hi:g}: {rule} is not finite "
                                     "on this range; give a range where it is")
            new_axes[i] = scaled
            del new_ranges[name]
            new_ranges[scaled] = (ends[0], ends[1])
            back[i] = (lambda f: lambda x: float(f(x)))(inverse)
        return cls(axes, dict(ranges), tuple(new_axes), new_ranges, tuple(back))

    @property
    def mapped(self) -> bool:
        """Whether an axis is computed in another name than the user's."""
        return self.axes != self.user

    def point(self, p: Sequence[float]) -> tuple[float, float]:
        """A point of the computed plane in the user's names."""
        return self.back[0](p[0]), self.back[1](p[1])
