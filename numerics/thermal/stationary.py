"""The stationary state of a noisy model, averaged against simulated (``kbm noise``)."""

from __future__ import annotations

import dataclasses
import functools
import math
from pathlib import Path

import numpy as np

from kbm.errors import ParameterError
from kbm.model.builtins import with_slider_defaults

from ..escape.noise_params import check_mu
from .averaged import AMPLITUDE, averaged_stationary
from ._beside import Averaged, Stepped, Tabulated, beside, histogram_edges
from .advice import fokker_planck_route, validity
from .averaged_error import state_averaged_errors
from ._kramers_outputs import DRIVEN, DRIVEN_REQUIRED, driven, fokker_planck_moments, fp_advice
from .order2 import order2_bins, second_order
from ..noise.budget import STEP_BUDGET
from ..noise.ensemble import MIN_TRAJECTORIES, stationary_ensemble
from ..noise.langevin import langevin_system, natural_step, split_noise
from ..noise._pilot import measured_step
from ..noise.validity import gap_z, validity_entry

__all__ = ["noise_report", "default_times", "STEPS_PER_PERIOD"]

#: steps per period of the fastest linear oscillation (well bottom or omega0)
STEPS_PER_PERIOD = 50
#: histogram bins
BINS = 40


def default_times(system, t_end: float | None, burn_in: float | None,
                  dt: float | None, measure: bool = True,
                  pilot: dict | None = None) -> tuple[float, float, float]:
    """``(t_end, burn_in, dt)``: ``dt`` from :func:`numerics.noise.langevin.natural_step` (the
    fastest linear period / 50, smaller when the numerical heating needs it), then
    :func:`numerics.noise._pilot.measured_step` (smaller when a pilot at ``dt`` and
    ``dt/2`` measures a bias of the moments beyond 2e-4; skipped with ``measure=False``,
    which gives the largest step the rule can choose), the burn-in
    20 and the run 400 relaxation times ``1/|mu|``, each a whole number of steps.
    ``pilot`` (a dict, ``kbm noise --json``'s ``step_pilot``) receives ``h0``, the rule's
    step or ``--dt``, and the pilot's record (:func:`numerics.noise._pilot.measured_step`;
    ``outcome`` ``"not run"`` and the ``reason`` when it does not run)."""
    mu = system.bound.mu
    if not mu:
        raise ParameterError("mu = 0: without damping the noise heats the oscillator without "
                             "bound and there is no stationary state; give mu != 0")
    h = float(dt) if dt is not None else natural_step(system, per_period=STEPS_PER_PERIOD)
    if dt is None and measure:
        h0 = h
        h, info = measured_step(system, h)
        if pilot is not None:
            pilot.update(h0=h0, **info)
    elif pilot is not None:
        pilot.update(h0=h, outcome="not run", reason="--dt given" if dt else "measure=False")
    if not (math.isfinite(h) and h > 0):
        raise ParameterError(f"--dt must be a positive number, got {h:g}")
    run = 400 / abs(mu) if t_end is None else float(t_end)
    burn = 20 / abs(mu) if burn_in is None else float(burn_in)
    for name, val in (("t-end", run), ("burn-in", burn)):
        if not (math.isfinite(val) and val >= 0) or (name == "t-end" and val <= 0):
            raise ParameterError(f"--{name} must be a positive number, got {val:g}")
    n = max(1, math.ceil(run / h - 1e-9))
    h = run / n
    burn = h * math.ceil(burn / h - 1e-9)
    return run, burn, h


#: the method names of ``kbm noise --method``
METHODS = ("averaging", "fokker-planck")
FOKKER_PLANCK = "Fokker-Planck (stationary Kramers equation, Hermite x Chebyshev spectral)"
#: the same on spectral elements in ``x`` (numerics.fokker_planck._elements_ladder, the
#: multi-well SEDF): ``fokker_planck.chebyshev`` is then the number of their nodes
FOKKER_PLANCK_ELEMENTS = ("Fokker-Planck (stationary Kramers equation, Hermite x spectral "
                          "elements)")


def _pilot_range(system, burn: float, h: float, seed: int) -> tuple[float, float]:
    """The range of ``x`` visited by trajectory 0 over the burn-in and as long again."""
    span = max(2 * burn, 200 * h)
    n = max(1, math.ceil(span / h))
    _, y = system.path((0.0, 0.0), n * h, h, seed=seed)
    x = y[np.isfinite(y[:, 0]), 0]
    lo, hi = float(np.min(x)), float(np.max(x))
    pad = 0.25 * (hi - lo) + 1e-9
    return lo - pad, hi + pad


