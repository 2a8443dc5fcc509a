"""The escape rate from the well at the origin as one JSON-ready report (``kbm escape``)."""

from __future__ import annotations

import math

from kbm.errors import ParameterError
from kbm.model.builtins import with_slider_defaults
from kbm.parameters.bound import bind
from kbm.parameters.names import noise_intensity

from ..noise.budget import STEP_BUDGET
from .envelope import origin_well_envelope
from .noise_params import check_mu
from .rate import averaged_escape

__all__ = ["escape_report", "MIN_TRAJECTORIES"]

#: the paper's values, used for a slider when not given (as in ``kbm friction``)

#: fewer trajectories give no meaningful standard error
MIN_TRAJECTORIES = 20
#: below this barrier in units of kT the rate formulas do not apply
MIN_BARRIER_OVER_KT = 2.0
#: below this barrier in units of kT (``D/mu``) there is no escape rate to compute: the
#: barrier is far under the thermal energy, nothing holds the slider in the well, and the
#: averaged envelope (cut ``40 D/mu`` above the well) would span hundreds of barriers
#: (``kbm escape cdc -p mu=0.1 -p Delta=3 -p D=100``, ``E_b/kT = 1e-3``, ran for minutes)
NO_RATE_BARRIER_OVER_KT = 0.1
#: above this barrier in units of kT the rate exp(-E_b/kT) is below 1e-304 and the averaged
#: MFPT overflows double precision (``kbm escape cdc -p mu=0.02 -p Delta=3 -p D=1e-9``
#: printed two RuntimeWarnings and "the mean first-passage time came out as nan ... check
#: mu > 0 and D > 0"; E_b/kT = 701 still gives 5e-304)
MAX_BARRIER_OVER_KT = 700.0


