"""The frequency-response diagram: the order-``N`` analytic curve next to the true one.

:func:`response_diagram` derives the forced KBM expansion, traces the slow flow's response
curve with its folds and backbone (:mod:`kbm.slowflow.steady`) and the true periodic
responses (:mod:`numerics.shooting.forced_branch`) over the same detuning range;
:meth:`ResponseDiagram.to_json` is the JSON of ``kbm response``.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from kbm.errors import ParameterError
from kbm.model.forced import ForcedOscillator, Resonance
from kbm.backend.forced import forced_expansion
from kbm.model.forced_builtins import get_forced_model
from kbm.slowflow.steady import ResponseCurve, backbone, response_curve
from kbm.output.strict_json import complex_pairs, json_fields

from numerics.shooting.forced_branch import NumericResponse, numeric_response
from numerics.flow.forced_system import ForcedSystem

__all__ = ["ResponseDiagram", "response_diagram", "SteadyStates", "steady_states"]


@dataclass(frozen=True)
class ResponseDiagram:
    """Analytic and numeric frequency-response curves of one forced model."""

    model: str
    resonance: Resonance
    order: int
    values: Mapping[str, float]
    sigmas: tuple[float, float]
    analytic: ResponseCurve
    numeric: NumericResponse | None
    backbone: tuple[tuple[float, float], ...]
    slow_flow: tuple[str, str]
    amplitude_window: float = 5.0

    def to_json(self) -> dict:
        """``analytic``: [{sigma, amplitude, stable}], ``numeric``: [{sigma, amplitude_max,
        amplitude, stable}], ``folds``: [{sigma, amplitude}] (of the order-``N`` curve),
        ``numeric_folds``, ``backbone``, ``order`` and the setting."""
        num = self.numeric
        return {
            "model": self.model, "resonance": str(self.resonance), "order": self.order,
            "parameters": dict(self.values),
            "sigma_range": list(self.sigmas),
            "slow_flow": {"da/dt": self.slow_flow[0], "dphi/dt": self.slow_flow[1]},
            "analytic": self.analytic.points(),
            "numeric": num.points() if num is not None else [],
            "folds": [json_fields(f, "sigma", "amplitude") for f in self.analytic.folds],
            "numeric_folds": [json_fields(o, "sigma", "amplitude", "amplitude_max", kind=(
                "branch point on x = 0" if o.amplitude_max < 1e-3 * self.amplitude_window
                else "fold")) for o in (num.folds if num is not None else ())],
            "backbone": [{"sigma": s, "amplitude": av} for s, av in self.backbone],
            "special": [sp.to_json() for sp in (num.special if num is not None else ())],
            "numeric_failures": list(num.failures) if num is not None else [],
        }


def response_diagram(model: ForcedOscillator | str, values: Mapping[str, object],
                     sigmas: tuple[float, float], *, order: int = 1, n_points: int = 400,
                     resonance: Resonance | str | None = None,
                     amplitudes: tuple[float, float] = (1e-3, 5.0), numeric: bool = True,
                     rtol: float = 1e-10) -> ResponseDiagram:
    """The frequency-response curve at order ``order`` and (``numeric``) the true one.

    Parameters
    ----------
    model
        A forced model or a built-in forced model's name.
    values
        Parameter values including ``mu``.
    sigmas
        The detuning range ``(from, to)``.
    order
        The KBM order of the analytic curve.
    n_points
        About the number of points per branch.
    amplitudes
        The amplitude window in which the fixed points are sought; for ``F`` that is not
        polynomial in ``x``, ``xdot`` (the slider's ``sin(k x + theta)``) also the interval
        on which the numeric backend computes the expansion
        (:func:`kbm.backend.forced.numeric_derive_forced`), so its lower end must stay clear of
        ``a = 0``.

    Raises
    ------
    kbm.errors.ParameterError
        For a bad range or missing values.
    """
    if isinstance(model, str):
        model = get_forced_model(model)
    lo, hi = float(sigmas[0]), float(sigmas[1])
    if not (np.isfinite(lo) and np.isfinite(hi) and hi > lo):
        raise ParameterError(f"the detuning range must be FROM < TO, got {lo} to {hi}")
    if not 2 <= n_points <= 100000:
        raise ParameterError(f"the number of points must be between 2 and 100000, got "
                             f"{n_points}")
    vals = model.resolve(values)
    res = forced_expansion(model, order, vals, resonance=resonance, a_range=amplitudes)
    sf = res.slow_flow({k: v for k, v in vals.items()}, order=order)
    curve = response_curve(sf, (lo, hi), amplitudes, n_points=n_points)
    num = None
    if numeric:
        system = ForcedSystem(model, vals, resonance=res.resonance, rtol=rtol)
        num = numeric_response(system, sf, (lo, hi), amplitudes, n_points=n_points)
    amps = np.linspace(amplitudes[0], amplitudes[1], 60)
    with np.errstate(all="ignore"):
        bb = backbone(sf, amps)
    bone = tuple((float(s), float(av)) for s, av in zip(bb, amps)
                 if np.isfinite(s) and lo <= s <= hi)
    return ResponseDiagram(model.name, res.resonance, order,
                           {k: float(v) for k, v in vals.items()}, (lo, hi), curve, num, bone,
                           (str(sf.exprs[0]), str(sf.exprs[1])), float(amplitudes[1]))


@dataclass(frozen=True)
class SteadyStates:
    """Every steady response at one detuning: the slow flow's fixed points and, for each,
    the true periodic response reached from it by shooting."""

    model: str
    resonance: Resonance
    order: int
    sigma: float
    values: Mapping[str, float]
    analytic: tuple
    trivial: str | None
    numeric: tuple
    failures: tuple[str, ...]

    def to_json(self) -> dict:
        """The keys of :meth:`ResponseDiagram.to_json` at one detuning (no folds)."""
        an = [json_fields(f, "sigma", "amplitude", "phase", "stable") for f in self.analytic]
        if self.trivial is not None:
            an.append({"sigma": self.sigma, "amplitude": 0.0, "phase": None,
                       "stable": self.trivial == "stable", "kind": self.trivial})
        return {"model": self.model, "resonance": str(self.resonance), "order": self.order,
                "parameters": dict(self.values), "sigma": self.sigma, "analytic": an,
                "numeric": [json_fields(o, "sigma", "amplitude_max", "amplitude", "stable",
                                        multipliers=complex_pairs(o.multipliers))
                            for o in self.numeric],
                "folds": [], "numeric_failures": list(self.failures)}


def steady_states(model: ForcedOscillator | str, values: Mapping[str, object], sigma: float,
                  *, order: int = 1, resonance: Resonance | str | None = None,
                  amplitudes: tuple[float, float] = (1e-3, 5.0), numeric: bool = True,
                  rtol: float = 1e-10) -> SteadyStates:
    """The steady responses at the detuning ``sigma`` (``--detuning``), predicted and true."""
    from kbm.slowflow.steady import fixed_points, trivial_state

    from numerics.errors import NumericsError
    from numerics.shooting.forced_branch import guess_from
    from numerics.shooting.forced_orbit import periodic_response

    if isinstance(model, str):
        model = get_forced_model(model)
    vals = model.resolve(values)
    res = forced_expansion(model, order, vals, resonance=resonance, a_range=amplitudes)
    sf = res.slow_flow(dict(vals), order=order)
    fps = tuple(fixed_points(sf, float(sigma), amplitudes))
    orbits, failures = [], []
    if numeric:
        system = ForcedSystem(model, vals, resonance=res.resonance, rtol=rtol)
        for f in fps:
            try:
                orbits.append(periodic_response(system, f.sigma,
                                                guess_from(system, f.amplitude, f.phase,
                                                           f.sigma)))
            except NumericsError as exc:
                failures.append(str(exc))
    return SteadyStates(model.name, res.resonance, order, float(sigma),
                        {k: float(v) for k, v in vals.items()}, fps,
                        trivial_state(sf, float(sigma)), tuple(orbits), tuple(failures))
