"""The one result of a branch of periodic orbits of ``N`` degrees of freedom
(:mod:`numerics.shooting.continuation`): :class:`OrbitBranch`, its points
:class:`OrbitBranchPoint` and special points :class:`OrbitSpecialPoint`, rendered as JSON by
:class:`kbm.output.strict_json.Rendered` in one of two layouts: ``N``'s (also named :class:`CoupledBranch`,
:class:`CoupledBranchPoint`, :class:`CoupledSpecialPoint`; ``kbm branch`` and ``kbm response``
of a coupled system, :mod:`numerics.shooting.coupled_branch`) and that of one degree of freedom
on the section ``x' = 0``, the case ``N = 1`` (:class:`Branch`, :class:`BranchPoint`,
:class:`SpecialPoint`; ``kbm branch`` of an oscillator)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from kbm.output.strict_json import Rendered
from kbm.parameters.values import FrozenMap

__all__ = ["OrbitBranch", "OrbitBranchPoint", "OrbitSpecialPoint", "BranchPoint",
           "SpecialPoint", "Branch", "SPECIAL_KINDS", "branch_point", "CoupledBranch",
           "CoupledBranchPoint", "CoupledSpecialPoint"]


@dataclass(frozen=True, eq=False)
class OrbitBranch(Rendered):
    """A branch of periodic orbits in one parameter, autonomous or ``forced``, of ``dof``
    degrees of freedom: the ``model``'s and the varied ``parameter``'s names, its allowed
    ``bounds``, the ``points`` (:class:`OrbitBranchPoint`) in the order of arclength, the
    ``special`` points located (:class:`OrbitSpecialPoint`: folds, ends, ...), the
    ``reasons`` each direction stopped (the range's end, a collapse of the steps with the
    numbers, the period's growth, the amplitude's decay to a Hopf point), the cost,
    ``evaluations`` (integrations of one period), the other parameter values ``params`` and
    the points ``dropped`` (they failed the convergence test)."""

    model: str
    parameter: str
    bounds: tuple[float, float]
    points: tuple
    special: tuple
    reasons: tuple[str, ...]
    evaluations: int
    params: Mapping[str, object] = field(default_factory=dict)
    dropped: int = 0
    forced: bool = False
    dof: int = 1

    layout = ("model", "parameter", "bounds", "forced", "dof", "points", "special", "reasons",
              "evaluations")

    def __post_init__(self) -> None:
        object.__setattr__(self, "params", FrozenMap(self.params))

    def folds(self) -> tuple:
        """The special points of kind ``"fold"``."""
        return tuple(s for s in self.special if s.kind == "fold")


#: the labels of special points: a fold of cycles (two cycles merge, the non-trivial
#: multiplier passes through +1), a Hopf end (amplitude -> 0), a homoclinic end (period ->
#: infinity at a separatrix), and an end where the continuation could not go on
SPECIAL_KINDS = ("fold", "hopf", "homoclinic", "end")


@dataclass(frozen=True, eq=False)
class OrbitBranchPoint(Rendered):
    """A periodic orbit on a branch of ``N`` degrees of freedom: the parameter, the period,
    the ``state`` at the section (autonomous: ``xdot_1 = 0``; forced: ``t = 0``), ``max
    |x_i|`` over the orbit (``amplitudes``), the ``2N`` multipliers (autonomous: the trivial
    one first), ``stable`` (every non-trivial one inside the unit circle) and Newton's last
    ``residual``.  One degree of freedom on ``x' = 0`` is the case ``N = 1``
    (:class:`BranchPoint`): :attr:`x0`, :attr:`amplitude_max` and :attr:`multipliers` name
    its parts."""

    parameter: float
    period: float
    state: tuple[float, ...]
    amplitudes: tuple[float, ...]
    floquet_multipliers: tuple[complex, ...]
    stable: bool
    residual: float

    layout = ("parameter", "period", "state", "amplitudes", "floquet_multipliers", "stable",
              "residual")

    #: the names of one degree of freedom: ``x_1`` at the section, ``max x_1``, the multipliers
    x0 = property(lambda self: self.state[0])
    amplitude_max = property(lambda self: self.amplitudes[0])
    multipliers = property(lambda self: self.floquet_multipliers)


class BranchPoint(OrbitBranchPoint):
    """The case ``N = 1`` on the section ``x' = 0`` (state ``(x0, 0)``) in its layout: the
    ``multipliers`` are ``(trivial, non-trivial)`` (the eigenvalue of the monodromy matrix
    nearest 1, a check, and ``exp(oint div f dt)/trivial``, Liouville)."""

    layout = ("parameter", "amplitude_max", "period", "stable", "multipliers", "x0", "residual")

    def __init__(self, parameter: float, x0: float, period: float, amplitude_max: float,
                 multipliers: tuple[complex, complex], stable: bool, residual: float):
        super().__init__(parameter, period, (x0, 0.0), (amplitude_max,), multipliers, stable,
                         residual)


def branch_point(pt) -> BranchPoint:
    """The record of a converged point of :class:`numerics.shooting.planar.PlanarProblem`."""
    return BranchPoint(parameter=float(pt.u[2]), x0=float(pt.u[0]), period=float(pt.u[1]),
                       amplitude_max=pt.amp, multipliers=pt.mults,
                       stable=bool(abs(pt.mults[1]) < 1.0),
                       residual=float(np.max(np.abs(pt.R))))


@dataclass(frozen=True, eq=False)
class OrbitSpecialPoint(Rendered):
    """A located special point: its ``kind`` (one of :data:`SPECIAL_KINDS`, or
    ``period-doubling``, ``neimark-sacker``), the ``parameter``, the ``period``, the
    ``amplitudes`` and multipliers there, the final bisection ``bracket`` of the parameter,
    the orbit's ``state`` at the section (a symmetric system has its partner orbit's point at
    the same parameter: both are listed) and the ``message`` saying how it was located.  One
    degree of freedom is the case :class:`SpecialPoint`."""

    kind: str
    parameter: float
    period: float
    amplitudes: tuple[float, ...]
    floquet_multipliers: tuple[complex, ...]
    bracket: tuple[float, float]
    state: tuple[float, ...] = ()
    message: str = ""

    layout = ("kind", "parameter", "period", "amplitudes", "floquet_multipliers", "bracket",
              "state")

    #: the first amplitude (one degree of freedom: the largest ``x``, at a Hopf end the
    #: ``x`` of the equilibrium the cycle shrinks onto)
    amplitude = property(lambda self: self.amplitudes[0])


class SpecialPoint(OrbitSpecialPoint):
    """The case of one degree of freedom in its layout (``period``: at a homoclinic end the
    last one computed)."""

    layout = ("kind", "parameter", "amplitude", "period", "message")

    def __init__(self, kind: str, parameter: float, amplitude: float, period: float,
                 message: str):
        super().__init__(kind, parameter, period, (amplitude,), (), (parameter, parameter),
                         message=message)


class Branch(OrbitBranch):
    """A branch of limit cycles of one degree of freedom (:class:`BranchPoint`,
    :class:`SpecialPoint`) in its layout; ``dropped``: the points that failed the
    convergence test (:data:`numerics.shooting.acceptance.TRIVIAL_TOL`)."""

    layout = ("model", "parameter", "params", "bounds", "points", "special", "reasons",
              "evaluations", "dropped")


#: the coupled system's names of the one result
CoupledBranch, CoupledBranchPoint, CoupledSpecialPoint = (OrbitBranch, OrbitBranchPoint,
                                                          OrbitSpecialPoint)
