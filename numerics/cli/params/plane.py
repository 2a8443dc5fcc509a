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

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field

from kbm.errors import ParameterError
from kbm.parameters.names import PhysicalAxis, physical_axis

__all__ = ["Plane"]


@dataclass(frozen=True)
class Plane:
    """The user's axes ``user`` over ``user_ranges``, computed as ``axes`` over
    ``ranges``; ``back[i]`` maps a value of ``axes[i]`` to one of ``user[i]`` (the two
    :class:`kbm.parameters.names.PhysicalAxis` bindings, ``bound``)."""

    bound: tuple[PhysicalAxis, PhysicalAxis]
    user: tuple[str, str] = field(init=False)
    user_ranges: Mapping[str, tuple[float, float]] = field(init=False)
    axes: tuple[str, str] = field(init=False)
    ranges: Mapping[str, tuple[float, float]] = field(init=False)
    back: tuple[Callable[[float], float], Callable[[float], float]] = field(init=False)

    def __post_init__(self):
        b = self.bound
        for key, value in (("user", (b[0].user, b[1].user)),
                           ("user_ranges", {a.user: (a.lo, a.hi) for a in b}),
                           ("axes", (b[0].name, b[1].name)),
                           ("ranges", {a.name: a.span for a in b}),
                           ("back", (b[0].to_user, b[1].to_user))):
            object.__setattr__(self, key, value)

    @classmethod
    def of(cls, model, params: Mapping[str, object], axes: Sequence[str],
           ranges: Mapping[str, tuple[float, float]]) -> "Plane":
        """The plane of ``axes`` (as given) for ``model`` with ``-p`` values ``params``: the
        diagram's rules for which physical axis it maps, each bound by
        :func:`kbm.parameters.names.physical_axis` (a map's other inputs from ``params``, else the
        model's defaults).

        Raises
        ------
        kbm.errors.ParameterError
            For a scaled parameter that would depend on both axes or on the ``mu`` axis
            through a fixed physical value, a missing value of a physical map's input, or
            a range on which the scaled value is not finite and monotone.
        """
        import sympy as sp

        physical = dict(getattr(model, "physical", {}) or {})
        defaults = dict(getattr(model, "defaults", {}) or {})
        axes = tuple(axes)
        maps: dict[str, tuple[str, object]] = {}  # axis -> (scaled, expression)
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
            if name in maps:
                raise ParameterError(f"--vary {name} sets more than one of the model's "
                                     f"parameters; vary {scaled} instead")
            for other in sorted(inputs - {name}):
                if params.get(other, defaults.get(other)) is None:
                    raise ParameterError(f"{rule} needs a value of {other}: give -p "
                                         f"{other}=VALUE")
            maps[name] = (scaled, expr)
        bound = []
        for name in axes:
            lo, hi = ranges[name]
            if name not in maps:
                bound.append(PhysicalAxis(name, float(lo), float(hi), name,
                                          (float(lo), float(hi))))
                continue
            scaled, expr = maps[name]
            ax = physical_axis({scaled: expr}, name, lo, hi, {**defaults, **params})
            if not ax.monotone:
                raise ParameterError(f"--vary {name}={lo:g}:{hi:g}: {ax.rule} is not finite "
                                     "on this range; give a range where it is")
            bound.append(ax)
        return cls(tuple(bound))

    def point(self, p: Sequence[float]) -> tuple[float, float]:
        """A point of the computed plane in the user's names."""
        return self.back[0](p[0]), self.back[1](p[1])
