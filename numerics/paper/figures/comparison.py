"""Figures of the KBM-versus-numerics comparison: convergence, validity map, phase portraits.

Each function takes an output folder and returns the paths it wrote (PNG).
matplotlib is imported here only, lazily, with the Agg backend.

- :func:`convergence_figure`: errors of KBM orders against ``mu`` (log-log) for van
  der Pol and the SEDF at fixed ``delta = Delta/mu``, with lines of the predicted
  slopes;
- :func:`validity_figure`: relative error of KBM orders 1 and 2 over ``(mu, Delta)``
  for each ``beta``, the 1 % contour, the paper's parameters marked;
- :func:`phase_fig3_figure`: KBM cycles of each order and the paper's formulas
  against the numerical cycle for the paper's Fig. 3 (``Delta = 1.5, mu = 0.1``);
- :func:`phase_small_figure`: the same where KBM is accurate (small ``Delta``),
  with the deviation from the true cycle along its phase.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from kbm.output.paper import POINTS
from numerics._plot import pyplot as _plt

__all__ = ["convergence_figure", "validity_figure", "phase_fig3_figure", "phase_small_figure"]


#: the error contours of the maps, one convention for every figure: (log10 level, style)
CONTOUR_LEVELS = ((-3, "--"), (-2, "-"))
#: what the contours mean, for the figures' titles
CONTOURS = "white contours: solid 1 % error, dashed 1e-3"


def error_contours(ax, x: np.ndarray, y: np.ndarray, log_error: np.ndarray):
    """The 1 % (solid) and 1e-3 (dashed) contours of ``log10`` relative errors, white (the
    styles given explicitly: matplotlib draws negative levels of a one-colour contour
    dashed by default).  Returns the contour set."""
    levels, styles = zip(*CONTOUR_LEVELS)
    return ax.contour(x, y, np.ma.masked_invalid(log_error), levels=list(levels), colors="w",
               linestyles=list(styles), linewidths=1.4)


def _save(fig, out_dir: Path, name: str) -> Path:
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    path = out_dir / name
    fig.savefig(path, dpi=120, bbox_inches="tight")
    _plt().close(fig)
    return path


# ----------------------------------------------------------------------------- convergence
def convergence_figure(out_dir: Path, *, quick: bool = False) -> list[Path]:
    """Log-log errors of each KBM order against ``mu`` with the predicted slopes."""
    from numerics.comparison.convergence import convergence_study

    plt = _plt()
    eps = [0.025, 0.05, 0.1] if quick else [0.0125, 0.025, 0.05, 0.1, 0.2]
    studies = [
        ("van der Pol", convergence_study("vdp", eps if quick else eps[1:],
                                          orders=(1, 2) if quick else (1, 2, 3, 4))),
        ("SEDF, Delta/mu = 2, beta = 1", convergence_study(
            "sedf", eps, orders=(1, 2), fixed={"delta": 2, "beta": 1, "k": "2*pi"})),
    ]
    keys = [("amplitude", "first-harmonic amplitude"), ("frequency", "frequency"),
            ("floquet_exponent", "Floquet exponent T dA/da"),
            ("dissipation", "Gamma over the KBM cycle")]
    fig, axes = plt.subplots(len(studies), len(keys), figsize=(4.0 * len(keys), 3.6 * len(studies)),
                             squeeze=False)
    for i, (title, s) in enumerate(studies):
        e = np.array(s.eps)
        for j, (key, name) in enumerate(keys):
            ax = axes[i][j]
            for N in s.orders:
                err = s.errors[(N, key)]
                line, = ax.loglog(e, err, "o-", label=f"N={N}: slope {s.slopes[(N, key)]:.2f} "
                                  f"(theory {s.predicted[(N, key)]})")
                p = s.predicted[(N, key)]
                ref = err[-1] * (e / e[-1]) ** p
                ax.loglog(e, ref, ":", color=line.get_color(), lw=1)
            if key == "dissipation":
                ax.loglog(e, np.maximum(s.numeric_dissipation, 1e-16), "k^--", ms=4,
                          label="|Gamma| true cycle")
            ax.set_title(f"{title}\n{name}", fontsize=9)
            ax.set_xlabel("mu")
            # label the values of mu used, not the log axis's minor ticks (they overlap)
            from matplotlib.ticker import NullFormatter

            ax.xaxis.set_minor_formatter(NullFormatter())
            ax.set_xticks(e, [f"{v:g}" for v in e], fontsize=7)
            ax.set_ylabel("|KBM - numerical|")
            ax.legend(fontsize=7)
            ax.grid(True, which="both", alpha=0.3)
    fig.suptitle("Convergence of KBM predictions (dotted: predicted order)")
    fig.tight_layout()
    return [_save(fig, out_dir, "kbm_convergence.png")]


# ----------------------------------------------------------------------------- validity
def validity_figure(out_dir: Path, *, quick: bool = False, vmap=None) -> list[Path]:
    """Relative error of KBM orders 1, 2 over ``(mu, Delta)`` per ``beta``, 1 % contour."""
    from numerics.paper.validity import validity_map

    plt = _plt()
    if vmap is None:
        if quick:
            vmap = validity_map([0.05, 0.1], [0.01, 0.1, 1.5], [1.0], workers=2,
                                progress=False)
        else:
            vmap = validity_map(progress=False)
    mus = np.array(vmap.axes["mu"])
    Ds = np.array(vmap.axes["Delta"])
    betas = vmap.axes["beta"]
    fig, axes = plt.subplots(len(betas), len(vmap.orders),
                             figsize=(4.6 * len(vmap.orders), 3.8 * len(betas)), squeeze=False,
                             constrained_layout=True)
    im = None
    for i, b in enumerate(betas):
        for j, N in enumerate(vmap.orders):
            ax = axes[i][j]
            err = vmap.array(N, b)
            with np.errstate(divide="ignore", invalid="ignore"):
                z = np.log10(err)
            im = ax.pcolormesh(_edges(mus), _edges(Ds), np.ma.masked_invalid(z),
                               vmin=-6, vmax=-0.5, cmap="viridis", shading="flat")
            ax.set_xscale("log")
            ax.set_yscale("log")
            if np.isfinite(z).sum() >= 4 and len(mus) > 1 and len(Ds) > 1:
                error_contours(ax, mus, Ds, z)
            bad = np.isnan(err)
            for (r, c) in zip(*np.nonzero(bad)):
                ax.plot(mus[c], Ds[r], "rx", ms=6)
            for (m0, D0) in POINTS:
                ax.plot(m0, D0, "r*", ms=13, mec="k")
            ax.set_title(f"KBM order {N}, beta = {b:g}", fontsize=10)
            ax.set_xlabel("mu")
            ax.set_ylabel("Delta")
    fig.colorbar(im, ax=axes, label="log10 relative error (max of a, max x, frequency)")
    fig.suptitle("SEDF: where KBM is accurate\n"
                 f"{CONTOURS}; star: the paper's mu = 0.1, Delta = 1.5, 3; "
                 "x: no cycle, true or KBM", fontsize=10)
    return [_save(fig, out_dir, "kbm_validity.png")]


def _edges(v: np.ndarray) -> np.ndarray:
    """Cell edges (geometric midpoints) around log-spaced centres."""
    v = np.asarray(v, dtype=float)
    if v.size == 1:
        return np.array([v[0] / 1.5, v[0] * 1.5])
    mid = np.sqrt(v[:-1] * v[1:])
    return np.concatenate([[v[0] ** 2 / mid[0]], mid, [v[-1] ** 2 / mid[-1]]])


# ----------------------------------------------------------------------------- phase portraits
def _portrait(ax, comp, title):
    c = comp.numeric
    ax.plot(np.append(c.x, c.x[0]), np.append(c.xdot, c.xdot[0]), "k-", lw=2.5,
            label="numerical", zorder=1)
    styles = {0: ("C3", ":"), 1: ("C0", "--"), 2: ("C1", "-."), 3: ("C2", "--"),
              4: ("C4", "-.")}
    for p in comp.predictions:
        if not p.success:
            continue
        col, ls = styles.get(p.order, ("C5", "--"))
        ax.plot(np.append(p.x, p.x[0]), np.append(p.xdot, p.xdot[0]), ls, color=col, lw=1.4,
                label=p.label if p.source != "paper" else "paper eqs. 5-9", zorder=2)
    ax.set_title(title, fontsize=9)
    ax.set_xlabel("x")
    ax.set_ylabel("dx/dt")
    xm, vm = 1.35 * np.max(np.abs(c.x)), 1.35 * np.max(np.abs(c.xdot))
    ax.set_xlim(-xm, xm)
    ax.set_ylim(-vm, vm)


def _deviation(ax, comp, with_paper=False):
    """Signed distance of each predicted orbit from the true cycle, along the true cycle's
    phase t/T (the distance to the nearest point of the prediction's closed curve, positive
    outside).  A polar angle is not monotonic on cycles that are not star-shaped, which
    drew stripes."""
    c = comp.numeric
    q = np.column_stack([c.x, c.xdot])
    phase = np.arange(len(q)) / len(q)
    for p in comp.predictions:
        if not p.success or (p.source == "paper" and not with_paper):
            continue
        curve = np.column_stack([p.x, p.xdot])
        d = np.linalg.norm(q[:, None, :] - curve[None, :, :], axis=2)
        j = np.argmin(d, axis=1)
        sign = np.sign(np.hypot(*curve[j].T) - np.hypot(*q.T))
        ax.plot(phase, sign * d[np.arange(len(q)), j], label=p.label)
    ax.axhline(0, color="k", lw=0.8)
    ax.set_xlabel("phase t/T of the true cycle (0 at the maximum of x)")
    ax.set_ylabel("signed distance to the true cycle")
    ax.set_title("deviation from the true cycle in the phase plane", fontsize=9)
    ax.legend(fontsize=7)


def phase_fig3_figure(out_dir: Path, *, quick: bool = False) -> list[Path]:
    """KBM orders 1, 2 and the paper's formulas vs the numerical cycle, paper Fig. 3."""
    from numerics.comparison import compare
    from numerics.paper.printed import paper_prediction

    plt = _plt()
    betas = (0.5, 1.0) if quick else (0.1, 0.25, 0.5, 1.0)
    fig, axes = plt.subplots(2, len(betas), figsize=(4.2 * len(betas), 8.4), squeeze=False)
    for j, b in enumerate(betas):
        comp = compare("sedf", {"mu": 0.1, "Delta": 1.5, "beta": b, "lam": 1}, orders=(1, 2),
                       extra=[paper_prediction])
        _portrait(axes[0][j], comp, f"Delta = 1.5, mu = 0.1, beta = {b:g}")
        _deviation(axes[1][j], comp)
    axes[0][0].legend(fontsize=7, loc="lower left")
    fig.suptitle("Paper Fig. 3 parameters: KBM cycles and the paper's eqs. (5)-(9) vs the "
                 "true cycle (the paper's curve leaves the frame: its eq. 8 lacks the "
                 "factor 1/(2n(n+1)))", fontsize=10)
    fig.tight_layout()
    return [_save(fig, out_dir, "kbm_phase_fig3.png")]