def averaged_tabulated(model, params: dict, D: float, system) -> Averaged:
    """The averaged stationary state (:func:`.averaged.averaged_stationary`) with its
    density tabulated on the histogram's edges (:class:`._beside.Tabulated`), made beside
    the Fokker-Planck solve (:func:`._beside.beside`).

    Raises
    ------
    numerics.escape.noise_params.NoStationaryState
        The averaging's refusal (before the pilot: vdp at D = 1e300 ran the pilot first,
        whose variance overflowed, then refused).
    """
    avg, why = averaged_stationary(model, params, D, system.omega0)
    if avg is not None:
        edges = histogram_edges(avg, BINS)
        avg = dataclasses.replace(avg, bins=Tabulated(edges, np.asarray(avg.bins(edges))))
    return Averaged(avg, why)


def step_pilot(system, *, trajectories: int, times: tuple, t_end, burn_in, dt,
               budget: float) -> Stepped:
    """The step pilot (:func:`default_times`) when the ensemble of ``trajectories`` at
    ``times`` (the largest step's) is within ``budget`` steps, else its record of why not."""
    run, burn, h = times
    pilot = {"h0": h, "outcome": "not run", "reason": "the simulation is refused (budget)"}
    if trajectories * (run + burn) / h <= budget:
        pilot = {}
        run, burn, h = default_times(system, t_end, burn_in, dt, pilot=pilot)
    return Stepped(pilot, (run, burn, h))


