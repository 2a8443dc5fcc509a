"""Figures of classical KBM against the energy method: where each holds, and how it converges.

- :func:`methods_figure`: over ``(mu, Delta)`` per ``beta``, which methods are within
  1 % of the true cycle (colour) and within 1e-3 (cell labels), and the best error
  of each method (:func:`numerics.paper.methods.methods_map`);
- :func:`fixed_delta_figure`: log-log relative errors against ``mu`` at fixed
  ``Delta`` (:func:`numerics.comparison.fixed_delta.fixed_delta_convergence`), both
  methods, with lines of the predicted slopes.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from kbm.output.paper import POINTS
from numerics.paper.figures.comparison import CONTOURS, _edges, _save, error_contours
from numerics._plot import pyplot as _plt

__all__ = ["methods_figure", "fixed_delta_figure"]

_SHORT = {"KBM order 1": "K1", "KBM order 2": "K2", "energy order 1": "E1",
          "energy order 2": "E2"}


def methods_figure(out_dir: Path, *, quick: bool = False, mmap=None) -> list[Path]:
    """Where classical KBM and the energy method are within 1 % and 1e-3 of the true cycle."""
    from matplotlib.colors import ListedColormap

    from numerics.paper.methods import methods_map

    plt = _plt()
    if mmap is None:
        mmap = (methods_map([0.02, 0.2], [0.01, 1.5], [1.0], workers=2, progress=False)
                if quick else methods_map(progress=False))
    mus, Ds = np.array(mmap.axes["mu"]), np.array(mmap.axes["Delta"])
    betas = mmap.axes["beta"]
    fig, axes = plt.subplots(len(betas), 3, figsize=(16, 5.2 * len(betas)), squeeze=False,
                             constrained_layout=True)
    cmap = ListedColormap(["#d9d9d9", "#9ecae1", "#a1d99b", "#fdd49e"])
    names = ["neither within 1 %", "KBM only", "energy only", "both"]
    for i, b in enumerate(betas):
        err = {m: mmap.array(m, b) for m in _SHORT}
        kbm = np.fmin(err["KBM order 1"], err["KBM order 2"])
        en = np.fmin(err["energy order 1"], err["energy order 2"])
        cls = (kbm <= 1e-2).astype(float) + 2 * (en <= 1e-2)
        cls[np.all([np.isnan(v) for v in err.values()], axis=0)] = np.nan  # no true cycle
        ax = axes[i][0]
        ax.pcolormesh(_edges(mus), _edges(Ds), np.ma.masked_invalid(cls), cmap=cmap,
                      vmin=-0.5, vmax=3.5, shading="flat")
        for r in range(len(Ds)):
            for c in range(len(mus)):
                if np.isnan(cls[r, c]):
                    ax.plot(mus[c], Ds[r], "rx", ms=7)
                    continue
                ok = [s for m, s in _SHORT.items() if err[m][r, c] <= 1e-3]
                lab = "\n".join(" ".join(s for s in ok if s[0] == f) for f in "KE")
                ax.text(mus[c], Ds[r], lab.strip() or "-", ha="center", va="center",
                        fontsize=8, linespacing=0.9)
        _frame_paper_cells(ax, mus, Ds)
        for k, n in enumerate(names):
            ax.plot([], [], "s", color=cmap(k), ms=9, label=n)
        ax.plot([], [], "s", mfc="none", mec="r", mew=2, ms=9, label="the paper's parameters")
        ax.plot([], [], "rx", ms=7, label="no true cycle")
        ax.legend(fontsize=9, loc="upper center", bbox_to_anchor=(0.5, -0.15), ncol=2,
                  handletextpad=0.2, columnspacing=0.8)
        ax.set_title(f"beta = {b:g}: within 1 % (colour), within 1e-3 (labels)", fontsize=11)
        for j, (z, title) in enumerate(((kbm, "classical KBM, best of orders 1, 2"),
                                        (en, "energy method, best of orders 1, 2")), start=1):
            ax = axes[i][j]
            with np.errstate(divide="ignore", invalid="ignore"):
                lz = np.log10(z)
            im = ax.pcolormesh(_edges(mus), _edges(Ds), np.ma.masked_invalid(lz), vmin=-10,
                               vmax=0, cmap="viridis", shading="flat")
            if np.isfinite(lz).sum() >= 4 and len(mus) > 1 and len(Ds) > 1:
                error_contours(ax, mus, Ds, lz)
            ax.set_title(f"{title}, beta = {b:g}", fontsize=11)
            fig.colorbar(im, ax=ax, label="log10 relative error")
        for ax in axes[i]:
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.set_xlabel("mu", fontsize=11)
            ax.set_ylabel("Delta", fontsize=11)
            ax.tick_params(labelsize=10)
        for ax in axes[i][1:]:  # the first panel frames the paper's cells (labels stay clear)
            for (m0, D0) in POINTS:
                ax.plot(m0, D0, "r*", ms=12, mec="k")
    fig.suptitle("SEDF: classical KBM (K1, K2) and the energy method (E1, E2) against the "
                 "true cycle; error = max relative error of a, max x, frequency\n"
                 f"{CONTOURS}; x: no true cycle; red star or frame: the paper's parameters",
                 fontsize=12)
    return [_save(fig, out_dir, "methods_map.png")]


def _short(row: str) -> str:
    """``"energy order 2"`` -> ``"E2"``, ``"KBM order 1"`` -> ``"K1"`` (as in the methods map)."""
    kind, _, n = row.split()
    return ("E" if kind == "energy" else "K") + n


def _frame_paper_cells(ax, mus: np.ndarray, Ds: np.ndarray) -> None:
    """A red frame round each grid cell of the paper's parameters (a star there would cover
    the cell's labels); a star where the point is off the grid."""
    from matplotlib.patches import Rectangle

    em, eD = _edges(mus), _edges(Ds)
    for (m0, D0) in POINTS:
        c, r = np.nonzero(np.isclose(mus, m0))[0], np.nonzero(np.isclose(Ds, D0))[0]
        if len(c) and len(r):
            c, r = c[0], r[0]
            ax.add_patch(Rectangle((em[c], eD[r]), em[c + 1] - em[c], eD[r + 1] - eD[r],
                                   fill=False, ec="r", lw=2, zorder=3))
        else:
            ax.plot(m0, D0, "r*", ms=12, mec="k")