def phase_small_figure(out_dir: Path, *, quick: bool = False) -> list[Path]:
    """Small-``Delta`` cases where KBM is accurate: portraits and deviations from the true cycle."""
    from numerics.comparison import compare

    plt = _plt()
    cases = [("sedf", {"mu": 0.05, "Delta": 0.1, "beta": 1, "lam": 1}, (1, 2)),
             ("sedf", {"mu": 0.1, "Delta": 0.01, "beta": 0.25, "lam": 1}, (1, 2))]
    if not quick:
        cases.append(("vdp", {"mu": 0.2}, (1, 2, 3, 4)))
    fig, axes = plt.subplots(2, len(cases), figsize=(4.4 * len(cases), 8.0), squeeze=False)
    for j, (model, params, orders) in enumerate(cases):
        comp = compare(model, params, orders=orders)
        title = f"{model}: " + ", ".join(f"{k} = {v:g}" for k, v in params.items()
                                         if k != "lam")
        _portrait(axes[0][j], comp, title)
        _deviation(axes[1][j], comp)
    axes[0][0].legend(fontsize=7, loc="lower left")
    fig.suptitle("Where KBM is accurate: small Delta (sedf) and van der Pol", fontsize=10)
    fig.tight_layout()
    return [_save(fig, out_dir, "kbm_phase_small.png")]

