"""The stationary state of a noisy model, averaged against simulated (``kbm noise``)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from kbm.errors import ParameterError
from kbm.models import SLIDERS

from ..escape.report import SLIDER_DEFAULTS
from .averaged import averaged_stationary
from ..noise.ensemble import MIN_TRAJECTORIES, stationary_ensemble
from ..noise.langevin import langevin_system, measured_step, natural_step, split_noise

__all__ = ["noise_report", "default_times", "STEPS_PER_PERIOD", "DEFAULT_BUDGET"]

#: steps per period of the fastest linear oscillation (well bottom or omega0)
STEPS_PER_PERIOD = 50
#: the largest number of integration steps run without --budget
DEFAULT_BUDGET = 2e9
#: histogram bins
BINS = 40


def default_times(system, t_end: float | None, burn_in: float | None,
                  dt: float | None) -> tuple[float, float, float]:
    """``(t_end, burn_in, dt)``: ``dt`` from :func:`numerics.noise.langevin.natural_step` (the
    fastest linear period / 50, smaller when the numerical heating needs it), then
    :func:`numerics.noise.langevin.measured_step` (smaller when a pilot at ``dt`` and
    ``dt/2`` measures a bias of the moments beyond 2e-4), the burn-in
    20 and the run 400 relaxation times ``1/|mu|``, each a whole number of steps."""
    mu = system.bound.mu
    if not mu:
        raise ParameterError("mu = 0: without damping the noise heats the oscillator without "
                             "bound and there is no stationary state; give mu != 0")
    h = (measured_step(system, natural_step(system, per_period=STEPS_PER_PERIOD))[0]
         if dt is None else float(dt))
    if not (math.isfinite(h) and h > 0):
        raise ParameterError(f"--dt must be a positive number, got {dt}")
    run = 400 / abs(mu) if t_end is None else float(t_end)
    burn = 20 / abs(mu) if burn_in is None else float(burn_in)
    for name, val in (("t-end", run), ("burn-in", burn)):
        if not (math.isfinite(val) and val >= 0) or (name == "t-end" and val <= 0):
            raise ParameterError(f"--{name} must be a positive number, got {val}")
    n = max(1, math.ceil(run / h - 1e-9))
    h = run / n
    burn = h * math.ceil(burn / h - 1e-9)
    return run, burn, h


def _pilot_range(system, burn: float, h: float, seed: int) -> tuple[float, float]:
    """The range of ``x`` visited by trajectory 0 over the burn-in and as long again."""
    span = max(2 * burn, 200 * h)
    n = max(1, math.ceil(span / h))
    _, y = system.path((0.0, 0.0), n * h, h, seed=seed)
    x = y[np.isfinite(y[:, 0]), 0]
    lo, hi = float(np.min(x)), float(np.max(x))
    pad = 0.25 * (hi - lo) + 1e-9
    return lo - pad, hi + pad


def noise_report(model, params: dict, *, trajectories: int = 100, t_end=None, burn_in=None,
                 dt=None, seed: int = 0, budget: float = DEFAULT_BUDGET, executor=None,
                 workers: int | None = None, progress: bool = False, store=None,
                 figure: str | Path | None = None) -> dict:
    """The stationary moments and density: averaged prediction against an ensemble.

    Parameters
    ----------
    model : str or kbm.models.Oscillator
    params : dict
        Parameters with ``D``.
    trajectories, t_end, burn_in, dt, seed :
        The ensemble (:func:`numerics.noise.ensemble.stationary_ensemble`); ``None`` times
        take :func:`default_times`.
    budget : float
        Largest number of integration steps; beyond it the simulation is refused with the
        estimate and the averaged answer is given alone (the rare-event guard).
    figure : path, optional
        Where to draw the averaged density over the histogram.

    Returns
    -------
    dict
        ``model, params, D, trajectories, t_end, burn_in, dt, seed, method, moments,
        density, steps, message`` (``moments.a2``/``moments.x2`` with ``averaged``,
        ``simulated``, ``stderr``; ``moments.x2.boltzmann`` for linear damping).
    """
    params, D = split_noise(params)
    name = model if isinstance(model, str) else model.name
    if isinstance(model, str) and model in SLIDERS:
        for k, val in SLIDER_DEFAULTS.items():
            params.setdefault(k, val)
    if not isinstance(trajectories, int) or trajectories < MIN_TRAJECTORIES:
        raise ParameterError(f"--trajectories {trajectories}: at least {MIN_TRAJECTORIES} are "
                             "needed for a meaningful standard error")
    system = langevin_system(model, params, D, "auto")
    run, burn, h = default_times(system, t_end, burn_in, dt)
    avg, why = averaged_stationary(model, params, D, system.omega0)
    steps = trajectories * (run + burn) / h
    out = {
        "model": name, "params": {k: str(v) for k, v in params.items()}, "D": D,
        "trajectories": trajectories, "t_end": run, "burn_in": burn, "dt": h, "seed": seed,
        "method": avg.method if avg else None,
        "moments": {
            "a2": {"averaged": avg.a2 if avg else None, "simulated": None, "stderr": None},
            "x2": {"averaged": avg.x2 if avg else None, "simulated": None, "stderr": None,
                   "boltzmann": avg.boltzmann_x2 if avg else None},
        },
        "density": None, "steps": steps, "message": why, "scheme": system.scheme,
    }
    if steps > budget:
        out["message"] = (f"simulation refused: {trajectories} trajectories x "
                          f"{(run + burn) / h:.3g} steps = {steps:.3g} steps > budget "
                          f"{budget:.3g}; the averaged answer is given alone (raise --budget, "
                          "or fewer --trajectories / a shorter --t-end)")
        return out
    if avg is not None:
        variable, (lo, hi) = avg.variable, avg.support
        if variable == "a":
            lo = 0.0
    else:
        variable = "x"
        lo, hi = _pilot_range(system, burn, h, seed)
    ens = stationary_ensemble(model, params, D, trajectories=trajectories, t_end=run,
                              burn_in=burn, dt=h, seed=seed, variable=variable,
                              bins=(lo, hi, BINS), executor=executor, workers=workers,
                              progress=progress, store=store, scheme=system.scheme)
    out["moments"]["a2"].update(simulated=ens.a2.value, stderr=ens.a2.stderr)
    out["moments"]["x2"].update(simulated=ens.x2.value, stderr=ens.x2.stderr)
    averaged = avg.bins(ens.edges) if avg is not None else None
    out["density"] = {
        "variable": variable,
        "grid": ens.centres.tolist(), "edges": ens.edges.tolist(),
        "averaged": None if averaged is None else [float(v) for v in averaged],
        "simulated": ens.density.tolist(), "stderr": ens.density_stderr.tolist(),
        "outside": ens.outside,
    }
    if figure is not None:
        _figure(figure, out, name, D)
    return out


def _title(rep: dict, name: str, D: float) -> str:
    """The figure's title: the model, every parameter, the noise ``D``, and for the CDC its
    temperature ``kT = D/mu`` (:mod:`numerics.thermal`) on a line of their own."""
    import textwrap

    def value(v: str) -> str:
        try:
            return f"{float(v):.4g}"
        except ValueError:
            return v

    pars = ", ".join(f"{k} = {value(v)}" for k, v in rep["params"].items())
    mu = value(rep["params"].get("mu", ""))
    kT = (f", kT = D/mu = {D / float(mu):.4g}"
          if name == "cdc" and mu.replace(".", "", 1).isdigit() and float(mu) > 0 else "")
    return "\n".join(textwrap.wrap(f"{name}: {pars}", 64) + [f"noise D = {D:g}{kT}"])


def _figure(path, rep: dict, name: str, D: float) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    d = rep["density"]
    c, e = np.asarray(d["grid"]), np.asarray(d["edges"])
    fig, ax = plt.subplots(figsize=(5.2, 3.4), dpi=150)
    ax.bar(c, d["simulated"], width=np.diff(e), color="0.8", edgecolor="0.5", lw=0.4,
           label=f"simulated ({rep['trajectories']} trajectories)")
    ax.errorbar(c, d["simulated"], yerr=2 * np.asarray(d["stderr"]), fmt="none", ecolor="0.3",
                lw=0.6, label="± 2 standard errors")
    if d["averaged"] is not None:
        ax.step(e, list(d["averaged"]) + [d["averaged"][-1]], where="post", color="C3", lw=1.2,
                label=rep["method"].split(" (")[0])
    label = {"a": "amplitude $a$", "x": "$x$", "E": "energy $E$"}[d["variable"]]
    ax.set_xlabel(label)
    ax.set_ylabel("stationary density")
    ax.set_title(_title(rep, name, D), fontsize=8)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