def escape_report(model: str, params: dict, *, trajectories: int = 200, t_end=None, dt=None,
                  seed: int = 0, budget: float = STEP_BUDGET, simulate: bool = True,
                  method: str = "averaging", fp_budget: float | None = None) -> dict:
    """Averaged, Kramers and (within ``budget``) simulated escape rates.

    Parameters
    ----------
    model : str
    params : dict
        Parameters with ``D`` (the noise intensity) and ``mu``.
    trajectories, t_end, dt, seed :
        The simulation (see :func:`numerics.escape.simulate.simulated_escape`).
    budget : float
        Largest expected number of integration steps; beyond it the simulation is
        refused with the estimate (the rare-event guard).
    simulate : bool
        ``False``: the averaged rates only.
    method : {"averaging", "fokker-planck"}
        ``"fokker-planck"`` adds ``rate_fokker_planck``: the slowest decay rate of the
        Kramers equation with a sink at the next wells' bottoms (the transition rate;
        :mod:`numerics.fokker_planck.escape`), with ``fokker_planck.sink_error``,
        ``truncation_error``, ``chebyshev_error``, ``scale_error`` (nonlinear damping: the
        change under another velocity scale, part of ``truncation_error``; else ``None``)
        ``wells`` (where the sink sits) and ``sink_ladder`` (the rates of the rising, then
        the falling ladder of sharpening sinks, whose top rungs bracket the rate, where the
        first two sinks disagree by more than 1e-7, :mod:`numerics.fokker_planck._sink`;
        else empty);
        with the simulation, also its like quantity ``rate_simulated_wells`` and
        ``stderr_wells``: first passages to the next wells' bottoms from the well's
        Boltzmann density (:mod:`numerics.escape.transitions`; ``simulated_wells`` holds
        the counts, ``t_end`` (default five FP lifetimes), the start and the stream), and
        ``z_fokker_planck``, the FP rate minus it over the combined standard error.
        ``rate_simulated`` stays the first passage to the saddles from the bottom (the
        averaged MFPT's quantity); it exceeds the transition rate as the friction grows
        (1.05 times at mu = 1, 1.35 at mu = 5 in docs/noise.rst's case), towards twice it
        when the friction is much larger than the barrier frequency (a particle at the
        saddle then goes on or falls back with equal chance).
    fp_budget : float, optional
        The Fokker-Planck solve's ``max_cost`` (``kbm escape --fp-budget``; default that of
        :func:`numerics.fokker_planck.kramers_escape`).

    Returns
    -------
    dict
        Keys ``rate_averaged``, ``rate_simulated``, ``stderr``, ``barrier`` and the
        details (``rate_kramers``, ``rate_melnikov``, ``rate_turnover``, ``omega_b``,
        ``kT``, ``barrier_over_kT``, ``mfpt_averaged``, ``trajectories``, ``escaped``,
        ``t_end``, ``dt``, ``seed``, ``estimated_steps`` (of both runs with
        ``fokker-planck``), ``message``).  ``rate_melnikov`` is Mel'nikov-Meshkov's
        ``A(delta) (omega_0/2 pi) exp(-E_b/kT)`` for a well with one exit and no
        spatial-diffusion factor (kept as it was); ``rate_turnover`` is the rate of the
        well's two equal exits at any friction, ``(lambda_+/omega_b) 2 A(delta/2)
        (omega_0/2 pi) exp(-E_b/kT)`` (:mod:`numerics.escape.turnover`), the formula to
        compare with ``rate_fokker_planck``; ``omega_b`` is the saddles' barrier
        frequency (``None`` with ``rate_turnover`` where the two saddles differ).
        ``validity`` (:func:`_validity`) states the averaged rate's order and expected
        error and its gap to ``rate_simulated``, flagged beyond four standard errors (the
        advice then among ``warnings``).
    """
    params = dict(params)
    if method not in ("averaging", "fokker-planck"):
        raise ParameterError(f"--method {method!r}: choose averaging or fokker-planck")
    check_mu(params)
    if "D" not in params:
        raise ParameterError("give the noise intensity: -p D=VALUE (x'' + ... = sqrt(2 D) xi)")
    D = noise_intensity(params.pop("D"), "without noise nothing escapes the well")
    if not isinstance(trajectories, int) or trajectories < MIN_TRAJECTORIES:
        raise ParameterError(f"--trajectories {trajectories}: at least {MIN_TRAJECTORIES} are "
                             "needed for a meaningful standard error")
    for name, val in (("t-end", t_end), ("dt", dt)):
        if val is not None and not (math.isfinite(val) and val > 0):
            raise ParameterError(f"--{name} must be a positive number, got {val:g}")
    params = with_slider_defaults(model, params)
    # the missing values named as the user gives them (Delta, not the scaled delta)
    bind(model, {k: val for k, val in params.items() if k != "v"}).require(
        what="the escape rate")
    _check_barrier(model, params, D)
    env = origin_well_envelope(model, params, D)  # the MFPT needs the well alone
    esc = averaged_escape(env)
    if dt is None:
        from ..noise.langevin import langevin_system, natural_step

        split = env.split
        system = langevin_system(split.model, {**{k: float(v) for k, v in split.params.items()},
                                               "mu": float(split.mu)}, D)
        h = natural_step(system, per_period=40)
    else:
        h = float(dt)
    run = 5 * esc.mfpt if t_end is None else float(t_end)
    # each trajectory runs until it escapes or t_end: expected time <= min(MFPT, t_end)
    steps = trajectories * min(esc.mfpt, run) / h
    out = {
        "model": model, "params": {k: str(v) for k, v in params.items()}, "D": D,
        "barrier": esc.barrier, "saddles": list(esc.saddles),
        "kT": esc.kT, "barrier_over_kT": None if esc.kT is None else esc.barrier / esc.kT,
        "rate_averaged": esc.rate_averaged, "mfpt_averaged": esc.mfpt,
        "rate_kramers": esc.rate_kramers, "rate_melnikov": esc.rate_melnikov,
        "rate_turnover": esc.rate_turnover, "omega_b": esc.omega_b,
        "action_at_barrier": esc.action, "omega0": esc.omega0,
        "rate_simulated": None, "stderr": None, "trajectories": trajectories,
        "escaped": None, "censored": None, "t_end": run, "dt": h, "seed": seed,
        "estimated_steps": steps, "message": "", "warnings": [],
    }
    if method == "fokker-planck":
        from ..fokker_planck import kramers_escape

        fp = kramers_escape(model, params, D, esc.saddles,
                            **({} if fp_budget is None else {"max_cost": fp_budget}))
        out["rate_fokker_planck"] = fp.rate
        out["fokker_planck"] = {"sink_error": fp.sink_error,
                                "truncation_error": fp.truncation_error,
                                "chebyshev_error": fp.chebyshev_error,
                                "scale_error": (None if math.isnan(fp.scale_error)
                                                else fp.scale_error),
                                "wells": list(fp.wells),
                                "hermite": fp.hermite, "chebyshev": fp.chebyshev,
                                "sink_ladder": list(fp.sink_ladder)}
        if fp.budget_note:  # a sink ladder stopped by --fp-budget
            out["warnings"].append(fp.budget_note)
    if method == "fokker-planck":  # the simulated transitions to the next wells too
        steps += trajectories * min(1.0 / fp.rate, _wells_end(fp, t_end)) / h
        out["estimated_steps"] = steps
    ratio = out["barrier_over_kT"]
    if ratio is not None and ratio < MIN_BARRIER_OVER_KT:
        out["warnings"].append(
            f"E_b/kT = {ratio:.3g} < {MIN_BARRIER_OVER_KT:g}: the barrier is not high against "
            "the noise, so the escape rate formulas (averaged MFPT, Kramers, Mel'nikov-"
            "Meshkov, turnover) do not apply (they assume E_b >> kT); lower D or use the "
            "simulated first-passage rate" + (" (drop --no-simulation)" if not simulate
                                              else " (raise --budget)" if steps > budget
                                              else ""))
    if not simulate:
        out["message"] = "simulation not requested (--no-simulation)"
        return _checked(out, params, method)
    if steps > budget:
        out["message"] = (f"simulation refused: about {steps:.3g} steps expected "
                          f"({trajectories} trajectories x MFPT {esc.mfpt:.3g} / dt {h:.3g}"
                          + (f", plus {trajectories} to the next wells x 1/rate_FP "
                             f"{1.0 / fp.rate:.3g} / dt" if method == "fokker-planck" else "")
                          + ") "
                          f"> budget {budget:.3g}; the averaged rate is the answer "
                          "(raise --budget to simulate anyway)")
        return _checked(out, params, method)
    from ..errors import NumericsError
    from .simulate import simulated_escape

    try:
        sim = simulated_escape(env.split, D, esc.saddles, trajectories=trajectories,
                               t_end=run, dt=h, seed=seed)
    except NumericsError as exc:
        out["message"] = f"simulation: {exc}"
        return _checked(out, params, method)
    out.update(rate_simulated=sim.rate, stderr=sim.stderr, escaped=sim.escaped,
               censored=sim.censored)
    if method == "fokker-planck":
        _simulate_wells(out, env.split, D, esc, fp, trajectories=trajectories,
                        t_end=_wells_end(fp, t_end), dt=h, seed=seed)
    return _checked(out, params, method)


