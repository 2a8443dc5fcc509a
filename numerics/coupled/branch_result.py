"""What a branch of periodic orbits of a coupled system returns (``kbm branch``,
``kbm response`` for ``N`` degrees of freedom, :mod:`numerics.coupled.continuation`): its
points, its located special points and the branch, with their JSON forms."""

from __future__ import annotations

from dataclasses import dataclass

from numerics.shooting.orbit import multiplier_json

__all__ = ["CoupledBranch", "CoupledBranchPoint", "CoupledSpecialPoint"]


@dataclass(frozen=True)
class CoupledBranchPoint:
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

    def to_json(self) -> dict:
        return {"parameter": self.parameter, "period": self.period,
                "state": list(self.state), "amplitudes": list(self.amplitudes),
                "floquet_multipliers": [multiplier_json(z) for z in self.floquet_multipliers],
                "stable": self.stable, "residual": self.residual}


@dataclass(frozen=True)
class CoupledSpecialPoint:
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

    def to_json(self) -> dict:
        return {"kind": self.kind, "parameter": self.parameter, "period": self.period,
                "amplitudes": list(self.amplitudes),
                "floquet_multipliers": [multiplier_json(z) for z in self.floquet_multipliers],
                "bracket": list(self.bracket), "state": list(self.state)}


@dataclass(frozen=True)
class CoupledBranch:
    """A branch of periodic orbits of a coupled system in one parameter.

    ``reasons`` says why each direction ended (the range's end, a collapse of the steps
    with the numbers, the period's growth, the amplitude's decay to a Hopf point).
    """

    model: str
    parameter: str
    bounds: tuple[float, float]
    forced: bool
    dof: int
    points: tuple[CoupledBranchPoint, ...]
    special: tuple[CoupledSpecialPoint, ...]
    reasons: tuple[str, ...]
    evaluations: int

    def to_json(self) -> dict:
        return {"model": self.model, "parameter": self.parameter, "bounds": list(self.bounds),
                "forced": self.forced, "dof": self.dof,
                "points": [p.to_json() for p in self.points],
                "special": [s.to_json() for s in self.special],
                "reasons": list(self.reasons), "evaluations": self.evaluations}
