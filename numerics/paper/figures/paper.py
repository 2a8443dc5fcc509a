"""The paper's Figs. 2-6, recomputed (mu = 0.1, Omega = 1, lambda = 1 as the paper states).

Each function writes a PNG (and a PDF) with the parameters in the title and
returns the paths.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from kbm.output.paper import FIG4, FIG5
from numerics.sliding.potential import potential
from numerics.sliding.reference import slide
from numerics.sliding.stickslip import analyze
from numerics._plot import pyplot as _plt, save_png_pdf

__all__ = ["fig2_potential", "fig3_phase_portraits", "fig4_sliding", "fig5_sedf_vs_cdc",
           "fig6_kinetic_friction"]


def fig2_potential(out_dir: Path) -> list[Path]:
    """Fig. 2: U(x, 0) of eq. (4) for lambda = 1 and several Delta."""
    plt = _plt()
    fig, ax = plt.subplots(figsize=(6, 4))
    x = np.linspace(-4, 4, 2001)
    for D in (0.5, 1.5, 3.0):
        ax.plot(x, potential(x, 0.0, Delta=D, lam=1.0, Omega=1.0), label=rf"$\Delta = {D:g}$")
    ax.set_xlabel("$x$")
    ax.set_ylabel("$U(x, 0)$")
    ax.set_title(r"Fig. 2: $U = \Omega^2 x^2/2 - (\lambda/2\pi)\Delta\cos(2\pi x/\lambda)$, "
                 r"$\lambda = 1$, $\Omega = 1$", fontsize=9)
    ax.legend()
    return save_png_pdf(fig, out_dir / "fig2_potential")


def fig3_phase_portraits(out_dir: Path) -> list[Path]:
    """Fig. 3: phase portraits of the undriven SEDF, Delta = 1.5, several beta: the true
    limit cycles by shooting, a transient from x = 0.1, and (dashed) the cycle the energy
    balance predicts: the conservative orbit v = +-sqrt(2 (E* - G(x))) with Gamma(E*) = 0
    (paper eq. 10 as the cycle condition, :func:`numerics.predict`)."""
    from kbm.model.conservative import split_conservative
    from numerics.comparison.predict import predict
    from numerics.cycles.shooting import limit_cycle
    from numerics.sliding.reference import slide as _slide

    plt = _plt()
    fig, ax = plt.subplots(figsize=(6, 5))
    for beta in (0.1, 0.25, 0.5, 1.0):
        params = {"mu": 0.1, "Delta": 1.5, "lam": 1, "beta": beta}
        c = limit_cycle("sedf", params)
        line, = ax.plot(np.append(c.x, c.x[0]), np.append(c.xdot, c.xdot[0]), lw=1.2,
                        label=rf"$\beta = {beta:g}$ (T = {c.period:.3f})")
        tr = _slide("sedf", {"mu": 0.1, "Delta": 1.5, "beta": beta, "v": 0.0}, t_end=60.0,
                    x0=0.1)
        ax.plot(tr.x, tr.xdot, lw=0.4, alpha=0.5, color=line.get_color())
        G = split_conservative("sedf", params).numpy_functions()[2]
        for k, pc in enumerate(q for q in predict("sedf", params).cycles if q.stable):
            s_ = np.linspace(0.0, np.pi, 400)
            xs = 0.5 * (pc.amplitude_max + pc.amplitude_min) \
                - 0.5 * (pc.amplitude_max - pc.amplitude_min) * np.cos(s_)
            vs = np.sqrt(np.maximum(2 * (pc.energy - G(xs)), 0.0))
            ax.plot(np.concatenate([xs, xs[::-1]]), np.concatenate([vs, -vs[::-1]]), "k--",
                    lw=0.7, label="energy balance $\\Gamma(E^*) = 0$" if beta == 1.0 and k == 0
                    else None)
    ax.plot([0.1], [0.0], "k>", ms=6)
    ax.set_xlabel("$x$")
    ax.set_ylabel(r"$\dot x$")
    ax.set_title(r"Fig. 3: undriven SEDF, $\Delta = 1.5$, $\mu = 0.1$, $\Omega = 1$, "
                 r"$\lambda = 1$ (transients from $x = 0.1$; dashed: predicted)", fontsize=9)
    ax.legend(fontsize=8)
    return save_png_pdf(fig, out_dir / "fig3_phase_portraits")


def _samples(t_end: float, per_period: int = 200) -> int:
    """Output samples for a run of ``t_end`` with ``per_period`` per natural period (Omega = 1)."""
    return int(per_period * t_end / (2 * math.pi)) + 1


def fig4_sliding(out_dir: Path) -> list[Path]:
    """Fig. 4: SEDF sliding, Delta = 3, beta = 1, v = 0.1: phase space (A) and series (B)."""
    plt = _plt()
    # 200 samples per natural period: a slip's well oscillations (period ~1.4 at Delta = 3)
    # are resolved, not drawn as straight segments
    r = slide("sedf", FIG4, t_end=300.0, n_samples=_samples(300.0))
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4))
    a1.plot(r.x, r.xdot, lw=0.6)
    a1.set_xlabel("$x$")
    a1.set_ylabel(r"$\dot x$")
    a1.set_title("(A) phase space")
    a2.plot(r.t, r.x, lw=0.8, label="$x$")
    a2.plot(r.t, FIG4["v"] * r.t, "k--", lw=0.6, label="stage $vt$")
    a2.set_xlabel("$t$")
    a2.legend(fontsize=8)
    a2.set_title("(B) time series")
    fig.suptitle(r"Fig. 4: SEDF, $\Delta = 3$, $\beta = 1$, $v = 0.1$, $\mu = 0.1$, "
                 r"$\Omega = 1$, $\lambda = 1$, start at the origin", fontsize=10)
    return save_png_pdf(fig, out_dir / "fig4_sliding")


def fig5_sedf_vs_cdc(out_dir: Path) -> list[Path]:
    """Fig. 5: SEDF vs CDC, Delta = 3, beta = 1, v = 0.01: positions and friction force."""
    plt = _plt()
    cdc_p = {k: v for k, v in FIG5.items() if k != "beta"}
    s = slide("sedf", FIG5, t_end=1500.0)
    c = slide("cdc", cdc_p, t_end=1500.0)
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(9, 6), sharex=True)
    a1.plot(c.t, c.x, lw=0.8, label="CDC (eq. 12)")
    a1.plot(s.t, s.x, lw=0.8, label="SEDF (eq. 3)")
    a1.plot(s.t, FIG5["v"] * s.t, "k--", lw=0.5, label="stage $vt$")
    a1.set_ylabel("$x$")
    a1.legend(fontsize=8)
    a2.plot(c.t, c.force, lw=0.6, label=f"CDC, peak {c.force.max():.3f}")
    a2.plot(s.t, s.force, lw=0.6, label=f"SEDF, peak {s.force.max():.3f}")
    a2.set_ylabel(r"friction force $\Omega^2(vt - x)$")
    a2.set_xlabel("$t$")
    a2.legend(fontsize=8)
    fig.suptitle(r"Fig. 5: SEDF vs CDC, $\Delta = 3$, $\beta = 1$, $v = 0.01$, $\mu = 0.1$, "
                 r"$\Omega = 1$, $\lambda = 1$", fontsize=10)
    return save_png_pdf(fig, out_dir / "fig5_sedf_vs_cdc")


def fig6_kinetic_friction(out_dir: Path) -> list[Path]:
    """Fig. 6: kinetic friction (running mean of the spring force over one potential
    period of the stage) of the SEDF vs time; region I while |x| <= 1/sqrt(beta)."""
    plt = _plt()
    # resolved well oscillations: the running mean of a sparsely sampled, fast force showed
    # false V-shapes
    r = slide("sedf", FIG5, t_end=1500.0, n_samples=_samples(1500.0))
    win = FIG5["lam"] / FIG5["v"]
    n = max(1, int(round(win / (r.t[1] - r.t[0]))))
    kern = np.ones(n) / n
    # full windows only: a zero-padded window would pull the mean down at both ends
    mean = np.convolve(r.force, kern, mode="valid")
    t_mean = r.t[n // 2: n // 2 + mean.size]
    fig, ax = plt.subplots(figsize=(9, 4))
    ax.plot(r.t, r.force, lw=0.4, alpha=0.5, label="spring force")
    # the paper's running mean over one potential period of the stage: where slips are
    # several wells apart its V-shapes are slips entering and leaving the window (a property
    # of the window, not of the friction), so the mean over each whole stick-slip cycle
    # (slip onset to slip onset) is drawn too
    ax.plot(t_mean, mean, lw=1.0, color="C1", alpha=0.8,
            label=rf"running mean over $\lambda/v = {win:g}$ (the paper's)")
    onsets = [s.t_start for s in analyze(r).slips if s.wells != 0]
    for k, (a, b) in enumerate(zip(onsets[:-1], onsets[1:])):
        sel = (r.t >= a) & (r.t < b)
        if sel.sum() > 1:
            ax.plot([a, b], [r.force[sel].mean()] * 2, color="C3", lw=2.2,
                    label="mean over each stick-slip cycle" if k == 0 else None)
    xb = 1 / math.sqrt(FIG5["beta"])
    inside = np.abs(r.x) <= xb
    t_out = r.t[np.argmax(~inside & (r.t > 0))] if np.any(~inside) else r.t[-1]
    ax.axvspan(0, t_out, color="0.9", zorder=0)
    ax.text(0.5 * t_out, ax.get_ylim()[1] * 0.9, "I", ha="center")
    ax.text(0.5 * (t_out + r.t[-1]), ax.get_ylim()[1] * 0.9, "II", ha="center")
    ax.set_xlabel("$t$")
    ax.set_ylabel("friction force")
    ax.set_title(r"Fig. 6: SEDF kinetic friction, $\Delta = 3$, $\beta = 1$, $v = 0.01$; "
                 r"I: $|x| \leq 1/\sqrt{\beta}$ until $t = $" + f"{t_out:.0f}", fontsize=9)
    ax.legend(fontsize=8)
    return save_png_pdf(fig, out_dir / "fig6_kinetic_friction")