def noise_report(model, params: dict, *, trajectories: int = 100, t_end=None, burn_in=None,
                 dt=None, seed: int = 0, budget: float = STEP_BUDGET, executor=None,
                 workers: int | None = None, progress: bool = False, store=None,
                 figure: str | Path | None = None, method: str = "averaging",
                 fokker_planck: bool = True, order: int = 1, extrapolate: bool = False,
                 fp_budget: float | None = None, energy_density: bool = True) -> dict:
    """The stationary moments and density: averaged prediction against an ensemble.

    Parameters
    ----------
    model : str or kbm.model.builtins.Oscillator
    params : dict
        Parameters with ``D > 0``.
    trajectories, t_end, burn_in, dt, seed :
        The ensemble (:func:`~numerics.noise.ensemble.stationary_ensemble`); ``None``: as
        :func:`default_times`.
    budget : float
        Largest number of integration steps; beyond it the simulation is refused (the
        rare-event guard) with the estimate, and the averaged answer is given alone.
    figure : path, optional
        Where to draw the averaged density over the histogram.
    method : {"averaging", "fokker-planck"}
        ``"fokker-planck"`` requires the stationary Kramers solution (and raises why when
        there is none); the averaged numbers are given too.
    fokker_planck : bool
        Report ``moments.*.fokker_planck`` for a model at rest (``None`` with the reason in
        ``fokker_planck_message`` otherwise).
    fp_budget : float, optional
        The Fokker-Planck solve's cost budget (``kbm noise --fp-budget``; default
        :data:`FP_BUDGET` with ``method="fokker-planck"``, else :data:`FP_DEFAULT_BUDGET`).
    energy_density : bool
        With ``method="fokker-planck"``: ``fokker_planck.energy_density``, ``P(E)`` with its
        stated error (``None`` without it; ``kbm noise`` prints no ``P(E)`` and asks for it
        with ``--json`` or ``--out`` only: its grid step beyond the moments' is 18 s of
        the 50 s CPU of the SEDF at mu = 0.01).
    order : {1, 2}
        The order of the amplitude averaging (:mod:`kbm.noise.stochastic_order2` for 2, where it
        applies; the first order is kept otherwise, with the reason in ``message``).
    extrapolate : bool
        Also report the two-level Richardson value ``E_dt + (4/3)(E_{dt/2} - E_dt)``
        (weak order 4, :func:`numerics.noise.extrapolate.two_level_moments`: BAOAB at
        ``dt`` with Gaussian increments, the same trajectories and times, plus the
        correction from a smaller coupled ensemble at ``dt`` and ``dt/2``) as
        ``moments.*.extrapolated`` with ``extrapolated_stderr``, and how in
        ``extrapolation`` (``None`` without it).

    Returns
    -------
    dict
        ``model, params, D, trajectories, t_end, burn_in, dt, seed, method, moments,
        density, steps, message`` (``moments.a2``/``moments.x2`` with ``averaged``,
        ``simulated``, ``stderr``; ``moments.x2.boltzmann`` for linear damping),
        ``averaged_order`` (the order of ``moments.*.averaged``, ``None`` without it),
        ``moments.*.averaged_error`` and ``averaged_error_source`` (its expected error and
        where it comes from, :mod:`.averaged_error`) and ``validity`` (the gap to the
        simulation, flagged beyond ``|z| > 4``).
    """
    check_mu(dict(params))
    params, D = split_noise(params, "without noise there is no stationary density")
    name = model if isinstance(model, str) else model.name
    params = with_slider_defaults(model, params)
    if not isinstance(trajectories, int) or trajectories < MIN_TRAJECTORIES:
        raise ParameterError(f"--trajectories {trajectories}: at least {MIN_TRAJECTORIES} are "
                             "needed for a meaningful standard error")
    system = langevin_system(model, params, D, "auto")
    # the budget is checked at the largest step the rule can choose before the pilot that
    # measures the step runs (a run refused for its size costs no pilot)
    run, burn, h = default_times(system, t_end, burn_in, dt, measure=False)
    if method not in METHODS:
        raise ParameterError(f"--method {method!r}: choose one of {', '.join(METHODS)}")
    if order not in (1, 2):
        raise ParameterError(f"--order {order}: the stochastic averaging is of order 1 or 2")
    if method == "fokker-planck" and driven(model, params):  # before the averaging beside
        raise ParameterError(f"--method fokker-planck: {DRIVEN}{DRIVEN_REQUIRED}")
    # the averaging and the step pilot beside the Fokker-Planck solve where it is made
    # (._beside); the averaging's refusal first, then the pilot's errors
    from ..fokker_planck._ahead import fp_workers

    solve = fokker_planck or method == "fokker-planck"
    try:
        processes = fp_workers(workers) if solve else 1
    except ParameterError:  # a bad KBM_FP_WORKERS: the solve says so, as before
        processes = 1
    (fp, fp_why), averaged, stepped = beside(
        lambda: (fokker_planck_moments(
            model, params, D, system.omega0, required=method == "fokker-planck",
            budget=fp_budget, energy_density=energy_density, workers=workers)
            if solve else (None, "not requested")),
        functools.partial(averaged_tabulated, model, params, D, system),
        functools.partial(step_pilot, system, trajectories=trajectories, times=(run, burn, h),
                          t_end=t_end, burn_in=burn_in, dt=dt, budget=budget), processes)
    avg, why, pilot, (run, burn, h) = averaged.avg, averaged.why, stepped.pilot, stepped.times
    so, so_values, so_why = second_order(model, params, D, avg) if order == 2 else (None, {}, "")
    if so_why:
        why = f"{why}; {so_why}" if why else so_why
    steps = trajectories * (run + burn) / h
    out = {
        "model": name, "params": {k: str(v) for k, v in params.items()}, "D": D,
        "trajectories": trajectories, "t_end": run, "burn_in": burn, "dt": h, "seed": seed,
        "method": avg.method if avg else None,
        "moments": {
            "a2": {"averaged": avg.a2 if avg else None, "simulated": None, "stderr": None,
                   "fokker_planck": fp["a2"] if fp else None},
            "x2": {"averaged": avg.x2 if avg else None, "simulated": None, "stderr": None,
                   "boltzmann": avg.boltzmann_x2 if avg else None,
                   "fokker_planck": fp["x2"] if fp else None},
        },
        "fokker_planck": None if fp is None else {
            "method": FOKKER_PLANCK_ELEMENTS if fp.get("elements") else FOKKER_PLANCK,
            "hermite": fp["hermite"], "chebyshev": fp["chebyshev"],
            "half_width": fp["half_width"], "sigma": fp["sigma"], "v2": fp["v2"],
            "hermite_change": fp["hermite_change"], "basis": fp["basis"],
            "chebyshev_change": fp["chebyshev_change"],
            "energy_density": fp["energy_density"], "advice": fp_advice(fp, fp["budget"])},
        "fokker_planck_message": fp_why, "density": None, "steps": steps,
        "step_pilot": pilot, "message": why, "scheme": system.scheme,
        "validity": validity_entry({"a2": None, "x2": None}, False),
        "averaged_order": None if avg is None else 1,
        "extrapolation": None,
    }
    if so is not None:
        out["averaged_order"] = 2
        out["method"] = avg.method.replace("first order", "second order")
        out["moments"]["a2"]["averaged"] = so.moment(2, so_values)
        out["moments"]["x2"]["averaged"] = so.x2(so_values)
    nxt = None  # the next order, the expected error's reference without Fokker-Planck
    if fp is None and so is None and avg is not None and avg.method == AMPLITUDE:
        so1, values1, _ = second_order(model, params, D, avg)
        if so1 is not None:
            nxt = {"a2": so1.moment(2, values1), "x2": so1.x2(values1)}
    state_averaged_errors(out, nxt)
    if steps > budget:
        refusal = (f"simulation refused: {trajectories} trajectories x "
                   f"{(run + burn) / h:.3g} steps = {steps:.3g} steps > budget {budget:.3g}; "
                   + ("the averaged answer is given alone" if avg is not None else
                      "without an averaged state there is no answer")
                   + " (raise --budget, or fewer --trajectories / a shorter --t-end)")
        out["message"] = f"{why}; {refusal}" if why else refusal  # why: kept, not replaced
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
    compared = {k: out["moments"][k] for k in ("a2", "x2")}
    raise_order = fp_route = False  # what the advice may name, looked up when flagged
    if gap_z(compared)[1]:
        raise_order = (out["averaged_order"] == 1 and order == 1 and avg.method == AMPLITUDE
                       and (nxt is not None or second_order(model, params, D, avg)[0]
                            is not None))
        fp_route = None if fp is not None else fokker_planck_route(model, params, fp_why)
    change = None if fp is None else fp["hermite_change"]
    out["validity"] = validity(compared, out["averaged_order"] or 1, raise_order,
                               fp_route or None, None if fp is None else {
                                   k: None if change is None else change * abs(fp[k])
                                   for k in ("a2", "x2")})
    state_averaged_errors(out, nxt)
    averaged = (order2_bins(so, so_values, ens.edges) if so is not None
                else avg.bins(ens.edges) if avg is not None else None)
    out["density"] = {
        "variable": variable,
        "grid": ens.centres.tolist(), "edges": ens.edges.tolist(),
        "averaged": None if averaged is None else [float(v) for v in averaged],
        "simulated": ens.density.tolist(), "stderr": ens.density_stderr.tolist(),
        "outside": ens.outside,
    }
    if extrapolate:
        out["extrapolation"] = _extrapolation(system, out, trajectories, run, burn, h, seed)
    if figure is not None:
        _figure(figure, out, name, D)
    return out


