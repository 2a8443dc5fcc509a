"""Friction at finite temperature: the pulled sliders with thermal noise, simulated.

The slider of the paper's eq. (3) or (12) pulled at ``v`` with ``sqrt(2 D) xi`` on the
right-hand side (``kT = D/mu`` for the CDC) is integrated by the Langevin kernels of
:mod:`numerics.noise` (weak order 2), an ensemble of independent trajectories per point.
After a burn-in of ``max(5 lam/v, 20/mu)`` each trajectory runs ``wells`` stage periods
``lam/v``; per trajectory are taken

* the mean spring force ``Omega^2 <v t - x>`` (the kinetic friction);
* the slip force: the largest spring force since the previous slip, at each slip (a
  forward crossing of a barrier top ``x = (n + 1/2) lam`` more than one natural period
  ``2 pi/Omega`` after the previous crossing);
* the backward jumps (crossings of a barrier top against the pull more than a natural
  period after the previous crossing, so not the ringing of a slip), the thermally
  activated events that make friction linear in ``v`` as ``v -> 0`` (thermolubricity).

Each estimate is the mean over trajectories with its standard error (their standard
deviation over ``sqrt(N)``); slip forces are pooled over all slips with the
between-trajectory error.  As ``D -> 0`` the point joins the athermal law of
:func:`numerics.sliding.friction.friction_point` (a test checks it).

References
----------
Y. Sang, M. Dube and M. Grant, PRL 87 (2001) 174301 (creep: ``F_c - F ~ T^{2/3}
|ln(v/v_c)|^{2/3}``); M. H. Muser, PRB 84 (2011) 125419 (``F = a(T) arsinh(v/v_c(T))``,
``a ~ T^{2/3}``); E. Gnecco et al., PRL 84 (2000) 1172 (the logarithmic velocity law).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from kbm.errors import ParameterError
from kbm.strict_json import json_fields

from ..executor import map_chunks
from ..noise.ensemble import Estimate
from ..noise.langevin import langevin_system, natural_step, noise_intensity
from ..noise.seeds import check_seed, trajectory_states

__all__ = ["ThermalFrictionPoint", "ThermalFrictionMap", "thermal_friction_point",
           "thermal_friction_map", "STEPS_PER_PERIOD"]

#: steps per period of the well-bottom oscillation.  A slip of the lightly damped CDC
#: crosses several wells and how many is decided by its energy: at 40 steps the D = 0
#: friction at mu = 0.1, Delta = 3, v = 0.1 came out 0.717 (DOP853: 0.786), at 160 0.785
STEPS_PER_PERIOD = 160
#: fewest trajectories per point
MIN_TRAJECTORIES = 4


@dataclass(frozen=True)
class ThermalFrictionPoint:
    """One point of a thermal friction law.

    Attributes
    ----------
    model : str
    params : dict
        Physical parameters with ``v`` and ``D``.
    kT : float or None
        ``D/mu`` (the CDC's temperature); ``None`` for the self-excited sliders.
    mean_force : Estimate
        Time- and ensemble-averaged spring force.
    slip_force : Estimate
        Mean peak spring force before a slip (NaN without slips); the peak of a force
        that fluctuates with ``x``, so above the force at the moment of escape by a few
        thermal widths ``Omega^2 sqrt(kT)/omega_w``.
    slip_position : Estimate
        Mean stage position at a slip relative to the well left, ``v t - n lam``: the
        quantity of the rate theory (:func:`numerics.escape.creep.slip_force`, whose
        ``advance`` is ``L_0`` minus it).
    slips, backward : int
        Slips and backward barrier crossings counted over all trajectories.
    trajectories : int
    t_end, burn_in, dt : float
    seed : int
    error : str or None
        Why there is no result (a diverged trajectory), else ``None``.
    """

    model: str
    params: Mapping[str, float]
    kT: float | None
    mean_force: Estimate
    slip_force: Estimate
    slip_position: Estimate
    slips: int
    backward: int
    trajectories: int
    t_end: float
    burn_in: float
    dt: float
    seed: int
    error: str | None = field(default=None)

    def __repr__(self) -> str:
        head = f"ThermalFrictionPoint({self.model}; v={self.params['v']:g}, D={self.params['D']:g}"
        if self.error:
            return f"{head}: failed: {self.error})"
        return (f"{head}: mean force {self.mean_force!r}, slip force {self.slip_force!r}, "
                f"{self.slips} slips, {self.backward} backward)")

    def to_json(self) -> dict:
        return {"v": self.params["v"], "D": self.params["D"], "kT": self.kT,
                "mean_force": self.mean_force.value, "mean_force_stderr": self.mean_force.stderr,
                "slip_force": self.slip_force.value, "slip_force_stderr": self.slip_force.stderr,
                "slip_position": self.slip_position.value,
                "slip_position_stderr": self.slip_position.stderr,
                "slips": self.slips, "backward": self.backward, "t_end": self.t_end,
                "burn_in": self.burn_in, "dt": self.dt, "error": self.error}


def _times(system, v: float, lam: float, wells: float) -> tuple[float, float, float]:
    mu = system.bound.mu
    h0 = natural_step(system, per_period=STEPS_PER_PERIOD)
    run = wells * lam / v
    n = max(1, math.ceil(run / h0))
    h = run / n
    burn = max(5 * lam / v, 20 / abs(mu))
    return run, h * math.ceil(burn / h), h


def _point_task(task) -> list:
    model, params, trajectories, wells, seed, index = task
    params = dict(params)
    D = params.pop("D")
    system = langevin_system(model, params, D)
    v, lam = float(params["v"]), float(params.get("lam", 1.0))
    run, burn, h = _times(system, v, lam, wells)
    Omega = float(params.get("Omega", 1.0))
    states = trajectory_states(seed, 0, trajectories, stream=(index,))
    y0 = np.zeros((trajectories, 2))
    rows = system.kernels.slip_stats(system._p(), system.sigma, y0, 0.0, h, round(burn / h),
                                     round(run / h), states, lam, 2 * math.pi / Omega, v)
    return [(rows.tolist(), run, burn, h)]


def _point(model: str, params: dict, rows, run: float, burn: float, h: float, N: int,
           seed: int) -> ThermalFrictionPoint:
    rows = np.asarray(rows, float)
    mu = float(params["mu"])
    kT = params["D"] / mu if model == "cdc" else None
    if not np.all(np.isfinite(rows)):
        bad = int(np.count_nonzero(~np.isfinite(rows[:, 0])))
        nan = Estimate(math.nan, math.nan)
        return ThermalFrictionPoint(model, params, kT, nan, nan, nan, 0, 0, N, run, burn, h, seed,
                                    error=f"{bad} of {N} trajectories diverged (runaway)")
    slips = rows[:, 1]
    total = float(slips.sum())
    slip, position = _ratio(rows[:, 2], slips, N), _ratio(rows[:, 5], slips, N)
    return ThermalFrictionPoint(model, params, kT, Estimate.of(rows[:, 0]), slip, position,
                                int(total), int(rows[:, 4].sum()), N, run, burn, h, seed)


def _ratio(sums, counts, N: int) -> Estimate:
    """``sum(sums)/sum(counts)`` over trajectories and its standard error (the ratio
    estimator's delta method: trajectories are the independent units)."""
    total = float(np.sum(counts))
    if total == 0:
        return Estimate(math.nan, math.nan)
    mean = float(np.sum(sums) / total)
    resid = sums - mean * counts
    return Estimate(mean, float(math.sqrt(N / (N - 1) * np.sum(resid**2)) / total))


def thermal_friction_point(model: str, params: Mapping[str, object], *, trajectories: int = 16,
                           wells: float = 20, seed: int = 0) -> ThermalFrictionPoint:
    """The friction of ``model`` pulled at ``params['v']`` with noise ``params['D']``.

    Parameters
    ----------
    model : {"cdc", "sedf_comoving", "sedf"}
    params : mapping
        ``mu, Delta, v, D`` (``lam = Omega = 1`` by default; ``beta`` for the SEDF).
    trajectories : int
    wells : float
        Stage periods ``lam/v`` averaged over per trajectory.
    seed : int
    """
    return thermal_friction_map(model, params, {"v": [params["v"]]}, trajectories=trajectories,
                                wells=wells, seed=seed, workers=1).points[0]


@dataclass(frozen=True, eq=False)
class ThermalFrictionMap:
    """Thermal friction on a grid of ``v`` and ``D`` (or ``T``)."""

    model: str
    params: Mapping[str, float]
    axes: Mapping[str, np.ndarray]
    points: tuple
    trajectories: int
    wells: float
    seed: int
    note: str = ""

    def __repr__(self) -> str:
        return (f"ThermalFrictionMap({self.model}, axes {', '.join(self.axes)}, "
                f"{len(self.points)} points)")

    def field(self, name: str) -> np.ndarray:
        """``"mean_force"``, ``"slip_force"`` (values) or ``"..._stderr"`` on the grid."""
        attr, _, err = name.partition("_stderr")
        vals = [getattr(getattr(p, attr.rstrip("_")), "stderr" if name.endswith("stderr")
                        else "value") for p in self.points]
        return np.asarray(vals, float).reshape([len(a) for a in self.axes.values()])

    def to_json(self) -> dict:
        return {**json_fields(self, "model", "params"),
                "axes": {k: list(map(float, v)) for k, v in self.axes.items()},
                **json_fields(self, "trajectories", "wells", "seed", "note"),
                "points": [p.to_json() for p in self.points]}


def thermal_friction_map(model: str, params: Mapping[str, object],
                         axes: Mapping[str, Sequence[float]], *, trajectories: int = 16,
                         wells: float = 20, seed: int = 0, executor=None,
                         workers: int | None = None, progress: bool = False,
                         store=None) -> ThermalFrictionMap:
    """Thermal friction laws and maps: every grid point an ensemble (on the executor).

    Parameters
    ----------
    model : str
    params : mapping
        The fixed parameters (``mu``, ``Delta``, ... and ``D`` or ``T`` unless an axis).
    axes : mapping
        One or two of ``v``, ``D``, ``T`` (``T = D/mu``, the CDC's temperature), ``Delta``,
        ``beta``; the last varies fastest.
    trajectories, wells, seed :
        Per point; point ``j``'s trajectory ``i`` draws from ``SeedSequence(seed,
        spawn_key=(j, i))``: no number depends on the executor or the chunking.

    Raises
    ------
    kbm.errors.ParameterError
        A missing ``v`` or ``D``, ``D < 0``, ``v <= 0``, too few trajectories.
    """
    seed = check_seed(seed)
    if not isinstance(trajectories, (int, np.integer)) or trajectories < MIN_TRAJECTORIES:
        raise ParameterError(f"--trajectories {trajectories}: at least {MIN_TRAJECTORIES} per "
                             "point are needed for a standard error")
    if not (math.isfinite(wells) and wells > 0):
        raise ParameterError(f"--wells {wells:g}: the stage periods per trajectory must be a "
                             "positive number")
    base = {k: float(v) for k, v in params.items()}
    base.setdefault("mu", 0.1)
    base.setdefault("lam", 1.0)
    base.setdefault("Omega", 1.0)
    names = list(axes)
    grids = np.meshgrid(*[np.asarray(axes[n], float) for n in names], indexing="ij")
    pts = []
    for vals in zip(*[g.ravel() for g in grids]):
        q = dict(base, **dict(zip(names, map(float, vals))))
        if "T" in q:
            if "D" in params or "D" in axes:
                raise ParameterError("give the noise as D or as T = D/mu, not both")
            q["D"] = q.pop("T") * q["mu"]
        if "D" not in q:
            raise ParameterError("thermal friction needs the noise: -p D=VALUE (or an axis "
                                 "--vary D=... / T=...)")
        q["D"] = noise_intensity(q["D"])
        if "v" not in q or not (math.isfinite(q["v"]) and q["v"] > 0):
            raise ParameterError(f"the stage velocity v must be > 0 (got {q.get('v')}): give "
                                 "-p v=VALUE or --vary v=...")
        pts.append(q)
    langevin_system(model, {k: v for k, v in pts[0].items() if k != "D"}, pts[0]["D"])
    tasks = [(model, q, int(trajectories), float(wells), seed, j) for j, q in enumerate(pts)]
    definition = repr(("thermal_friction", model, sorted(base.items()),
                       {k: list(map(float, v)) for k, v in axes.items()}, int(trajectories),
                       float(wells), seed))
    rows = map_chunks(_chunk_task, [[t] for t in tasks], executor=executor, workers=workers,
                      progress=progress, desc=f"{model} with noise", unit="point",
                      store=store, definition=definition if store is not None else None)
    points = tuple(_point(model, q, r[0], r[1], r[2], r[3], int(trajectories), seed)
                   for q, r in zip(pts, rows))
    note = ("the paper's SEDF (eq. 3) has no steady sliding state: its damping mu beta x^2 "
            "grows with the distance slid, so these are averages over the window, not a "
            "friction law (use sedf_comoving)") if model == "sedf" else ""
    return ThermalFrictionMap(model, base, {k: np.asarray(v, float) for k, v in axes.items()},
                              points, int(trajectories), float(wells), seed, note)


def _chunk_task(tasks) -> list:
    return [row for t in tasks for row in _point_task(t)]
