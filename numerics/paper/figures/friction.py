"""Friction laws and friction maps: the paper's question (does self-excitation lower friction?)
asked over whole ranges of the stage velocity, the potential strength and the excitability.

- :func:`draw_law` / :func:`law_figure`: the mean friction force (kinetic friction), the
  static friction and the dissipation per unit distance against ``v`` for one or more
  sliders on one figure, the regime of each point marked, against the quasi-static static
  friction ``Delta sqrt(1 - 1/eta^2)``, the one-well slip energy ``Delta W/lam`` and the
  viscous limit ``mu v``;
- :func:`map_figure`: a :class:`~numerics.sliding.maps.SliderComparison` on a
  two-parameter grid: the friction ratio SEDF/CDC (log colour scale, the contour where it is
  1), the dissipation ratio, and the regimes of both sliders, with the paper's points marked;
- :func:`study_figures`: the figures of a :class:`~numerics.paper.friction.FrictionStudy`;
- :func:`friction_figures`: the figures of the docs' "Friction laws" page
  (``kbm figures --only friction``), from :func:`numerics.paper.friction.friction_study`.

The study (its grids, its computation) is :mod:`numerics.paper.friction`; this module draws
it and builds on it, never the other way round.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np

from kbm.output.paper import FIG4, FIG5
from numerics.paper.friction import MAIN_JOB_SIZE, FrictionStudy, friction_study
from numerics._plot import pyplot as _plt

__all__ = ["draw_law", "law_figure", "map_figure", "friction_maps_from", "study_figures",
           "friction_figures"]

_REGIME_MARK = {"stick-slip": "o", "smooth sliding": "s", "self-oscillating sliding": "^",
                "oscillating sliding": "v", "runaway": "x"}
_REGIME_CODE = {"stick-slip": 0, "smooth sliding": 1, "self-oscillating sliding": 2,
                "oscillating sliding": 3, "runaway": 4, "": 5}
_LABEL = {"sedf_comoving": "SEDF (stage-attached)", "sedf": "SEDF (paper eq. 3)",
          "cdc": "CDC (eq. 12)"}

def _summary_regime(reg) -> str:
    kinds = sorted({str(r) or "failed" for r in np.ravel(reg)})
    return ", ".join(kinds)


def draw_law(maps, axes) -> None:
    """Draw friction laws (:class:`~numerics.sliding.maps.FrictionMap` over ``v``) on two axes:
    forces (mean and static) and dissipation per distance."""
    ax_f, ax_d = axes
    drawn: list[np.ndarray] = [[], []]  # what each panel shows, for limits that clip nothing
    absent = []
    for i, m in enumerate(maps):
        v = m.axes["v"]
        color = f"C{i}"
        label = _LABEL.get(m.model, m.model)
        F, S, D = m.field("mean_force"), m.field("static_force"), m.field("dissipation_per_distance")
        reg, steady = m.field("regime"), m.field("steady").astype(bool)
        def shown(y):
            y = np.abs(np.asarray(y, dtype=float))
            return y[np.isfinite(y) & (y > 0)]

        if not shown(F).size:  # every point a runaway or failed: no curve, no legend entry
            absent.append(f"{label}: no steady state at any v ({_summary_regime(reg)})")
            continue
        ax_f.plot(v, np.abs(F), "-", color=color, lw=1.4, label=f"{label}: |mean force|")
        if shown(S).size:
            ax_f.plot(v, S, ":", color=color, lw=1.2, label=f"{label}: static friction")
        ax_d.plot(v, np.abs(D), "-", color=color, lw=1.4, label=label)
        drawn[0] += [shown(F), shown(S)]
        drawn[1] += [shown(D)]
        for r, mark in _REGIME_MARK.items():
            sel = reg == r
            if sel.any():
                ax_f.plot(v[sel], np.abs(F[sel]), mark, color=color, ms=5,
                          mfc=color if r == "stick-slip" else "none", ls="none")
        neg = F < 0
        if neg.any():
            ax_f.plot(v[neg], np.abs(F[neg]), "o", color="k", ms=2, ls="none")
        if (~steady).any():
            ax_f.plot(v[~steady], np.abs(F[~steady]), "|", color="0.3", ms=10, ls="none")
    m0 = maps[0]
    p = dict(m0.params)
    v = m0.axes["v"]
    ax_f.plot(v, p.get("mu", 0.1) * v, "k--", lw=0.8, label=r"viscous limit $\mu v$")
    qs = m0.field("static_quasistatic")
    if np.isfinite(qs).any():
        ax_f.axhline(np.nanmax(qs), color="0.5", lw=0.8,
                     label=r"quasi-static $\Delta\sqrt{1-1/\eta^2}$")
    for ax in (ax_f, ax_d):
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("stage velocity $v$")
        ax.grid(True, which="major", alpha=0.3)
    ax_f.set_ylabel("spring force")
    ax_d.set_ylabel(r"dissipation per distance $\Gamma/(v\,\Delta t)$")
    for ax, parts in ((ax_f, drawn[0]), (ax_d, drawn[1])):
        vals = np.concatenate(parts) if parts else np.empty(0)
        if vals.size:  # the data's whole range, with a margin (nothing clipped)
            lo, hi = ax.get_ylim()
            ax.set_ylim(min(lo, vals.min() / 2), max(hi, vals.max() * 2))
    if absent:  # said above the panel, where it hides no curve and no legend
        ax_f.set_title("; ".join(absent), fontsize=8)
    ax_f.legend(fontsize=7, loc="lower right")
    ax_d.legend(fontsize=7, loc="lower right")


def law_figure(maps: Sequence, path: str | Path, title: str = "") -> Path:
    """Friction laws of one or more sliders (same ``v`` axis) written to ``path``."""
    plt = _plt()
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.2))
    draw_law(list(maps), axes)
    p = maps[0].params
    eta = maps[0].points[0].eta
    fig.suptitle(title or ("friction laws, " + ", ".join(f"{k} = {v:g}" for k, v in p.items())
                           + f", eta = {eta:.3g}  (filled: stick-slip, open: sliding, "
                           "triangle: self-oscillating, x: runaway, |: not steady, "
                           "dot: negative)"), fontsize=7)
    fig.tight_layout()
    path = Path(path)
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path


def map_figure(comp, path: str | Path, marks: Sequence[tuple[float, float, str]] = ()) -> Path:
    """A :class:`~numerics.sliding.maps.SliderComparison` on two axes (the first is ``v``):
    ratios and regimes, the paper's points ``marks = [(x, y, label)]`` drawn."""
    from matplotlib.colors import BoundaryNorm, ListedColormap, LogNorm

    plt = _plt()
    names = list(comp.first.axes)
    if len(names) != 2:
        raise ValueError(f"a map needs two axes, got {names}")
    X, Y = comp.first.axes[names[0]], comp.first.axes[names[1]]
    # two by two, so that the labels are readable at a paper's text width
    fig, axs = plt.subplots(2, 2, figsize=(11, 8.2))
    axs = axs.ravel()
    for ax, data, title in ((axs[0], comp.force_ratio, "mean force ratio SEDF/CDC"),
                            (axs[1], comp.dissipation_ratio, "dissipation ratio SEDF/CDC")):
        d = np.abs(np.asarray(data, dtype=float)).T
        d = np.where(d > 0, d, np.nan)
        ok = np.isfinite(d)
        lo, hi = (np.nanmin(d[ok]), np.nanmax(d[ok])) if ok.any() else (0.1, 10)
        lim = max(1 / lo, hi, 1.01)
        pc = ax.pcolormesh(X, Y, d, shading="nearest", cmap="RdBu_r",
                           norm=LogNorm(1 / lim, lim))
        fig.colorbar(pc, ax=ax)
        signed = np.asarray(data, dtype=float).T
        if np.isfinite(signed).sum() > 3:
            ax.contour(X, Y, signed, levels=[1.0], colors="k", linewidths=1.2)
        neg = signed < 0
        if neg.any():
            xx, yy = np.meshgrid(X, Y)
            ax.plot(xx[neg], yy[neg], "k.", ms=2)
        unsteady = ~comp.steady.T
        if unsteady.any():
            xx, yy = np.meshgrid(X, Y)
            ax.plot(xx[unsteady], yy[unsteady], "x", color="0.4", ms=2)
        ax.set_title(title + " (black line: 1)", fontsize=10)
    cmap = ListedColormap(["C0", "C1", "C2", "C4", "C3", "0.8"])
    norm = BoundaryNorm(np.arange(-0.5, 6.5), cmap.N)
    for ax, m in ((axs[2], comp.first), (axs[3], comp.second)):
        codes = np.vectorize(lambda r: _REGIME_CODE.get(r, 5))(m.field("regime")).T
        pc = ax.pcolormesh(X, Y, codes, shading="nearest", cmap=cmap, norm=norm)
        cb = fig.colorbar(pc, ax=ax, ticks=range(6))
        cb.ax.set_yticklabels(["stick-slip", "smooth", "self-osc.", "osc.", "runaway",
                               "failed"], fontsize=9)
        ax.set_title(f"regime: {_LABEL.get(m.model, m.model)}", fontsize=10)
    for ax in axs:
        ax.set_xscale("log")
        if names[1] == "beta":
            ax.set_yscale("log")
        ax.set_xlabel(names[0], fontsize=11)
        ax.set_ylabel(names[1], fontsize=11)
        ax.tick_params(labelsize=9)
        for x, y, label in marks:
            ax.plot([x], [y], "*", color="gold", mec="k", ms=12)
            ax.annotate(label, (x, y), fontsize=9, xytext=(3, 3), textcoords="offset points")
    fixed = ", ".join(f"{k} = {v:g}" for k, v in comp.first.params.items())
    fig.suptitle(f"SEDF against CDC over ({names[0]}, {names[1]}), {fixed}; dots: negative "
                 "friction (the SEDF propels itself), x: not steady", fontsize=10)
    fig.tight_layout()
    path = Path(path)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def _paper_marks(y_name: str) -> list[tuple[float, float, str]]:
    return [(FIG4["v"], FIG4[y_name], "Fig. 4"), (FIG5["v"], FIG5[y_name], "Figs. 5-6")]


