"""Figures of forced oscillators: response curves, Mathieu tongues, entrainment.

``python -m numerics.paper.figures.forced DIR`` writes the five figures of ``docs/forced.rst``
(Duffing primary resonance at orders 1 and 2 against shooting, the superharmonic
resonance, the Mathieu transition curves at delta = 1/4 and 1 against scipy's
characteristic values and Floquet numerics, the van der Pol locking boundary and its
closed curve of steady states);
:func:`plot_response` draws one :class:`~numerics.comparison.response_diagram.ResponseDiagram`
(``kbm response --out``).  matplotlib is
imported lazily (Agg backend).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from numerics.comparison.response_convergence import ConvergenceTable
from numerics.comparison.response_diagram import ResponseDiagram, response_diagram
from numerics._plot import pyplot as _plt, save as _save_ax

__all__ = ["duffing_figure", "locking_figure", "mathieu_figure", "plot_convergence",
           "plot_response", "superharmonic_figure", "vdp_response_figure", "write_all"]


def _draw(ax, d: ResponseDiagram, color: str, label: str, numeric: bool = True) -> None:
    for b in d.analytic.branches:
        s, av, st = b.sigma, b.amplitude, b.stable
        ax.plot(np.where(st, s, np.nan), np.where(st, av, np.nan), "-", color=color, lw=1.6,
                label=label)
        ax.plot(np.where(~st, s, np.nan), np.where(~st, av, np.nan), "--", color=color, lw=1.2)
        label = None
    for f in d.analytic.folds:
        ax.plot(f.sigma, f.amplitude, "o", color=color, ms=5, mfc="white")
    if d.analytic.trivial:
        tr = np.array([(s, st == "stable") for s, st in d.analytic.trivial], dtype=float)
        ax.plot(tr[:, 0], np.where(tr[:, 1] > 0, 0.0, np.nan), "-", color=color, lw=2.5)
        ax.plot(tr[:, 0], np.where(tr[:, 1] > 0, np.nan, 0.0), "--", color=color, lw=1.2)
    if numeric and d.numeric is not None:
        lab = "shooting (stable / unstable)"
        for b in d.numeric.branches:
            s = np.array([o.sigma for o in b])
            av = np.array([o.amplitude for o in b])
            st = np.array([o.stable for o in b])
            k = slice(None, None, max(1, len(b) // 60))
            ax.plot(s[k][st[k]], av[k][st[k]], ".", color="k", ms=4, label=lab)
            ax.plot(s[k][~st[k]], av[k][~st[k]], "x", color="k", ms=3)
            lab = None


def plot_response(d: ResponseDiagram, path: Path, extra: list[ResponseDiagram] = ()) -> Path:
    """Analytic curve(s) (stable solid, unstable dashed, folds circled), shooting points
    and backbone of a response diagram, written to ``path``."""
    plt = _plt()
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    colors = ["tab:blue", "tab:red", "tab:green"]
    for i, dd in enumerate([*extra, d]):
        _draw(ax, dd, colors[i % 3], f"KBM order {dd.order}", numeric=dd is d)
    if d.backbone:
        bb = np.array(d.backbone)
        ax.plot(bb[:, 0], bb[:, 1], ":", color="gray", label="backbone")
    ax.set_xlabel(r"detuning $\sigma$  ($\nu = (p/q)\,\omega_0 + \mu\sigma$)")
    ax.set_ylabel("amplitude $a$ at frequency $(q/p)\\nu$")
    pars = ", ".join(f"{k} = {v:g}" for k, v in d.values.items())
    ax.set_title(f"{d.model}, resonance {d.resonance}: {pars}", fontsize=9)
    return _save_ax(fig, ax, path)


def plot_convergence(t: ConvergenceTable, path: Path) -> Path:
    """The errors of each order against ``mu`` on log-log axes, each order's fitted slope in
    the legend, with a dotted guide line of the expected slope ``N`` through the middle
    point; written to ``path`` (``kbm response --convergence --out``)."""
    plt = _plt()
    fig, ax = plt.subplots(figsize=(5.6, 4.2))
    mus = np.asarray(t.mus, float)
    order = np.argsort(mus)
    mus = mus[order]
    colors = ["tab:blue", "tab:red", "tab:green", "tab:orange", "tab:purple", "tab:brown",
              "tab:pink", "tab:olive"]
    slopes = t.slopes
    for i, n in enumerate(t.orders):
        err = np.asarray(t.errors[n], float)[order]
        c = colors[i % len(colors)]
        ax.loglog(mus, err, "o-", color=c, ms=5,
                  label=f"order {n}: slope {slopes[n]:.2f} (expected {n})")
        ok = np.isfinite(err) & (err > 0)
        if ok.any():
            k = np.flatnonzero(ok)[ok.sum() // 2]
            ax.loglog(mus, err[k] * (mus / mus[k]) ** n, ":", color=c, lw=1)
    ax.set_xlabel(r"$\mu$")
    ax.set_ylabel("|order-N prediction - true (shooting)|")
    pars = ", ".join(f"{k} = {v:g}" for k, v in t.parameters.items())
    ax.set_title(f"{t.model}, resonance {t.resonance}: {t.quantity}\n{pars}", fontsize=9)
    return _save_ax(fig, ax, path)


def duffing_figure(out: Path) -> Path:
    vals = {"mu": 0.05, "zeta": 0.1, "alpha": 1, "h": 0.5}
    d1 = response_diagram("duffing-forced", vals, (-1, 3), order=1, numeric=False,
                          amplitudes=(1e-3, 3))
    d2 = response_diagram("duffing-forced", vals, (-1, 3), order=2, amplitudes=(1e-3, 3))
    return plot_response(d2, Path(out) / "forced_duffing.png", [d1])


def superharmonic_figure(out: Path) -> Path:
    """Hard superharmonic resonance (K cos(nu t), nu near omega0/3), orders 1 and 3."""
    vals = {"mu": 0.02, "zeta": 0.1, "alpha": 1, "K": 1}
    d1 = response_diagram("duffing-super-hard", vals, (-0.5, 1.5), order=1, numeric=False,
                          amplitudes=(1e-3, 3))
    d3 = response_diagram("duffing-super-hard", vals, (-0.5, 1.5), order=3,
                          amplitudes=(1e-3, 3))
    return plot_response(d3, Path(out) / "forced_superharmonic.png", [d1])


def mathieu_figure(out: Path) -> Path:
    """Transition curves delta(eps) of the tongues at delta = 1/4 (orders 1, 2, 4) and at
    delta = 1 (``mathieu-2``, opening at order 2: orders 2, 4) against scipy and Floquet."""
    from scipy.special import mathieu_a, mathieu_b

    from kbm.expansion.forced import derive_forced
    from kbm.slowflow.tongues import epsilon, mathieu_transition, transition_curves

    import sympy as sp

    plt = _plt()
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    eps = np.linspace(0, 0.8, 200)
    for n in (1, 2):
        ax.plot(mathieu_a(n, 2 * eps) / 4, eps, "k-", lw=2.5, alpha=0.35,
                label=r"$a_n/4$, $b_n/4$ (scipy)" if n == 1 else None)
        ax.plot(mathieu_b(n, 2 * eps) / 4, eps, "k-", lw=2.5, alpha=0.35)
    colors = {1: "tab:blue", 2: "tab:orange", 4: "tab:red"}
    for model, orders in (("mathieu", (1, 2, 4)), ("mathieu-2", (2, 4))):
        for n in orders:
            for i, tc in enumerate(transition_curves(derive_forced(model, n))):
                f = sp.lambdify(epsilon, mathieu_transition(tc), "numpy")
                ax.plot(f(eps) * np.ones_like(eps), eps, "--", color=colors[n],
                        label=f"KBM order {n}" if i == 0 and model == "mathieu" else None)
    fl = _floquet_boundaries(np.linspace(0.1, 0.8, 8))
    ax.plot(fl[:, 1], fl[:, 0], "ko", ms=4, label="Floquet (trace of monodromy = -2, +2)")
    ax.plot(fl[:, 2], fl[:, 0], "ko", ms=4)
    fl2 = _floquet_boundaries(np.linspace(0.2, 0.8, 7), n=2)
    ax.plot(fl2[:, 1], fl2[:, 0], "ko", ms=4)
    ax.plot(fl2[:, 2], fl2[:, 0], "ko", ms=4)
    ax.set_xlabel(r"$\delta$")
    ax.set_ylabel(r"$\varepsilon$")
    ax.set_title(r"$x'' + (\delta + \varepsilon\cos t)\,x = 0$: the tongues at "
                 r"$\delta = 1/4$ and $\delta = 1$", fontsize=9)
    ax.set_ylim(0, 1.1)  # room for the legend above the curves
    ax.legend(fontsize=8, loc="upper center", ncol=2)
    fig.tight_layout()
    path = Path(out) / "forced_mathieu.png"
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def _floquet_boundaries(eps, n: int = 1) -> np.ndarray:
    """``(eps, delta_low, delta_high)``: where the monodromy matrix of ``x'' + (delta + eps
    cos t) x = 0`` over ``2 pi`` has trace ``-2`` (``n`` odd) or ``+2`` (``n`` even): the
    edges of the tongue at ``n**2/4``."""
    from scipy.integrate import solve_ivp
    from scipy.optimize import brentq
    from scipy.special import mathieu_a, mathieu_b

    target = 2.0 if n % 2 == 0 else -2.0

    def trace(d, e):
        def f(t, y):
            k = d + e * np.cos(t)
            return [y[1], -k * y[0], y[3], -k * y[2]]

        s = solve_ivp(f, (0, 2 * np.pi), [1, 0, 0, 1], rtol=1e-11, atol=1e-12, method="DOP853")
        return s.y[0, -1] + s.y[3, -1] - target

    rows = []
    for e in eps:
        ends = sorted([mathieu_a(n, 2 * e) / 4, mathieu_b(n, 2 * e) / 4])
        mid = 0.5 * sum(ends)  # inside the tongue: |trace| > 2
        lo = brentq(trace, ends[0] - 0.05, mid, args=(e,), xtol=1e-12)
        hi = brentq(trace, mid, ends[1] + 0.05, args=(e,), xtol=1e-12)
        rows.append((e, lo, hi))
    return np.array(rows)


def locking_figure(out: Path) -> Path:
    """The locking boundary sigma(h) of forced van der Pol, orders 1-2 against shooting."""
    from kbm.expansion.forced import derive_forced

    from numerics.locking.entrainment import predicted_boundary, start_orbit, true_boundary
    from numerics.flow.forced_system import ForcedSystem

    plt = _plt()
    res = derive_forced("vdp-forced", 2)
    hs = np.linspace(0.1, 1.0, 10)
    mu = 0.2
    rows = []
    for h in hs:
        vals = {"mu": mu, "h": h}
        p1 = predicted_boundary(res.slow_flow(vals, order=1), 2.0).sigma
        p2 = predicted_boundary(res.slow_flow(vals, order=2), 2.0).sigma
        s = ForcedSystem("vdp-forced", vals)
        tb = true_boundary(s, start_orbit(s, res.slow_flow(vals, order=2)), 2.0).sigma
        rows.append((h, p1, p2, tb))
    r = np.array(rows)
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    for sign in (1, -1):
        ax.plot(r[:, 0], sign * r[:, 1], "-", color="tab:blue",
                label="KBM order 1" if sign > 0 else None)
        ax.plot(r[:, 0], sign * r[:, 2], "-", color="tab:red",
                label="KBM order 2" if sign > 0 else None)
        ax.plot(r[:, 0], sign * r[:, 3], "ko", ms=4,
                label="shooting + Floquet" if sign > 0 else None)
    ax.set_xlabel("forcing amplitude $h$")
    ax.set_ylabel(r"locking boundary $\sigma$")
    ax.set_title(rf"forced van der Pol, $\mu = {mu}$: locked for $|\sigma| <$ boundary "
                 "(symmetric)", fontsize=9)
    return _save_ax(fig, ax, Path(out) / "forced_vdp_locking.png")


def vdp_response_figure(out: Path) -> Path:
    """The closed curve of forced van der Pol's steady states (h = 0.4, order 2)."""
    vals = {"mu": 0.1, "h": 0.4}
    d = response_diagram("vdp-forced", vals, (-0.5, 0.5), order=2, n_points=200,
                         amplitudes=(1e-3, 3))
    return plot_response(d, Path(out) / "forced_vdp_response.png")


def slider_figure(out: Path) -> Path:
    """The self-excited slider locked to its washboard (the built-in ``slider``: mu = 0.05,
    delta = 1, k = 1, beta = 1; order 2 by the numeric forced backend, against shooting)."""
    vals = {"mu": 0.05, "delta": 1, "k": 1, "beta": 1}
    d = response_diagram("slider", vals, (-0.3, 0.3), order=2, n_points=200,
                         amplitudes=(0.5, 3))
    return plot_response(d, Path(out) / "forced_slider_response.png")


def write_all(out: Path) -> list[Path]:
    """All six figures of the docs page into ``out``."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    return [duffing_figure(out), superharmonic_figure(out), mathieu_figure(out),
            locking_figure(out), vdp_response_figure(out), slider_figure(out)]


if __name__ == "__main__":  # pragma: no cover
    for p in write_all(Path(sys.argv[1] if len(sys.argv) > 1 else "docs/figures")):
        print(p)