def _checked(out: dict, params: dict, method: str) -> dict:
    """``out`` with its ``validity`` (:func:`_validity`), the flag's advice among the
    warnings."""
    out["validity"] = _validity(out, float(params["mu"]), method == "fokker-planck")
    if out["validity"]["flagged"]:
        out["warnings"].append(out["validity"]["advice"])
    return out


def _validity(out: dict, mu: float, fokker_planck: bool) -> dict:
    """The averaged (energy-diffusion) rate against the simulated first passages to the
    saddles, the same quantity: ``{"z", "flagged", "threshold", "advice", "averaged_order",
    "expected_error", "expected_error_source"}`` (issue 36: each averaged number states its
    order and expected error, :func:`numerics.noise.validity.averaged_error`'s rule; a gap
    beyond four standard errors is flagged, :func:`numerics.noise.validity.gap_z`).

    The averaged rate is the low-friction limit (first order in mu): it needs the energy
    lost per cycle at the barrier small against kT, ``delta = mu I(E_b)/kT << 1`` (CDC,
    Delta = 3, kT = 0.35: at mu = 0.2, delta = 1.1, the averaged rate 0.0235 against the
    simulated 0.0155 +- 0.0011, +7.3 standard errors; at mu = 0.02, delta = 0.11, +2.6).
    The Fokker-Planck rate is not its reference: it is the transition rate to the next
    wells, up to twice smaller at high friction."""
    from ..noise.validity import Z_FLAG, averaged_error, gap_z, validity_entry

    rate = {"averaged": out["rate_averaged"], "simulated": out["rate_simulated"],
            "stderr": out["stderr"]}
    z, bad = gap_z({"rate": rate})
    error, source = averaged_error(rate)

    def advise() -> str:
        kT, action = out["kT"], out["action_at_barrier"]
        delta = (f" (delta = mu I(E_b)/kT = {mu * action / kT:.3g})"
                 if kT is not None and action is not None else "")
        return (f"the averaged energy-diffusion rate is {z['rate']:+.1f} standard errors from "
                f"the simulated one (|z| > {Z_FLAG:g}): it is the low-friction limit and "
                f"needs the energy lost per cycle at the barrier small against kT{delta}; "
                f"at mu = {mu:g} take the simulated rate, "
                + ("or the Fokker-Planck rate (the transitions to the next wells)"
                   if fokker_planck else "or --method fokker-planck (the Kramers equation "
                   "at any friction; the transitions to the next wells)"))
    return validity_entry(z["rate"], bad, advise, averaged_order=1, expected_error=error,
                          expected_error_source=source)


