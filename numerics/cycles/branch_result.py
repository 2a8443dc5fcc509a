"""Results of the continuation of limit cycles: :class:`BranchPoint`, :class:`SpecialPoint`,
:class:`Branch` (frozen, compared by identity, with ``to_json``)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from kbm.values import FrozenMap

from kbm.strict_json import finite
from numerics.shooting.orbit import multiplier_json

__all__ = ["BranchPoint", "SpecialPoint", "Branch", "SPECIAL_KINDS", "branch_point"]

#: the labels of special points: a fold of cycles (two cycles merge, the non-trivial
#: multiplier passes through +1), a Hopf end (amplitude -> 0), a homoclinic end (period ->
#: infinity at a separatrix), and an end where the continuation could not go on
SPECIAL_KINDS = ("fold", "hopf", "homoclinic", "end")


@dataclass(frozen=True, eq=False)
class BranchPoint:
    """One periodic orbit on a branch.

    Attributes
    ----------
    parameter : float
        Value of the varied parameter.
    x0 : float
        Section point ``x(0)`` (``x'(0) = 0``) the shooting closes.
    period : float
        ``T``.
    amplitude_max : float
        Largest ``x`` on the orbit (``x0`` or a larger sample of the orbit).
    multipliers : tuple of complex
        ``(trivial, non-trivial)``: the eigenvalue of the monodromy matrix closest to 1
        (a check) and ``exp(oint div f dt)/trivial`` (Liouville).
    stable : bool
        ``|non-trivial multiplier| < 1``.
    residual : float
        ``|(x(T) - x0, x'(T))|`` at this point.
    """

    parameter: float
    x0: float
    period: float
    amplitude_max: float
    multipliers: tuple[complex, complex]
    stable: bool
    residual: float

    def to_json(self) -> dict:
        """``parameter, amplitude_max, period, stable, multipliers`` (and ``x0``, ``residual``)."""
        return finite({"parameter": self.parameter, "amplitude_max": self.amplitude_max,
                       "period": self.period, "stable": self.stable,
                       "multipliers": [multiplier_json(m) for m in self.multipliers],
                       "x0": self.x0, "residual": self.residual})


def branch_point(pt) -> BranchPoint:
    """The record of a converged point of :class:`numerics.shooting.planar.PlanarProblem`."""
    return BranchPoint(parameter=float(pt.u[2]), x0=float(pt.u[0]), period=float(pt.u[1]),
                       amplitude_max=pt.amp, multipliers=pt.mults,
                       stable=bool(abs(pt.mults[1]) < 1.0),
                       residual=float(np.max(np.abs(pt.R))))


@dataclass(frozen=True, eq=False)
class SpecialPoint:
    """A labelled point of a branch.

    Attributes
    ----------
    kind : str
        One of :data:`SPECIAL_KINDS`.
    parameter, amplitude, period : float
        Where it is (``amplitude`` the largest ``x``; at a Hopf end the ``x`` of the
        equilibrium the cycle shrinks onto; the period is
        ``inf`` unknown at a homoclinic end: the last period computed is given).
    message : str
        How it was located.
    """

    kind: str
    parameter: float
    amplitude: float
    period: float
    message: str

    def to_json(self) -> dict:
        """``kind, parameter, amplitude`` (and ``period``, ``message``)."""
        return finite({"kind": self.kind, "parameter": self.parameter,
                       "amplitude": self.amplitude, "period": self.period,
                       "message": self.message})


@dataclass(frozen=True, eq=False)
class Branch:
    """A branch of periodic orbits in one parameter.

    Attributes
    ----------
    model, parameter : str
        The model's name and the varied parameter's name.
    params : Mapping
        The other parameter values (as given).
    bounds : tuple of float
        The range of the parameter that was allowed.
    points : tuple of BranchPoint
        In the order of arclength.
    special : tuple of SpecialPoint
        Folds, ends (Hopf, homoclinic, failures), in the order met.
    reasons : tuple of str
        Why the continuation stopped (one per direction followed).
    evaluations : int
        Number of integrations of one period (the cost).
    dropped : int
        Points the continuation passed through but did not print: they failed the
        convergence test (:data:`numerics.cycles.continuation.TRIVIAL_TOL`).
    """

    model: str
    parameter: str
    params: Mapping[str, object]
    bounds: tuple[float, float]
    points: tuple[BranchPoint, ...]
    special: tuple[SpecialPoint, ...]
    reasons: tuple[str, ...]
    evaluations: int
    dropped: int = 0

    def __post_init__(self) -> None:
        object.__setattr__(self, "params", FrozenMap(self.params))

    def folds(self) -> tuple[SpecialPoint, ...]:
        """The special points of kind ``"fold"``."""
        return tuple(s for s in self.special if s.kind == "fold")

    def to_json(self) -> dict:
        """``model, parameter, params, bounds, points, special, reasons, evaluations``."""
        return finite({"model": self.model, "parameter": self.parameter,
                       "params": {k: float(v) for k, v in sorted(self.params.items())},
                       "bounds": list(self.bounds),
                       "points": [p.to_json() for p in self.points],
                       "special": [s.to_json() for s in self.special],
                       "reasons": list(self.reasons), "evaluations": self.evaluations,
                       "dropped": self.dropped})
