"""Friction laws and maps: many steady sliding states on any executor, SEDF against CDC.

:func:`friction_map` measures :func:`~numerics.sliding.friction.friction_point` on the grid
of its axes (``v`` and any other parameters, e.g. ``Delta`` or ``beta``), in chunks of
neighbouring points on a local process pool or a Dask cluster
(:func:`numerics.executor.map_chunks`): the results come back in grid order and are the
same on every executor; a point that fails carries its error and the rest stand.
:func:`friction_law` is the one-axis case over the stage velocity.
:func:`compare_sliders` puts two sliders on the same grid (by default the stage-attached
SEDF and the CDC) and gives the ratios of their friction and dissipation, the regimes and
where the SEDF slides with less friction.
"""

from __future__ import annotations

import itertools
import math
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from kbm.errors import KBMError, ParameterError
from kbm.model.builtins import get_model
from kbm.output.strict_json import json_fields

from numerics.errors import NumericsError
from numerics.executor import chunk, map_chunks
from numerics.sliding.driven import driven_system
from numerics.sliding.friction import friction_point
from numerics.sliding.friction_records import FrictionPoint, FrictionSettings, eta
from numerics._show import num, params_text

__all__ = ["FrictionMap", "friction_map", "friction_law", "SliderComparison",
           "compare_sliders", "axis_values", "MEASURES"]

#: the per-point measures of a map (fields of FrictionPoint), in the order of the JSON
MEASURES = ("mean_force", "static_force", "dissipation_per_distance", "stuck_fraction",
            "regime", "force_fluctuation", "wells_per_slip", "peak_force", "energy_residual",
            "steady", "eta", "static_quasistatic")


def axis_values(name: str, values: Sequence[float]) -> np.ndarray:
    """The values of one axis, checked: finite, non-empty, ``v > 0``.

    Raises
    ------
    kbm.errors.ParameterError
        Naming the axis and the bad value.
    """
    arr = np.asarray(values, dtype=float)
    if arr.ndim != 1 or arr.size == 0:
        raise ParameterError(f"the axis {name} is empty: give at least one value")
    bad = arr[~np.isfinite(arr)]
    if bad.size:
        raise ParameterError(f"the axis {name} holds {bad[0]}: every value must be finite")
    if name in ("v", "lam", "Omega", "mu") and np.any(arr <= 0):
        raise ParameterError(f"the axis {name} must hold values > 0, got {arr[arr <= 0][0]:g}")
    if name == "Delta" and np.any(arr < 0):
        raise ParameterError(f"the axis Delta must hold values >= 0, got {arr[arr < 0][0]:g}")
    return arr


@dataclass(frozen=True, eq=False)
class FrictionMap:
    """Friction measures of one slider on a grid (the last axis varies fastest).

    Attributes
    ----------
    model
        The slider.
    params
        The fixed parameters.
    axes
        ``{name: values}`` in grid order.
    points
        :class:`~numerics.sliding.friction_records.FrictionPoint` per grid point, flattened.
    """

    model: str
    params: Mapping[str, float]
    axes: Mapping[str, np.ndarray]
    points: tuple[FrictionPoint, ...]

    def __repr__(self) -> str:
        axes = ", ".join(f"{k}: {len(v)} values {num(v[0], 4)}..{num(v[-1], 4)}"
                         for k, v in self.axes.items())
        return (f"FrictionMap({self.model}; {params_text(self.params)}; {axes}; "
                f"{len(self.failures)} failed; .field(name) gives a measure on the grid)")

    @property
    def shape(self) -> tuple[int, ...]:
        return tuple(len(a) for a in self.axes.values())

    def field(self, name: str) -> np.ndarray:
        """A measure on the grid, e.g. ``field("mean_force")`` (NaN where not measured)."""
        vals = [getattr(p, name) for p in self.points]
        dtype = object if isinstance(vals[0], str) else float
        return np.array(vals, dtype=dtype).reshape(self.shape)

    @property
    def failures(self) -> list[FrictionPoint]:
        return [p for p in self.points if not p.ok]

    def to_json(self) -> dict:
        """``model``, ``params``, ``axes``, then each of :data:`MEASURES` as nested lists in
        the grid's shape, ``note`` and ``error`` per point."""
        out: dict = {"model": self.model, "params": dict(self.params),
                     "axes": {k: v.tolist() for k, v in self.axes.items()},
                     "shape": list(self.shape)}
        for name in MEASURES + ("note", "error"):
            arr = np.empty(len(self.points), dtype=object)
            arr[:] = [getattr(p, name) for p in self.points]
            out[name] = arr.reshape(self.shape).tolist()
        return out

    def to_xarray(self):
        """The map as an :class:`xarray.Dataset`: one variable per measure of
        :data:`MEASURES` (and ``note``, ``error``) on the grid's axes as dimensions and
        coordinates, the fixed parameters as attributes.  Saved with
        ``.to_netcdf(path)`` and read back in one line with ``xarray.open_dataset(path)``.

        Raises
        ------
        numerics.errors.NumericsError
            If xarray is not installed (the optional extra ``pip install 'kbm[xarray]'``).
        """
        try:
            import xarray as xr
        except ImportError:
            raise NumericsError("a map as an xarray Dataset needs the optional extra: "
                                "pip install 'kbm[xarray]'") from None
        dims = list(self.axes)
        data = {}
        for name in MEASURES + ("note", "error"):
            vals = [getattr(p, name) for p in self.points]
            if name in ("regime", "note", "error"):
                arr = np.array(["" if v is None else str(v) for v in vals], dtype=str)
            elif name == "steady":
                arr = np.array([bool(v) for v in vals], dtype=np.int8)
            else:
                arr = np.array([np.nan if v is None else float(v) for v in vals])
            data[name] = (dims, arr.reshape(self.shape))
        attrs = {"model": self.model, "source": "kbm friction (numerics.sliding.maps)",
                 **{f"param_{k}": float(v) for k, v in self.params.items()}}
        return xr.Dataset(data, coords={k: np.asarray(v) for k, v in self.axes.items()},
                          attrs=attrs)


