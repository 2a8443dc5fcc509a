"""Bifurcation diagrams of limit cycles: every branch, stable solid, unstable dashed.

:func:`draw_diagram` draws a :class:`numerics.comparison.diagram.BranchDiagram`
(``amplitude_max`` or ``period`` against the varied parameter) with the special points
marked (fold: circle, Hopf end: square, homoclinic end: cross, other end: triangle) and
the analytic branches as small markers; :func:`diagram_figure` writes it to a file;
:func:`sedf_branches` draws the SEDF's cycles against ``Delta`` (``mu = 0.1``,
``beta = 1``) and against ``beta`` (``Delta = 1.5``).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from numerics._plot import pyplot as _plt, save_png_pdf


__all__ = ["draw_diagram", "diagram_figure", "sedf_branches"]

_MARK = {"fold": "o", "hopf": "s", "homoclinic": "X", "end": "^"}
_ANALYTIC = {"kbm": ("+", 4), "energy": ("x", 3)}


def draw_diagram(d, ax, quantity: str = "amplitude_max", analytic: bool = True,
                 legend: bool = True) -> list:
    """Draw the branches of ``d`` on ``ax``.

    Parameters
    ----------
    d : numerics.comparison.diagram.BranchDiagram
    ax : matplotlib.axes.Axes
    quantity : {"amplitude_max", "period"}
        What is plotted against the parameter (the analytic amplitudes are the KBM
        first-harmonic ``a*`` and the largest ``x`` of the energy-balance orbit).
    analytic : bool
        Overlay the analytic branches.
    legend : bool
        Draw the legend on ``ax`` (else the caller places the returned handles).

    Returns
    -------
    list
        The legend handles.
    """
    if quantity not in ("amplitude_max", "period"):
        raise ValueError(f"quantity must be 'amplitude_max' or 'period', got {quantity!r}")
    for i, b in enumerate(d.branches):
        p = np.array([q.parameter for q in b.points])
        y = np.array([getattr(q, quantity) for q in b.points])
        st = np.array([q.stable for q in b.points])
        color = f"C{i}"
        for k in range(len(p) - 1):  # a segment is drawn in the style of its more unstable end
            ok = st[k] and st[k + 1]
            ax.plot(p[k:k + 2], y[k:k + 2], color=color, lw=1.6 if ok else 1.2,
                    ls="-" if ok else "--")
        for s in b.special:
            yv = s.amplitude if quantity == "amplitude_max" else s.period
            ax.plot([s.parameter], [yv], marker=_MARK.get(s.kind, "^"), color="k", ms=7,
                    mfc="none" if s.kind == "fold" else "k", ls="none")
    if analytic:
        for j, c in enumerate(d.analytic):
            if not c.points:
                continue
            arr = np.array([(p, a, T) for p, a, T, _ in c.points], dtype=float)
            stab = np.array([s for *_, s in c.points], dtype=bool)
            m, ms = _ANALYTIC.get(c.method, (".", 3))
            y = arr[:, 1] if quantity == "amplitude_max" else arr[:, 2]
            col = f"C{j + 3}"
            ax.plot(arr[stab, 0], y[stab], ls="none", marker=m, ms=ms, color=col,
                    label=f"{c.method} order {c.order}")
            ax.plot(arr[~stab, 0], y[~stab], ls="none", marker=m, ms=ms, color=col, alpha=0.4)
    from matplotlib.lines import Line2D

    # the legend's lines in the colours the branches are drawn in (one branch: its colour;
    # several: one entry each, and the line styles in grey)
    style = "C0" if len(d.branches) == 1 else "0.45"
    branches = ([Line2D([], [], color=f"C{i}", lw=1.6, label=f"branch {i + 1}")
                 for i in range(len(d.branches))] if len(d.branches) > 1 else [])
    handles = [*branches,
               Line2D([], [], color=style, ls="-", lw=1.6, label="stable (continuation)"),
               Line2D([], [], color=style, ls="--", lw=1.2, label="unstable"),
               *[Line2D([], [], color="k", marker=v, ls="none", label=k,
                        mfc="none" if k == "fold" else "k")
                 for k, v in _MARK.items() if any(s.kind == k for b in d.branches
                                                  for s in b.special)]]
    h2, _ = ax.get_legend_handles_labels()
    if legend:
        ax.legend(handles=handles + h2, fontsize=7, loc="best")
    ax.set_xlabel(d.parameter)
    ax.set_ylabel("max x" if quantity == "amplitude_max" else "period T")
    lo, hi = d.bounds
    ax.set_xlim(lo - 0.02 * (hi - lo), hi + 0.02 * (hi - lo))
    return handles + h2


def diagram_figure(d, path: str | Path, title: str | None = None) -> list[Path]:
    """Write amplitude and period against the parameter side by side (PNG and PDF)."""
    plt = _plt()
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    handles = draw_diagram(d, axes[0], "amplitude_max", legend=False)
    draw_diagram(d, axes[1], "period", analytic=True, legend=False)
    _zoom_short_branches(d, axes[0])
    _period_law_inset(d, axes[1])
    # one legend for both panels, below them: on a panel it covered data
    fig.legend(handles=handles, loc="lower center", ncol=min(len(handles), 5), fontsize=8,
               frameon=False, bbox_to_anchor=(0.5, -0.02))
    fig.subplots_adjust(bottom=0.24)
    fig.suptitle(title or f"limit cycles of {d.model} against {d.parameter}", fontsize=10)
    return save_png_pdf(fig, path)


def _period_law_inset(d, ax) -> None:
    """For a branch that ends homoclinic with the period law fitted
    (:mod:`numerics.cycles.homoclinic`): an inset of ``T`` against ``-ln|p_h - p|`` with the
    line of the computed slope ``k = sum 1/lambda_u`` through the last point, so the
    logarithmic growth and the end found are seen together.  Drawn for a diagram of one
    branch only: with several, the inset would cover their curves."""
    import re

    if len(d.branches) != 1:
        return
    for i, b in enumerate(d.branches):
        end = next((s for s in b.special if s.kind == "homoclinic"), None)
        m = None if end is None else re.search(r"k = sum 1/lambda_u = ([0-9.eE+-]+)",
                                               end.message)
        if m is None or len(b.points) < 6:
            continue
        k, ph = float(m.group(1)), end.parameter
        p = np.array([q.parameter for q in b.points])
        T = np.array([q.period for q in b.points])
        near = np.abs(ph - p) < 0.25 * (np.max(p) - np.min(p))
        if np.count_nonzero(near) < 4:
            continue
        u = -np.log(np.abs(ph - p[near]))
        ins = ax.inset_axes([0.14, 0.48, 0.38, 0.36])
        ins.plot(u, T[near], "o", ms=2.5, color=f"C{i}")
        uu = np.linspace(u.min(), u.max(), 2)
        ins.plot(uu, T[near][-1] + k * (uu - u[-1]), "k--", lw=0.8)
        ins.set_xlabel(rf"$-\ln|{d.parameter}_h - {d.parameter}|$", fontsize=6)
        ins.set_ylabel("T", fontsize=6)
        ins.tick_params(labelsize=5)
        ins.set_title(f"{d.parameter}_h = {ph:.6g}; slope k = {k:.4g} (computed)", fontsize=6)
        return


def _zoom_short_branches(d, ax) -> None:
    """An inset that magnifies the branches spanning less than a tenth of the range (the
    SEDF's side-well cycles in beta, drawn under their end markers at full scale)."""
    lo, hi = d.bounds
    short = [i for i, b in enumerate(d.branches) if b.points and (
        max(q.parameter for q in b.points) - min(q.parameter for q in b.points)
        < 0.1 * (hi - lo))]
    if not short:
        return
    ins = ax.inset_axes([0.52, 0.5, 0.45, 0.45])
    ps, ys = [], []
    for i in short:
        b = d.branches[i]
        p = np.array([q.parameter for q in b.points])
        y = np.array([q.amplitude_max for q in b.points])
        st = np.array([q.stable for q in b.points])
        for k in range(len(p) - 1):
            ok = st[k] and st[k + 1]
            ins.plot(p[k:k + 2], y[k:k + 2], color=f"C{i}", lw=1.4 if ok else 1.1,
                     ls="-" if ok else "--")
        for s in b.special:
            ins.plot([s.parameter], [s.amplitude], marker=_MARK.get(s.kind, "^"), color="k",
                     ms=5, mfc="none" if s.kind == "fold" else "k", ls="none")
        ps += list(p)
        ys += list(y)
    pad_p = 0.08 * (max(ps) - min(ps) or 1.0)
    ins.set_xlim(min(ps) - pad_p, max(ps) + pad_p)
    ins.tick_params(labelsize=6)
    ins.set_title(f"branches {', '.join(str(i + 1) for i in short)} magnified", fontsize=7)
    ax.indicate_inset_zoom(ins, edgecolor="0.5")


def sedf_branches(out_dir: Path) -> list[Path]:
    """The SEDF's cycles against ``Delta`` (0 to 4; ``mu = 0.1, beta = 1``) and against
    ``beta`` (0.05 to 4; ``Delta = 1.5``): every branch through the start value, stable
    and unstable, with folds and ends, KBM order 1 and the energy balance overlaid."""
    from numerics.comparison.diagram import branch_diagram

    out_dir = Path(out_dir)
    d1 = branch_diagram("sedf", {"mu": 0.1, "beta": 1, "lam": 1, "Delta": 0}, "Delta",
                        (0.0, 4.0), orders=(1,), n_analytic=81)
    paths = diagram_figure(d1, out_dir / "sedf_branches_delta",
                           r"SEDF cycles against $\Delta$ ($\mu = 0.1$, $\beta = 1$, "
                           r"$\lambda = 1$)")
    d2 = branch_diagram("sedf", {"mu": 0.1, "Delta": 1.5, "lam": 1, "beta": 1}, "beta",
                        (0.05, 4.0), orders=(1,), n_analytic=81)
    paths += diagram_figure(d2, out_dir / "sedf_branches_beta",
                            r"SEDF cycles against $\beta$ ($\mu = 0.1$, $\Delta = 1.5$, "
                            r"$\lambda = 1$)")
    return paths
