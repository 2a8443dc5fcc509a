"""The steady-state criterion of a friction point and the record of one measured point
(:mod:`numerics.sliding.friction`): :class:`FrictionSettings`, :class:`FrictionPoint`, the
regimes, and the Prandtl-Tomlinson parameter ``eta = 2 pi Delta/(Omega^2 lam)`` with the
quasi-static static friction ``Delta sqrt(1 - 1/eta^2)``.

References
----------
L. Prandtl (1928), G. A. Tomlinson (1929); O. M. Braun and Y. S. Kivshar, *The
Frenkel-Kontorova Model* (Springer 2004), ch. 9.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field, fields

from kbm.errors import ParameterError
from kbm.output.strict_json import Rendered

from numerics._show import num, params_text

__all__ = ["FrictionSettings", "FrictionPoint", "eta", "REGIMES"]

#: the regimes of a steady sliding state
REGIMES = ("stick-slip", "smooth sliding", "self-oscillating sliding", "oscillating sliding",
           "runaway")


@dataclass(frozen=True)
class FrictionSettings:
    """The steady-state criterion and its run lengths (see the module docstring).

    Attributes
    ----------
    slips
        Slips averaged over in stick-slip.
    transient_slips, transient_wells, transient_damping
        The transient dropped: slips, stage periods ``lam/v``, times ``1/mu`` (then the
        slips before the slip pattern repeats, criterion 1 of
        :mod:`numerics.sliding.friction`).
    sliding_wells
        Whole stage periods averaged over when the slider never sticks (at least 20
        natural periods ``2 pi/Omega``).
    max_wells, max_periods
        The longest run, in stage periods ``lam/v`` and in natural periods (a point
        that has shown no window by then is an error).
    max_doublings, max_doublings_sliding
        How often a window that is not steady is dropped and one twice as long measured
        after it, with stick-slip and without (sliding windows are short: a mean force
        that is a small difference of large energy flows, as in the self-oscillating
        sliding of the SEDF, needs long ones); then the point is reported as measured,
        flagged not steady.
    samples_per_period
        Samples per period of the oscillation at the bottom of a well,
        ``2 pi/sqrt(Omega^2 + Delta k)``.
    steady_tol
        Largest relative difference of the two halves' mean forces of a steady window;
        a window that fails is dropped (counted as transient) and one twice as long
        is measured after it.
    energy_tol
        Largest change of the stored energy over a steady window, relative to the work
        of the stage ``F_bar v Delta t``.
    runaway_force, runaway_damping
        A run whose spring force exceeds ``runaway_force (Delta + Omega^2 lam + mu v)``,
        or whose damping rate exceeds ``runaway_damping`` times the well frequency
        ``sqrt(Omega^2 + Delta k)``, has no bounded sliding state (regime ``runaway``).
    """

    slips: int = 20
    transient_slips: int = 2
    transient_wells: float = 3.0
    transient_damping: float = 10.0
    sliding_wells: int = 20
    max_wells: int = 3000
    max_periods: float = 30_000.0
    max_doublings: int = 2
    max_doublings_sliding: int = 5
    samples_per_period: int = 16
    steady_tol: float = 0.01
    energy_tol: float = 1e-3
    runaway_force: float = 10.0
    runaway_damping: float = 50.0

    def __post_init__(self) -> None:
        for f in fields(self):
            val = getattr(self, f.name)
            if not (isinstance(val, (int, float)) and math.isfinite(val) and val >= 0):
                raise ParameterError(f"friction setting {f.name} must be a number >= 0, "
                                     f"got {val!r}")
        for name in ("slips", "sliding_wells", "max_wells", "samples_per_period"):
            if int(getattr(self, name)) != getattr(self, name) or getattr(self, name) < 1:
                raise ParameterError(f"friction setting {name} must be an integer >= 1, "
                                     f"got {getattr(self, name)!r}")


@dataclass(frozen=True)
class FrictionPoint(Rendered):
    """The friction measures of one steady sliding state (NaN where a measure does not
    apply); its JSON form every field (:class:`~kbm.output.strict_json.Rendered`).

    Attributes
    ----------
    model, params
        The slider and its physical parameters.
    eta
        Prandtl-Tomlinson parameter ``2 pi Delta/(Omega^2 lam)``.
    regime
        One of :data:`REGIMES` (``""`` when the run failed).
    steady
        Whether the two halves of the window agree (:class:`FrictionSettings`).
    mean_force, force_fluctuation
        Mean spring force over the window (kinetic friction) and its standard deviation.
    static_force, static_quasistatic
        Mean peak spring force before the slips; the quasi-static ``Delta sqrt(1 -
        1/eta^2)`` (NaN for ``eta <= 1``).
    peak_force
        Largest spring force in the window.
    dissipation_per_distance
        ``Delta Gamma/(v Delta t)``.
    energy_residual, audit
        ``|F_bar - dissipation_per_distance|`` over the larger of ``|F_bar|`` and the
        energy flow per distance (criterion 4); the power balance's integration error
        ``|v Delta J - Delta Gamma - Delta E|/Delta Gamma``.
    stuck_fraction, wells_per_slip, slips
        Fraction of the window stuck (in one well: an oscillation in the well between two
        stuck intervals counts as stuck); mean wells crossed per slip; slips in the window.
    halves
        Mean force of the window's two halves.
    window
        ``(t0, t1)``.
    steps
        Integrator steps of the whole run.
    note
        What the reader should know (not steady, fewer slips, runaway), or ``""``.
    error
        Why there is no result (the rest is NaN), or ``None``.
    """

    model: str
    params: Mapping[str, float]
    eta: float
    regime: str = ""
    steady: bool = False
    mean_force: float = math.nan
    force_fluctuation: float = math.nan
    static_force: float = math.nan
    static_quasistatic: float = math.nan
    peak_force: float = math.nan
    dissipation_per_distance: float = math.nan
    energy_residual: float = math.nan
    audit: float = math.nan
    stuck_fraction: float = math.nan
    wells_per_slip: float = math.nan
    slips: int = 0
    halves: tuple[float, float] = (math.nan, math.nan)
    window: tuple[float, float] = (math.nan, math.nan)
    steps: int = 0
    note: str = ""
    error: str | None = field(default=None)

    mappings_as_given = True

    @property
    def ok(self) -> bool:
        """A measured point (no error)."""
        return self.error is None

    def __repr__(self) -> str:
        head = f"FrictionPoint({self.model}; {params_text(self.params)}"
        if self.error:
            return f"{head}: failed: {self.error})"
        return (f"{head}: {self.regime or 'no regime'}, mean force {num(self.mean_force, 6)}, "
                f"static {num(self.static_force, 6)}, stuck {num(self.stuck_fraction, 3)}, "
                f"{'steady' if self.steady else 'not steady'})")


def eta(params: Mapping[str, float]) -> float:
    """Prandtl-Tomlinson parameter ``eta = 2 pi Delta/(Omega^2 lam)`` (``Omega = 1``, ``lam
    = 1`` by default)."""
    return (2 * math.pi * float(params.get("Delta", 0.0))
            / (float(params.get("Omega", 1.0))**2 * float(params.get("lam", 1.0))))


def _static_quasistatic(params: Mapping[str, float]) -> float:
    e = eta(params)
    return float(params.get("Delta", 0.0)) * math.sqrt(1 - 1 / e**2) if e > 1 else math.nan
