"""Friction at finite temperature: the pulled sliders with thermal noise, simulated.

The slider of the paper's eq. (3) or (12) pulled at ``v`` with ``sqrt(2 D) xi`` on the
right-hand side (``kT = D/mu`` for the CDC) is integrated by the Langevin kernels of
:mod:`numerics.noise` (weak order 2), an ensemble of independent trajectories per point.
After a burn-in of ``max(5 lam/v, 20/mu)`` each trajectory runs ``wells`` stage periods
``lam/v``; per trajectory are taken

* the mean spring force ``Omega^2 <v t - x>`` (the kinetic friction);
* the slip force: at each slip, the largest spring force during the stay in the well it
  leaves.  Crossings of barrier tops ``x = (n + 1/2) lam`` less than one natural period
  ``2 pi/Omega`` apart form one run (the wells of a slip, its ringing); a slip is a run
  that ends, a natural period in one well, ahead of the well it left;
* the backward jumps (runs that end behind the well they left), the thermally activated
  events that make friction linear in ``v`` as ``v -> 0`` (thermolubricity).  A run that
  ends in the well it left (an oscillation in the well, a barrier top recrossed: the
  comoving SEDF's swings) is neither (``tests/test_thermal_friction_slips.py``).

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
from kbm.output.strict_json import Rendered
from kbm.parameters.names import noise_intensity

from ..executor import CHUNKS, map_chunks
from ..noise.ensemble import Estimate
from ..noise.budget import STEP_BUDGET
from ..noise.langevin import langevin_system, natural_step
from ..noise.seeds import check_seed, trajectory_states
from ..sliding.driven import physical_values

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
    """Trajectories ``first .. first + count - 1`` of one point: their rows of
    ``slip_stats`` (a block of a point, so that a run of few points still has many tasks and
    the parent process, which waits on them, stops at once on Ctrl-C or SIGTERM)."""
    model, params, wells, seed, index, first, count = task
    params = dict(params)
    D = params.pop("D")
    system = langevin_system(model, params, D)
    v, lam = float(params["v"]), float(params.get("lam", 1.0))
    run, burn, h = _times(system, v, lam, wells)
    Omega = float(params.get("Omega", 1.0))
    states = trajectory_states(seed, first, count, stream=(index,))
    y0 = np.zeros((count, 2))
    rows = system.kernels.slip_stats(system._p(), system.sigma, y0, 0.0, h, round(burn / h),
                                     round(run / h), states, lam, 2 * math.pi / Omega, v)
    return [(index, rows.tolist(), run, burn, h)]


def _steps(model: str, pts: list, trajectories: int, wells: float, budget: float) -> None:
    """Refuse a run of more than ``budget`` integration steps, before any is taken.

    The step of a point depends on the parameters other than ``v`` and ``D`` (the
    stiffness of the well bottom and ``mu``): one system per distinct set of them, and the
    count stops as soon as it passes the budget.
    """
    if not (math.isfinite(budget) and budget > 0):
        raise ParameterError(f"--budget {budget:g}: the largest number of integration steps "
                             "must be a positive number")
    cache: dict = {}
    total, worst = 0.0, (0.0, 0.0, 0.0, 0.0, None)
    for k, q in enumerate(pts):
        key = tuple(sorted((n, x) for n, x in q.items() if n not in ("v", "D")))
        if key not in cache:
            cache[key] = natural_step(langevin_system(
                model, {n: x for n, x in q.items() if n != "D"}, q["D"]),
                per_period=STEPS_PER_PERIOD)
        h0 = cache[key]
        lam = q.get("lam", 1.0)
        run, burn = wells * lam / q["v"], max(5 * lam / q["v"], 20 / abs(q["mu"]))
        per = (run + burn) / h0
        total += trajectories * per
        if per > worst[0]:
            worst = (per, run, burn, h0, q["v"])
        if total > budget:
            per, run, burn, h0, v = worst
            more = "" if k + 1 == len(pts) else f" (already at {k + 1} of {len(pts)} points)"
            raise ParameterError(
                f"thermal friction refused: {total:.3g} integration steps > budget "
                f"{budget:.3g}{more}; at v = {v:g} one trajectory takes {per:.3g} steps "
                f"of dt = {h0:.3g} (burn-in {burn:.3g} + {wells:g} stage periods "
                f"lam/v = {run:.3g}) x {trajectories} trajectories; lower --wells or "
                "--trajectories, use fewer or faster points, or raise --budget")


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
                           wells: float = 20, seed: int = 0,
                           budget: float = STEP_BUDGET) -> ThermalFrictionPoint:
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
    budget : float
        Largest number of integration steps (:func:`thermal_friction_map`).

    Raises
    ------
    kbm.errors.ParameterError
        No ``v`` in ``params``, and as :func:`thermal_friction_map`.
    """
    if "v" not in params:
        raise ParameterError("thermal_friction_point needs the stage velocity: give params['v'] "
                             "(> 0), or call thermal_friction_map with an axis of v")
    return thermal_friction_map(model, params, {"v": [params["v"]]}, trajectories=trajectories,
                                wells=wells, seed=seed, budget=budget, workers=1).points[0]