def fixed_delta_figure(out_dir: Path, *, quick: bool = False, conv=None) -> list[Path]:
    """Log-log relative errors vs ``mu`` at fixed ``Delta``: energy orders and classical KBM."""
    from numerics.comparison.fixed_delta import fixed_delta_convergence

    plt = _plt()
    if conv is None:
        conv = (fixed_delta_convergence((1.5,), (1.0,), (0.1, 0.05, 0.025),
                                        energy_orders=(1, 2))
                if quick else fixed_delta_convergence())
    keys = [("frequency", "frequency"), ("amplitude_max", "max x"),
            ("floquet_exponent", "Floquet exponent L (dotted: theory - 1, L = O(mu))")]
    studies = conv.studies
    fig, axes = plt.subplots(len(studies), len(keys), figsize=(4.8 * len(keys),
                                                                3.6 * len(studies)),
                             squeeze=False, constrained_layout=True)
    for i, s in enumerate(studies):
        e = np.array(s.eps)
        for j, (key, name) in enumerate(keys):
            ax = axes[i][j]
            for row in s.rows:
                rel = s.relative[(row, key)]
                energy = row.startswith("energy")
                p = s.predicted[(row, key)]
                label = (f"{_short(row)}: {s.slopes[(row, key)]:.2f}"
                         + (f" ({p})" if p is not None else ""))
                line, = ax.loglog(e, rel, "o-" if energy else "s--", ms=4, label=label)
                ok = np.isfinite(s.errors[(row, key)])
                if energy and p is not None and ok.any():
                    # the exponent L itself is O(mu): its relative error falls one order slower
                    q = p - 1 if key == "floquet_exponent" else p
                    k = np.nonzero(ok)[0][-1]
                    ax.loglog(e, rel[k] * (e / e[k]) ** q, ":", color=line.get_color(), lw=1)
            ax.set_title(f"Delta = {s.Delta:g}, beta = {s.beta:g}: {name}", fontsize=9)
            ax.set_xlabel("mu")
            ax.set_ylabel("relative error")
            ax.legend(fontsize=8, title="slope (theory)", title_fontsize=8, loc="lower right",
                      framealpha=0.85, borderpad=0.3, labelspacing=0.25, handlelength=1.6)
            ax.grid(True, which="both", alpha=0.3)
    fig.suptitle("Fixed Delta: relative errors against mu.  The energy method (E1-E3, solid) "
                 "converges at its predicted orders (dotted);\nclassical KBM (K1, K2, dashed) "
                 "does not, as delta = Delta/mu grows.  Slopes fitted to the absolute errors "
                 "(theory in parentheses)", fontsize=11)
    return [_save(fig, out_dir, "fixed_delta_convergence.png")]