def _extrapolation(system, out: dict, trajectories: int, run: float, burn: float, h: float,
                   seed: int) -> dict:
    """The two-level Richardson estimator at ``h`` (BAOAB only,
    :func:`numerics.noise.extrapolate.two_level_moments`): ``moments.*.extrapolated`` and
    the ``extrapolation`` record, with its error estimate."""
    from ..noise.extrapolate import ORDER, two_level_moments

    if system.scheme != "baoab":
        return {"applied": False, "reason": "Richardson extrapolation to order 4 needs BAOAB's "
                "even expansion; this model runs Kloeden-Platen (damping not affine in x')"}
    mom, sizes = two_level_moments(system, h, trajectories=trajectories, t_end=run,
                                   burn_in=burn, seed=seed)
    for k, m in mom.items():
        out["moments"][k].update(extrapolated=m.value, extrapolated_stderr=m.stderr)
    return {
        "applied": True,
        "method": "two-level Richardson",
        "description": "E_dt + (4/3)(E_{dt/2} - E_dt): E_dt from BAOAB at dt (Gaussian "
                       "increments), the correction from a smaller coupled ensemble at dt and "
                       "dt/2 on one Brownian path and its antithetic twin (the two fine "
                       "increments of each coarse step swapped), its size by Giles' allocation "
                       "from the measured variance ratio; the same times as the main run",
        "order": ORDER, "dt": h, "steps": sizes["steps"], "coupling": sizes["coupling"],
        "trajectories": {"coarse": sizes["coarse"], "correction": sizes["correction"],
                         "pilot": sizes["pilot"]},
        "coarse": {k: m.coarse for k, m in mom.items()},
        "coarse_stderr": {k: m.coarse_stderr for k, m in mom.items()},
        "correction": {k: m.correction for k, m in mom.items()},
        "correction_stderr": {k: m.correction_stderr for k, m in mom.items()},
        "variance_ratio": {k: m.variance_ratio for k, m in mom.items()},
        "error_estimate": {k: m.stderr for k, m in mom.items()},
        "error_note": "error_estimate is the standard error of both levels combined "
                      "(independent streams); the remaining bias is O(dt^4) (7.5e-5 relative "
                      "at dt = 0.3 on the quartic benchmark, by the transfer operator of "
                      "numerics.noise.invariant)",
    }


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