def _chunk(job) -> list[FrictionPoint]:
    """One task: the points of a chunk in order (a failure stays with its point)."""
    model, fixed, pts, settings, engine = job
    out = []
    for p in pts:
        params = {**fixed, **p}
        try:
            out.append(friction_point(model, params, settings=settings, engine=engine))
        except KBMError as exc:
            out.append(FrictionPoint(model=model, params=params, eta=_safe_eta(params),
                                     error=str(exc)))
    return out


def _safe_eta(params: Mapping[str, object]) -> float:
    try:
        return eta({k: float(v) for k, v in params.items()})
    except (TypeError, ValueError, ZeroDivisionError):
        return math.nan


def friction_map(model: str, params: Mapping[str, object], axes: Mapping[str, Sequence[float]],
                 *, settings: FrictionSettings | None = None, engine: str = "compiled",
                 executor: object | None = None, workers: int | None = None,
                 progress: bool | None = None, chunksize: int | None = None,
                 store: object | None = None) -> FrictionMap:
    """Friction measures of ``model`` at every point of the grid of ``axes``.

    Parameters
    ----------
    model
        ``"sedf_comoving"``, ``"cdc"`` or ``"sedf"``.
    params
        The fixed parameters (``mu, Delta, lam, beta, Omega``; not the axes).
    axes
        ``{name: values}``, e.g. ``{"v": np.geomspace(1e-3, 3, 24), "Delta": [1, 2, 3]}``;
        the last axis varies fastest.  A parameter the model does not have (``beta`` of
        the CDC) is dropped from its points, and equal points are computed once.
    settings, engine
        :func:`~numerics.sliding.friction.friction_point`'s.
    executor, workers, chunksize
        Where the chunks run (:func:`numerics.executor.map_chunks`): ``None`` (a local
        pool of ``workers`` processes), a :class:`concurrent.futures.Executor` or a Dask
        :class:`distributed.Client`.
    progress
        A tqdm bar (default: more than 8 points).
    store
        A :class:`numerics.store.PointStore`: every finished chunk is committed to it, and
        with ``resume`` the chunks it holds are not computed again (the map is the same,
        byte for byte).

    Raises
    ------
    kbm.errors.ParameterError
        For an empty axis, a non-finite value, ``v <= 0``, an axis also fixed, or no ``v``
        anywhere.
    """
    if not axes:
        raise ParameterError("give at least one axis, e.g. axes={'v': [0.01, 0.1]}")
    ax = {name: axis_values(name, vals) for name, vals in axes.items()}
    fixed = dict(params)
    both = sorted(set(fixed) & set(ax))
    if both:
        raise ParameterError(f"{both[0]} is both fixed and an axis: give it once")
    if "v" not in ax and "v" not in fixed:
        raise ParameterError("the stage velocity v is missing: make it an axis "
                             "(axes={'v': [...]}) or fix it")
    own = set(get_model(model).parameters) | {"mu", "Delta", "lam", "Omega", "v"}
    grid = [{n: float(x) for n, x in zip(ax, combo) if n in own}
            for combo in itertools.product(*ax.values())]
    fixed = {k: v for k, v in fixed.items() if k in own}
    driven_system(model, {**fixed, **grid[0]}, engine=engine)  # bad parameters: one error now
    keys = [tuple(sorted(g.items())) for g in grid]
    unique = list(dict.fromkeys(keys))
    settings = settings or FrictionSettings()
    workers = workers or os.cpu_count() or 1
    chunks = chunk([dict(k) for k in unique], chunksize, largest=16)
    jobs = [(model, fixed, c, settings, engine) for c in chunks]

    def lost(job, exc):
        return [FrictionPoint(model=model, params={**fixed, **p}, eta=_safe_eta({**fixed, **p}),
                              error=f"task failed: {type(exc).__name__}: {exc}")
                for p in job[2]]

    show = len(unique) > 8 if progress is None else progress
    definition = repr(("numerics.sliding.maps.friction_map", model, sorted(fixed.items()),
                       chunks, settings, engine))
    res = map_chunks(_chunk, jobs, executor=executor, workers=workers, progress=show,
                     desc=f"friction {model}", sizes=[len(c) for c in chunks], on_error=lost,
                     store=store, definition=definition)
    found = dict(zip(unique, res))
    return FrictionMap(model=model, params=fixed, axes=ax,
                       points=tuple(found[k] for k in keys))