def _wells_end(fp, t_end) -> float:
    """The transitions' longest run: ``t_end``, or five FP lifetimes ``5/rate``."""
    return 5.0 / fp.rate if t_end is None else float(t_end)


def _simulate_wells(out: dict, split, D: float, esc, fp, **run) -> None:
    """Add the simulated transitions to the next wells (the FP rate's like quantity) and
    their ``z`` to ``out``."""
    from ..errors import NumericsError
    from .transitions import WELLS_STREAM, simulated_transitions

    try:
        sim = simulated_transitions(split, D, esc.saddles, kT=esc.kT, wells=fp.wells, **run)
    except NumericsError as exc:
        out["message"] = f"simulation to the next wells: {exc}"
        return
    fp_err = math.hypot(fp.sink_error, fp.truncation_error)
    out.update(rate_simulated_wells=sim.rate, stderr_wells=sim.stderr,
               z_fokker_planck=(fp.rate - sim.rate) / math.hypot(sim.stderr, fp_err))
    out["simulated_wells"] = {"escaped": sim.escaped, "censored": sim.censored,
                              "t_end": sim.t_end, "start": sim.start,
                              "settle": sim.settle, "settled": sim.settled,
                              "wells": [float(w) for w in fp.wells],
                              "stream": list(WELLS_STREAM)}


def _check_barrier(model: str, params: dict, D: float) -> None:
    """Refuse, before the envelope is built, a barrier far below the noise's energy
    ``D/mu`` (``kT`` for linear damping): ``E_b/kT < NO_RATE_BARRIER_OVER_KT``.

    Only the phase portrait is computed here; a model without a barrier at the origin is
    left to :func:`numerics.escape.rate.central_well`, which says why.
    """
    import sympy as sp

    from kbm.model.conservative import split_conservative
    from kbm.symbols import xdot

    from ..energy.portrait import phase_portrait

    split = split_conservative(model, {k: v for k, v in params.items() if k != "D"})
    if split.conservative or not float(split.mu) > 0:
        return
    wells = [a for a in phase_portrait(split).annuli
             if a.bounded and len(a.wells) == 1 and abs(a.wells[0]) < 1e-9]
    if not wells:
        return
    mu = float(split.mu)
    barrier = wells[0].energy_max - wells[0].energy_min
    scale = D / mu
    what = ("kT = D/mu" if sp.simplify(split.h + xdot) == 0
            else "D/mu (the noise's energy scale; the damping is not linear)")
    if barrier / scale > MAX_BARRIER_OVER_KT:
        raise ParameterError(
            f"E_b/kT = {barrier / scale:.3g} > {MAX_BARRIER_OVER_KT:g} (barrier E_b - E_0 = "
            f"{barrier:.4g}, {what} = {scale:.4g}): the escape rate ~ exp(-E_b/kT) is below "
            "1e-304, beyond double precision and any simulation; raise D to "
            f"{barrier * mu / MAX_BARRIER_OVER_KT:.3g} or more")
    if barrier / scale >= NO_RATE_BARRIER_OVER_KT:
        return
    raise ParameterError(
        f"E_b/kT = {barrier / scale:.3g} < {NO_RATE_BARRIER_OVER_KT:g} (barrier E_b - E_0 = "
        f"{barrier:.4g}, {what} = {scale:.4g}): the barrier is far below the thermal energy, "
        "the well at the origin does not hold the slider and there is no escape rate; "
        f"lower D to {barrier * mu / MIN_BARRIER_OVER_KT:.3g} or "
        f"less (E_b/kT >= {MIN_BARRIER_OVER_KT:g}, where the rate formulas apply)")