def friction_maps_from(v_delta, v_beta, out_dir: Path) -> list[Path]:
    """The (v, Delta) and (v, beta) maps of two :class:`SliderComparison`, the paper's points
    marked."""
    return [map_figure(v_delta, Path(out_dir) / "friction_map_v_delta.png",
                       _paper_marks("Delta")),
            map_figure(v_beta, Path(out_dir) / "friction_map_v_beta.png", _paper_marks("beta"))]


def study_figures(study: FrictionStudy, out_dir) -> list[Path]:
    """The law figure of each ``Delta`` and the two maps of ``study``."""
    Path(out_dir).mkdir(parents=True, exist_ok=True)
    out = [law_figure(maps, Path(out_dir) / f"friction_law_delta{d:g}.png")
           for d, maps in study.laws.items()]
    return out + friction_maps_from(study.v_delta, study.v_beta, Path(out_dir))


def friction_figures(out_dir: Path, size: int | None = None,
                     progress: bool = False) -> list[Path]:
    """The friction laws and maps (:func:`numerics.paper.friction.friction_study`): the main
    job's 8 x 8 maps by default (as ``kbm reproduce``), ``size=32`` for the docs' figures."""
    dims = dict(MAIN_JOB_SIZE) if size is None else {"size": size, "laws": max(12, size * 3 // 4)}
    return study_figures(friction_study(progress=progress, **dims), out_dir)