@dataclass(frozen=True, eq=False)
class ThermalFrictionMap(Rendered):
    """Thermal friction on a grid of ``v`` and ``D`` (or ``T``).

    ``params`` holds the fixed values, the defaults ``mu = 0.1``, ``lam = 1``, ``Omega = 1``
    included, and ``None`` (JSON ``null``) for a default that is an axis (``mu`` of ``--vary
    mu=...``): its values are in ``axes``.
    """

    model: str
    params: Mapping[str, float | None]
    axes: Mapping[str, np.ndarray]
    points: tuple
    trajectories: int
    wells: float
    seed: int
    note: str = ""

    layout = ("model", "params", "axes", "trajectories", "wells", "seed", "note", "points")
    mappings_as_given = True

    def __repr__(self) -> str:
        return (f"ThermalFrictionMap({self.model}, axes {', '.join(self.axes)}, "
                f"{len(self.points)} points)")

    def field(self, name: str) -> np.ndarray:
        """``"mean_force"``, ``"slip_force"`` (values) or ``"..._stderr"`` on the grid."""
        attr, _, err = name.partition("_stderr")
        vals = [getattr(getattr(p, attr.rstrip("_")), "stderr" if name.endswith("stderr")
                        else "value") for p in self.points]
        return np.asarray(vals, float).reshape([len(a) for a in self.axes.values()])


def thermal_friction_map(model: str, params: Mapping[str, object],
                         axes: Mapping[str, Sequence[float]], *, trajectories: int = 16,
                         wells: float = 20, seed: int = 0, executor=None,
                         workers: int | None = None, progress: bool = False,
                         store=None, budget: float = STEP_BUDGET) -> ThermalFrictionMap:
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
    budget : float
        Largest number of integration steps of the whole run (trajectories x (burn-in +
        ``wells`` stage periods)/dt summed over the points); a larger run is refused
        before it starts.  The trajectories of a point are cut into blocks (tasks), so a
        run of one point also spreads over the workers and stops at once on Ctrl-C or
        SIGTERM (:func:`numerics.executor.map_chunks`).

    Raises
    ------
    kbm.errors.ParameterError
        A missing ``v`` or ``D``, ``D < 0``, ``v <= 0``, too few trajectories, more steps
        than ``budget``.
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
        # as the deterministic slider (mu <= 0 was blamed on D, Delta < 0 passed)
        physical_values({k: q[k] for k in ("lam", "Omega", "mu", "Delta") if k in q})
        if "T" in q:
            if "D" in params or "D" in axes:
                raise ParameterError("give the noise as D or as T = D/mu, not both")
            q["D"] = q.pop("T") * q["mu"]
        if "D" not in q:
            raise ParameterError("thermal friction needs the noise: -p D=VALUE (or an axis "
                                 "--vary D=... / T=...)")
        q["D"] = noise_intensity(q["D"])
        if "v" not in q or not (math.isfinite(q["v"]) and q["v"] > 0):
            got = f" (got {q['v']:g})" if "v" in q else ""  # not "got None"
            raise ParameterError(f"the stage velocity v must be > 0{got}: give -p v=VALUE or "
                                 "--vary v=...")
        pts.append(q)
    langevin_system(model, {k: v for k, v in pts[0].items() if k != "D"}, pts[0]["D"])
    N = int(trajectories)
    _steps(model, pts, N, float(wells), float(budget))
    # blocks of trajectories, cut by the data (about CHUNKS tasks or one per point)
    size = max(1, min(N, -(-len(pts) * N // CHUNKS)))
    tasks = [[(model, q, float(wells), seed, j, first, min(size, N - first))]
             for j, q in enumerate(pts) for first in range(0, N, size)]
    definition = repr(("thermal_friction", model, sorted(base.items()),
                       {k: list(map(float, v)) for k, v in axes.items()}, N,
                       float(wells), seed, "blocks", size))
    blocks = map_chunks(_chunk_task, tasks, executor=executor, workers=workers,
                        progress=progress, desc=f"{model} with noise", unit="trajectory",
                        sizes=[t[0][-1] for t in tasks], store=store,
                        definition=definition if store is not None else None)
    rows: list = [[] for _ in pts]
    times: list = [None] * len(pts)
    for j, r, run, burn, h in blocks:
        rows[j].extend(r)
        times[j] = (run, burn, h)
    points = tuple(_point(model, q, rows[j], *times[j], N, seed) for j, q in enumerate(pts))
    note = ("the paper's SEDF (eq. 3) has no steady sliding state: its damping mu beta x^2 "
            "grows with the distance slid, so these are averages over the window, not a "
            "friction law (use sedf_comoving)") if model == "sedf" else ""
    # a default (mu = 0.1, lam, Omega) is no fixed value where it is an axis: None (null)
    fixed = {k: None if k in axes else v for k, v in base.items()}
    return ThermalFrictionMap(model, fixed, {k: np.asarray(v, float) for k, v in axes.items()},
                              points, int(trajectories), float(wells), seed, note)


def _chunk_task(tasks) -> list:
    return [row for t in tasks for row in _point_task(t)]
