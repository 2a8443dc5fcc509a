"""The results of a two-parameter bifurcation diagram (issue 38).

- :class:`Curve`: one codim-1 curve in the plane of the two varied parameters (a fold of
  cycles, a Hopf curve of an equilibrium, a homoclinic connection, ...), true or averaged;
- :class:`Codim2Point`: a named codim-2 point (cusp, Bogdanov–Takens, Bautin, ...);
- :class:`Diagram`: the curves and points of one model on two axes, its JSON and figure.

The JSON contract (scripts depend on it): ``curves`` is a list of ``{kind, points: [[p1,
p2], ...], method: "true" | "averaged", order}``, ``codim2`` a list of ``{kind, point:
[p1, p2]}``; each object may carry more keys (``detail``).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType

from kbm.output.strict_json import Rendered, jsonable

__all__ = ["Curve", "Codim2Point", "Diagram"]

_METHODS = ("true", "averaged")


def _frozen(mapping: Mapping | None) -> Mapping:
    return MappingProxyType(dict(mapping or {}))


class _Detailed(Rendered):
    """A result rendered as its :attr:`layout` then the keys of its ``detail`` the layout
    does not hold (mappings as given, :func:`kbm.output.strict_json.jsonable`)."""

    mappings_as_given = True

    def to_json(self) -> dict:
        out = super().to_json()
        return jsonable({**out, **{k: v for k, v in self.detail.items() if k not in out}})


@dataclass(frozen=True)
class Curve(_Detailed):
    """One codim-1 curve in the parameter plane.

    Parameters
    ----------
    kind : str
        ``"fold"`` (of cycles), ``"hopf"``, ``"homoclinic"``, ``"period-doubling"``, ...
    points : tuple of (float, float)
        The curve's points ``(p1, p2)`` in the order of the continuation; for a true curve
        each one is a converged solution of the defining system.
    method : str
        ``"true"`` (the defining system of the ODE) or ``"averaged"``.
    order : int or None
        The averaging order of an averaged curve (``None`` for a true curve).
    detail : Mapping
        More keys of the JSON object (e.g. the saddles a homoclinic loop visits, the
        residuals, the period along the curve).
    """

    kind: str
    points: tuple[tuple[float, float], ...]
    method: str = "true"
    order: int | None = None
    detail: Mapping = field(default_factory=dict)

    layout = ("kind", "points", "method", "order")

    def __post_init__(self):
        if self.method not in _METHODS:
            raise ValueError(f"Curve.method is 'true' or 'averaged', got {self.method!r}")
        pts = tuple((float(a), float(b)) for a, b in self.points)
        object.__setattr__(self, "points", pts)
        object.__setattr__(self, "detail", _frozen(self.detail))


@dataclass(frozen=True)
class Codim2Point(_Detailed):
    """A codim-2 point on the curves: ``kind`` (``"cusp"``, ``"bogdanov-takens"``,
    ``"bautin"``, ``"fold-homoclinic"``, ``"saddle-change"``, ...) at ``point = (p1, p2)``,
    with ``detail`` (the curves it lies on, the test function's value)."""

    kind: str
    point: tuple[float, float]
    detail: Mapping = field(default_factory=dict)

    layout = ("kind", "point")

    def __post_init__(self):
        object.__setattr__(self, "point", (float(self.point[0]), float(self.point[1])))
        object.__setattr__(self, "detail", _frozen(self.detail))


#: line colours of the curves' kinds in :meth:`Diagram.plot`
_COLOURS = {"hopf": "C0", "fold": "C1", "homoclinic": "C3", "heteroclinic": "C4",
            "period-doubling": "C2", "neimark-sacker": "C5"}


@dataclass(frozen=True)
class Diagram(_Detailed):
    """The bifurcation diagram of ``model`` at ``params`` on ``axes = (p1, p2)`` over
    ``ranges = {p1: (lo, hi), p2: (lo, hi)}``."""

    model: str
    params: Mapping
    axes: tuple[str, str]
    ranges: Mapping
    curves: tuple[Curve, ...] = ()
    codim2: tuple[Codim2Point, ...] = ()
    detail: Mapping = field(default_factory=dict)

    layout = ("model", "params", "axes", "ranges", "curves", "codim2")

    def __post_init__(self):
        object.__setattr__(self, "params", _frozen(self.params))
        object.__setattr__(self, "axes", tuple(self.axes))
        object.__setattr__(self, "ranges", _frozen({k: tuple(float(x) for x in v)
                                                    for k, v in dict(self.ranges).items()}))
        object.__setattr__(self, "curves", tuple(self.curves))
        object.__setattr__(self, "codim2", tuple(self.codim2))
        object.__setattr__(self, "detail", _frozen(self.detail))

    def plot(self, path) -> Path:
        """Draw the diagram into ``path`` (a file, or a folder: ``diagram-MODEL.png`` in it):
        true curves solid, averaged curves dashed (lighter for higher orders), codim-2
        points as labelled markers."""
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        path = Path(path)
        if path.suffix == "" or path.is_dir():
            path.mkdir(parents=True, exist_ok=True)
            path = path / f"diagram-{self.model}.png"
        fig, ax = plt.subplots(figsize=(8.4, 4.6), dpi=150)
        seen = set()
        for c in self.curves:
            if not c.points:
                continue
            xs, ys = zip(*c.points)
            colour = _COLOURS.get(c.kind, "k")
            if c.method == "true":
                style, label = "-", c.kind
            else:
                style, label = ("--" if (c.order or 1) == 1 else ":"), \
                    f"{c.kind} averaged{'' if c.order is None else f' order {c.order}'}"
            extra = c.detail.get("label")
            if extra:
                label = f"{label} {extra}"
            ax.plot(xs, ys, style, color=colour, lw=1.2 if c.method == "true" else 1.0,
                    label=None if label in seen else label)
            seen.add(label)
        markers = "osD^v<>ph*"
        kinds = sorted({p.kind for p in self.codim2})
        for p in self.codim2:
            m = markers[kinds.index(p.kind) % len(markers)]
            ax.plot(*p.point, m, color="k", ms=5, mfc="none",
                    label=None if p.kind in seen else p.kind)
            seen.add(p.kind)
        a, b = self.axes
        if a in self.ranges:
            ax.set_xlim(*self.ranges[a])
        if b in self.ranges:
            ax.set_ylim(*self.ranges[b])
        ax.set_xlabel(a)
        ax.set_ylabel(b)
        fixed = ", ".join(f"{k}={v}" for k, v in self.params.items() if k not in self.axes)
        ax.set_title(f"{self.model}: {fixed}", fontsize=8)
        if seen:
            ax.legend(fontsize=6, loc="upper left", bbox_to_anchor=(1.01, 1.0))
        fig.tight_layout()
        fig.savefig(path, metadata={"Software": None})
        plt.close(fig)
        return path
