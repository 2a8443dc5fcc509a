"""The one result of a branch of periodic orbits (:mod:`numerics.shooting.continuation`):
:class:`OrbitBranch`, the base of both branch types, rendered as JSON by :class:`Rendered`
in one of two layouts: one degree of freedom's (:class:`Branch`, :class:`BranchPoint`,
:class:`SpecialPoint`; ``kbm branch`` of an oscillator, also as
:mod:`numerics.cycles.branch_result`) and ``N``'s (:class:`CoupledBranch`,
:class:`CoupledBranchPoint`, :class:`CoupledSpecialPoint`; ``kbm branch`` and
``kbm response`` of a coupled system, :mod:`numerics.coupled.continuation`)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from kbm.values import FrozenMap
from kbm.strict_json import finite
from numerics.shooting.orbit import multiplier_json

__all__ = ["Rendered", "OrbitBranch", "BranchPoint", "SpecialPoint", "Branch", "SPECIAL_KINDS",
           "branch_point", "CoupledBranch", "CoupledBranchPoint", "CoupledSpecialPoint"]


class Rendered:
    """A result whose JSON form is its :attr:`layout`, the attributes in that order: a
    result as its JSON, a mapping as floats by sorted key, a tuple as a list, a complex
    multiplier by :func:`~numerics.shooting.orbit.multiplier_json`."""

    layout: ClassVar[tuple[str, ...]] = ()

    def to_json(self) -> dict:
        """The attributes of :attr:`layout` (NaN and infinities as ``null``)."""
        return finite({k: _json(getattr(self, k)) for k in self.layout})


def _json(value: Any) -> Any:
    if isinstance(value, Rendered):
        return value.to_json()
    if isinstance(value, Mapping):
        return {k: float(v) for k, v in sorted(value.items())}
    if isinstance(value, (tuple, list)):
        return [_json(v) for v in value]
    return multiplier_json(value) if isinstance(value, complex) else value


@dataclass(frozen=True, eq=False)
class OrbitBranch(Rendered):
    """A branch of periodic orbits in one parameter: the ``model``'s and the varied
    ``parameter``'s names, its allowed ``bounds``, the ``points`` in the order of arclength,
    the ``special`` points located (folds, ends, ...), the ``reasons`` each direction
    stopped and the cost, ``evaluations`` (integrations of one period)."""

    model: str
    parameter: str
    bounds: tuple[float, float]
    points: tuple
    special: tuple
    reasons: tuple[str, ...]
    evaluations: int

    def folds(self) -> tuple:
        """The special points of kind ``"fold"``."""
        return tuple(s for s in self.special if s.kind == "fold")


#: the labels of special points: a fold of cycles (two cycles merge, the non-trivial
#: multiplier passes through +1), a Hopf end (amplitude -> 0), a homoclinic end (period ->
#: infinity at a separatrix), and an end where the continuation could not go on
SPECIAL_KINDS = ("fold", "hopf", "homoclinic", "end")


@dataclass(frozen=True, eq=False)
class BranchPoint(Rendered):
    """One periodic orbit on a branch of one degree of freedom: the varied ``parameter``,
    the section point ``x0`` (``x'(0) = 0``) the shooting closes, the ``period``,
    ``amplitude_max`` (the largest ``x`` on the orbit), the ``multipliers`` ``(trivial,
    non-trivial)`` (the eigenvalue of the monodromy matrix nearest 1, a check, and
    ``exp(oint div f dt)/trivial``, Liouville), ``stable`` (``|non-trivial| < 1``) and the
    ``residual`` ``|(x(T) - x0, x'(T))|`` at this point."""

    parameter: float
    x0: float
    period: float
    amplitude_max: float
    multipliers: tuple[complex, complex]
    stable: bool
    residual: float

    layout = ("parameter", "amplitude_max", "period", "stable", "multipliers", "x0", "residual")


def branch_point(pt) -> BranchPoint:
    """The record of a converged point of :class:`numerics.shooting.planar.PlanarProblem`."""
    return BranchPoint(parameter=float(pt.u[2]), x0=float(pt.u[0]), period=float(pt.u[1]),
                       amplitude_max=pt.amp, multipliers=pt.mults,
                       stable=bool(abs(pt.mults[1]) < 1.0),
                       residual=float(np.max(np.abs(pt.R))))


@dataclass(frozen=True, eq=False)
class SpecialPoint(Rendered):
    """A labelled point of a branch: its ``kind`` (one of :data:`SPECIAL_KINDS`), where it is
    (``parameter``; ``amplitude`` the largest ``x``, at a Hopf end the ``x`` of the
    equilibrium the cycle shrinks onto; ``period``, at a homoclinic end the last one
    computed) and the ``message`` saying how it was located."""

    kind: str
    parameter: float
    amplitude: float
    period: float
    message: str

    layout = ("kind", "parameter", "amplitude", "period", "message")


@dataclass(frozen=True, eq=False)
class Branch(OrbitBranch):
    """A branch of limit cycles of one degree of freedom in one parameter
    (:class:`OrbitBranch`; :class:`BranchPoint` in the order of arclength, the
    :class:`SpecialPoint` in the order met), with the other parameter values ``params`` (as
    given) and the points it ``dropped``: passed through but not printed, they failed the
    convergence test (:data:`numerics.cycles.continuation.TRIVIAL_TOL`)."""

    params: Mapping[str, object]
    dropped: int = 0

    layout = ("model", "parameter", "params", "bounds", "points", "special", "reasons",
              "evaluations", "dropped")

    def __post_init__(self) -> None:
        object.__setattr__(self, "params", FrozenMap(self.params))


@dataclass(frozen=True)
class CoupledBranchPoint(Rendered):
    """A periodic orbit on a branch: the parameter, the period, the state at the section
    (autonomous: ``xdot_1 = 0``; forced: ``t = 0``), ``max |x_i|`` over the orbit, the
    ``2N`` multipliers (autonomous: the trivial one first) and Newton's last residual."""

    parameter: float
    period: float
    state: tuple[float, ...]
    amplitudes: tuple[float, ...]
    floquet_multipliers: tuple[complex, ...]
    stable: bool
    residual: float

    layout = ("parameter", "period", "state", "amplitudes", "floquet_multipliers", "stable",
              "residual")


@dataclass(frozen=True)
class CoupledSpecialPoint(Rendered):
    """A located special point: ``kind`` is ``fold``, ``period-doubling`` or
    ``neimark-sacker``; ``bracket`` the final bisection interval of the parameter, ``state``
    the orbit's state at the section (a symmetric system has its partner orbit's point at
    the same parameter: both are listed)."""

    kind: str
    parameter: float
    period: float
    amplitudes: tuple[float, ...]
    floquet_multipliers: tuple[complex, ...]
    bracket: tuple[float, float]
    state: tuple[float, ...] = ()

    layout = ("kind", "parameter", "period", "amplitudes", "floquet_multipliers", "bracket",
              "state")


@dataclass(frozen=True)
class CoupledBranch(OrbitBranch):
    """A branch of periodic orbits of a coupled system in one parameter
    (:class:`~numerics.shooting.branch_result.OrbitBranch`), autonomous or ``forced``, of
    ``dof`` degrees of freedom.

    ``reasons`` says why each direction ended (the range's end, a collapse of the steps
    with the numbers, the period's growth, the amplitude's decay to a Hopf point).
    """

    forced: bool
    dof: int

    layout = ("model", "parameter", "bounds", "forced", "dof", "points", "special", "reasons",
              "evaluations")