def friction_law(model: str, params: Mapping[str, object], v: Sequence[float],
                 **kwargs) -> FrictionMap:
    """The friction law of ``model``: :func:`friction_map` over the stage velocity ``v``."""
    return friction_map(model, params, {"v": v}, **kwargs)


@dataclass(frozen=True, eq=False)
class SliderComparison:
    """Two sliders on one grid: ``first`` (the SEDF) against ``second`` (the CDC).

    Attributes
    ----------
    force_ratio, dissipation_ratio
        ``first/second`` of the mean force and of the dissipation per distance, NaN
        where either point has no measure (failed, or a runaway).
    steady
        Where both points are steady.
    better
        Where ``first`` slides with less friction *and* less dissipation.
    """

    first: FrictionMap
    second: FrictionMap

    def _ratio(self, name: str) -> np.ndarray:
        a, b = self.first.field(name), self.second.field(name)
        with np.errstate(all="ignore"):
            return a / b

    @property
    def steady(self) -> np.ndarray:
        """Where both points are steady (elsewhere the ratios are of means over the
        longest windows, flagged)."""
        return (self.first.field("steady").astype(bool)
                & self.second.field("steady").astype(bool))

    @property
    def force_ratio(self) -> np.ndarray:
        return self._ratio("mean_force")

    @property
    def dissipation_ratio(self) -> np.ndarray:
        return self._ratio("dissipation_per_distance")

    @property
    def better(self) -> np.ndarray:
        with np.errstate(invalid="ignore"):
            return (self.force_ratio < 1) & (self.dissipation_ratio < 1)

    def summary(self) -> dict:
        """Counts: points compared, where the first is better, the ratios' range."""
        fr = self.force_ratio
        ok = np.isfinite(fr)
        return {"compared": int(ok.sum()), "points": int(fr.size),
                "steady": int((ok & self.steady).sum()),
                "first_better": int(self.better.sum()),
                "first_better_steady": int((self.better & self.steady).sum()),
                "force_ratio_min": float(np.nanmin(fr)) if ok.any() else math.nan,
                "force_ratio_max": float(np.nanmax(fr)) if ok.any() else math.nan}

    def to_json(self) -> dict:
        return json_fields(self, "first", "second", "force_ratio", "dissipation_ratio", "better",
                           "steady", summary=self.summary())


def compare_sliders(params: Mapping[str, object], axes: Mapping[str, Sequence[float]], *,
                    models: tuple[str, str] = ("sedf_comoving", "cdc"),
                    **kwargs) -> SliderComparison:
    """:func:`friction_map` of two sliders on the same grid (the SEDF's ``beta`` is not
    given to the CDC), and their ratios."""
    first = friction_map(models[0], params, axes, **kwargs)
    second = friction_map(models[1], params, axes, **kwargs)
    return SliderComparison(first=first, second=second)
