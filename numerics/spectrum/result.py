"""The report of ``kbm spectrum`` for a self-excited oscillator: averaged against simulated.

:func:`line_report` evaluates the averaged line (:mod:`numerics.spectrum.phase_diffusion`),
chooses the run from it (a PSD resolution of a quarter of the averaged half width, lags of
the phase-variance fit from five amplitude relaxation times), simulates the ensemble
(:mod:`numerics.spectrum.simulate`) and returns the JSON-ready report whose keys scripts
depend on:

- ``linewidth: {averaged, simulated, stderr}``: the HWHM of the fundamental (angular);
- ``frequency: {averaged, simulated, stderr}``: the mean angular frequency;
- ``psd: {omega, averaged, simulated, lower, upper}``: near the fundamental;
- ``validity: {z, flagged, threshold, advice}``: the gaps of the two in standard errors
  and the flag ``|z| > 4`` (:func:`line_validity`, as ``kbm noise``);
- ``linewidth`` and ``frequency`` each also hold ``averaged_order`` and the averaged
  number's expected error, ``expected_error`` and ``expected_error_source``
  (:func:`line_errors`; at order 2 the line width's and the line centre's against the
  true cycle's phase response and frequency, :func:`true_cycle`, computed for them when
  ``--floquet`` was not asked for).

:func:`write_figures` draws the PSD (averaged over the simulated band) and the linewidth
against ``D`` (matplotlib imported there only).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from kbm.errors import ParameterError
from kbm.parameters.names import noise_intensity

from .linewidth import fit_lorentzian
from .phase_diffusion import LINEWIDTH_NEED, LineTheory, line_theory
from .simulate import simulate_line
from .._memo import memo
from ..noise.validity import Z_FLAG, averaged_error, gap_z, validity_entry

if TYPE_CHECKING:
    from .floquet import PhaseResponse

__all__ = ["line_report", "line_validity", "line_errors", "next_line", "true_cycle",
           "write_figures", "DEFAULT_TRAJECTORIES"]

#: trajectories of a run without --trajectories
DEFAULT_TRAJECTORIES = 64


def default_duration(th: LineTheory) -> float:
    """A run that resolves the line (resolution HWHM/4) and the phase growth (lags from
    ``5/lambda`` to ``duration/8``)."""
    return float(max(8 * math.pi / th.linewidth, 100.0 / th.relaxation))


def line_report(model, params: dict, D: float, *, order: int = 1,
                trajectories: int = DEFAULT_TRAJECTORIES, duration: float | None = None,
                resolution: float | None = None, seed: int = 0, workers: int | None = None,
                store=None, progress: bool = False, simulate: bool = True,
                floquet: bool = False, shared: int = 1) -> dict:
    """The averaged and simulated linewidth, frequency and PSD of a self-excited model.

    Parameters
    ----------
    model : str or kbm.model.builtins.Oscillator
    params : dict
        ``mu`` and the model's parameters (``D`` apart).
    D : float
        Noise intensity, ``> 0``.
    order : {1, 2}
    trajectories, duration, resolution, seed, workers, store, progress :
        The ensemble (defaults from the averaged line: :func:`default_duration`, a
        resolution of a quarter of the averaged HWHM).
    simulate : bool
        ``False``: the averaged line alone (``simulated`` entries ``None``).
    floquet : bool
        Add ``linewidth.floquet`` and ``frequency.floquet``: the small-noise linewidth
        ``D <Z_v^2>`` and the frequency of the true cycle (:mod:`numerics.spectrum.floquet`).
    shared : int
        Runs of a sweep the step limit is shared by (:mod:`numerics.spectrum._cost`).

    Raises
    ------
    kbm.errors.ParameterError
        ``D <= 0`` and other bad values.
    numerics.errors.NoCycleError
        No limit cycle: no line.
    numerics.spectrum.psd.ResolutionError
        A run too short for the resolution (the message gives the resolution it would give).
    """
    D = noise_intensity(D, LINEWIDTH_NEED)
    for name, val in (("duration", duration), ("resolution", resolution)):
        if val is not None and not (isinstance(val, (int, float)) and math.isfinite(val)
                                    and val > 0):
            raise ParameterError(f"{name} must be a positive number, got {val!r}")
    th = line_theory(model, params, D, order=order)
    nxt = next_line(model, params, D, order)
    G = th.linewidth
    if resolution is None:
        resolution = G / 4
    if duration is None:
        duration = max(default_duration(th), 2 * math.pi / resolution * 1.001)
    window = (max(th.frequency - 25 * G, 0.0), th.frequency + 25 * G)
    rep = {"model": th.name, "kind": "self-excited", "order": order,
           "params": {k: float(v) for k, v in params.items()}, "D": float(D),
           "linewidth": {"averaged": G, "simulated": None, "stderr": None,
                         "linearised": th.linewidth_linear, "fit": None, "fit_stderr": None,
                         "fit_stderr_source": None,
                         "averaged_order": order, "small_noise": th.small_noise},
           "frequency": {"averaged": th.frequency, "simulated": None, "stderr": None,
                         "linearised": th.frequency_linear, "cycle": th.frequency_cycle,
                         "step_bias": None, "averaged_order": order},
           "theory": th.as_dict()}
    pr = true_cycle(model, params, required=floquet) if floquet or order >= 2 else None
    if floquet:
        rep["linewidth"]["floquet"] = pr.linewidth(D)
        rep["frequency"]["floquet"] = pr.frequency
    true_small = None if pr is None else pr.linewidth(D)
    true_freq = None if pr is None else pr.frequency
    if not simulate:
        omega = np.linspace(*window, 401)
        rep["psd"] = {"omega": omega.tolist(), "averaged": th.psd(omega).tolist(),
                      "simulated": None, "lower": None, "upper": None}
        rep["validity"] = line_validity(rep, nxt is not None)
        return line_errors(rep, nxt, true_small, true_freq)
    sim = simulate_line(model, {k: v for k, v in params.items()}, D,
                        trajectories=trajectories, duration=float(duration),
                        burn_in=10.0 / th.relaxation, window=window, resolution=resolution,
                        tau_min=5.0 / th.relaxation, amplitude=th.amplitude, seed=seed,
                        workers=workers, store=store, progress=progress, shared=shared)
    fit = fit_lorentzian(sim.psd, sim.frequency.value, G)
    rep["linewidth"].update(simulated=sim.linewidth.value, stderr=sim.linewidth.stderr,
                            fit=fit.hwhm if fit.success else None,
                            fit_stderr=fit.hwhm_stderr if fit.success else None,
                            fit_stderr_source=fit.stderr_source if fit.success else None)
    rep["frequency"].update(simulated=sim.frequency.value, stderr=sim.frequency.stderr,
                            step_bias=sim.step_bias)
    p = sim.psd
    rep["psd"] = {"omega": p.omega.tolist(), "averaged": th.psd(p.omega).tolist(),
                  "simulated": p.mean.tolist(), "lower": p.lower.tolist(),
                  "upper": p.upper.tolist(), "resolution": p.resolution,
                  "confidence": p.confidence}
    rep["phase_variance"] = {"tau": sim.taus.tolist(), "m2": sim.m2.tolist(),
                             "stderr": sim.m2_stderr.tolist()}
    rep["simulation"] = {"trajectories": sim.trajectories, "duration": sim.duration,
                         "burn_in": sim.burn_in, "dt": sim.dt, "sample": sim.sample,
                         "seed": sim.seed, "resolution": p.resolution}
    rep["validity"] = line_validity(rep, nxt is not None)
    return line_errors(rep, nxt, true_small, true_freq)


#: the names of the compared quantities in the advice
_LABELS = {"linewidth": "half width (HWHM)", "frequency": "line centre Omega"}


def line_validity(rep: dict, raise_order: bool = True) -> dict:
    """The gap ``(averaged - simulated)/stderr`` of the linewidth and of the frequency
    (the simulated frequency less the scheme's ``step_bias``, which the averaging does not
    have) and the flag ``|z| > 4`` (:func:`numerics.noise.validity.gap_z`), with what to do.

    Parameters
    ----------
    rep : dict
        A :func:`line_report` (``order``, ``params``, ``linewidth``, ``frequency``).
    raise_order : bool
        Whether ``--order 2`` applies (:func:`next_line` has a second-order line): advised
        only then, and only at order 1.  ``--floquet`` is advised only when the report has
        no true cycle's line; with it, the advice gives that line's gap to the simulation
        instead (Omega's less the scheme's bias).

    Returns
    -------
    dict
        ``z`` (``linewidth``, ``frequency``; ``None`` without a simulation), ``flagged``,
        ``threshold`` and ``advice`` (``""`` unless flagged).
    """
    compared = _compared(rep)
    z, bad = gap_z(compared)

    def advise() -> str:
        worst = max(bad, key=lambda k: abs(z[k]))
        order = rep["order"]
        floquet = {k: {"averaged": m.get("floquet"), "simulated": m["simulated"],
                       "stderr": m["stderr"]} for k, m in compared.items()}
        zf = gap_z(floquet)[0]
        options = (["--order 2 (second-order averaging)"] if order == 1 and raise_order
                   else [])
        if any(v is None for v in zf.values()):
            options.append("--floquet (the true cycle's line, exact in mu)")
        remedy = "use " + " or ".join(options) if options else ""
        if all(v is not None for v in zf.values()):
            remedy += ("; " if remedy else "") + (
                f"the true cycle's line (adjoint Floquet, exact in mu, first order in D) is "
                f"{zf['linewidth']:+.1f} (HWHM) and {zf['frequency']:+.1f} (Omega) standard "
                "errors from the simulated one")
        bias = " (the scheme's frequency bias removed)" if worst == "frequency" else ""
        mu = rep["params"].get("mu")
        return (f"the averaged {_LABELS[worst]} is {z[worst]:+.1f} standard errors from the "
                f"simulated one{bias} (|z| > {Z_FLAG:g}): the "
                f"{'first' if order == 1 else 'second'}-order averaging is not accurate enough"
                + ("" if mu is None else f" at mu = {mu:g}") + " (mu too large for this "
                f"order, or D too large for the small-noise line); {remedy}; a gap near "
                f"{Z_FLAG:g} may be the statistics: a longer --duration or more "
                "--trajectories shrink the standard error")
    return validity_entry(z, bad, advise)


def _compared(rep: dict) -> dict:
    """The linewidth and frequency entries as the averaging predicts them: the simulated
    frequency less the scheme's ``step_bias`` (:mod:`numerics.spectrum.simulate`), which
    the averaged equations do not have."""
    fr = dict(rep["frequency"])
    if fr["simulated"] is not None:
        fr["simulated"] -= fr.get("step_bias") or 0.0
    return {"linewidth": rep["linewidth"], "frequency": fr}


def next_line(model, params: dict, D: float, order: int) -> LineTheory | None:
    """The averaged line one order up, the reference of the first order's expected error
    (:func:`line_errors`), where the second order applies: at ``order == 1`` for a force
    ``F`` polynomial in ``x`` and ``x'`` (there the symbolic second order takes a tenth of
    a second: van der Pol 0.12 s, Rayleigh 0.08 s of CPU), whose averaged cycle persists at
    second order.  ``None`` otherwise: at order 2 (no third order), and for a
    transcendental ``F`` (the SEDF's ``sin(k x)``: its second-order line ran 310 s of CPU
    and then failed), whose first order states the simulation's bound instead."""
    if order != 1:
        return None
    from kbm.errors import KBMError
    from kbm.parameters.bound import bind
    from kbm.symbols import x, xdot

    try:
        if not bind(model, params).model.F.is_polynomial(x, xdot):
            return None
        return line_theory(model, params, D, order=2)
    except (KBMError, ArithmeticError, ValueError):
        # no second-order cycle, a value the second order lacks, or a second-order cycle
        # the noise escapes from (F = (1 - x^2) x' - x^5, mu = 0.1, D = 0.01: mu^2 A_2's
        # a^7 makes an unstable cycle at a = 2.57 only 3.7 in ln P above a* = 1.74): the
        # first order keeps the next source
        return None


def true_cycle(model, params: dict, *, required: bool = True) -> PhaseResponse | None:
    """The phase response of the true cycle (:func:`numerics.spectrum.floquet.phase_response`,
    exact in ``mu``), computed once per model and parameters (:func:`numerics._memo.memo`: a
    sweep in ``D`` reuses it).

    ``required=False`` (the order-2 line's expected error, :func:`line_errors`, when
    ``--floquet`` was not asked for): ``None`` where no stable cycle is found instead of the
    error."""
    from kbm.errors import KBMError

    try:
        return _true_cycle(model, tuple(sorted(params.items())))
    except (KBMError, ArithmeticError, ValueError):
        if required:
            raise
        return None


@memo(maxsize=8)
def _true_cycle(model, params: tuple) -> PhaseResponse:
    from .floquet import phase_response

    return phase_response(model, dict(params))


def line_errors(rep: dict, nxt: LineTheory | None = None,
                true_small: float | None = None, true_freq: float | None = None) -> dict:
    """``rep`` (a :func:`line_report`) with ``expected_error`` and
    ``expected_error_source`` in ``linewidth`` and ``frequency``: the rule of
    :func:`numerics.noise.validity.averaged_error` (as ``kbm noise``'s moments), with

    - ``"next order"``: at order 1 where :func:`next_line` applies, ``|X_2 - X_1|``;
    - ``"simulation"``: otherwise ``|averaged - simulated| + 2 stderr``, the simulated
      frequency less the scheme's ``step_bias`` (as :func:`line_validity`);
    - ``None`` with ``"none"``: at order 2 without a simulation (``--no-simulation``) nor
      a true cycle.

    How good the "next order" is, stated/true (tests/test_spectrum_expected_error.py):

    - van der Pol's line centre: 1.0035 times the first approximation's error ``mu^2/16``
      (Bogoliubov-Mitropolsky's second approximation, ``1 - mu^2/16``) at mu = 0.05, 0.1,
      0.2 and D/mu = 1e-3 (the 0.35 % is the noise-induced shift), 1.004-1.007 times the
      true cycle's error (:mod:`numerics.spectrum.floquet`, exact in mu) at mu = 0.025-0.2;
    - the cubic stiffness ``F = (1 - x^2) x' - x^3`` (first-order line off by O(mu)), against
      the true cycle at D/mu = 1e-3: line width 0.996, 0.995, 0.988, 0.973 (1.019-1.086
      while the order-2 phase response was right to O(mu) only) and line centre 1.05, 1.10,
      1.18, 1.32 at mu = 0.025, 0.05, 0.1, 0.2; against simulations at mu = 0.1, D = 0.01,
      the line width 0.84 and 1.24 (32 trajectories, seed 1; 64, seed 0);
    - van der Pol's line width has no O(mu) error, and the second order's change is its
      true ``7 mu^2/256`` of ``D``: 1.10, 1.03, 1.04 times the true error at mu = 0.05, 0.1,
      0.2 and D/mu = 1e-4 (1.58 at mu = 0.025, where the widening of O(D/mu) is as large;
      4.9-7.8 times while order 2's ``mu^2`` term was the first-order transform's wrong
      one).

    At order 2 the line width's small-noise part is right through ``mu^2`` (the phase
    response through the third-order transform, :func:`kbm.noise.phase_response.phase_response`:
    van der Pol's ``<Z_v^2> = 1/8 + 7 mu^2/256 + O(mu^4)``, the true cycle's; the cubic
    stiffness' error falls like ``mu^3``), and nothing in the averaging states the size of
    its remainder.  With ``true_small``, the true cycle's small-noise line ``D <Z_v^2>``
    (:func:`true_cycle`), the order-2 width states ``"true cycle"``: ``|averaged| |1 -
    true_small/small_noise|``, the averaged line's error were its phase response the true
    one, unless the simulation's bound is larger; without a simulation plus the whole
    finite-``D/mu`` widening ``|averaged - small_noise|`` (the stationary density's part,
    whose own error only a simulation measures: counted whole, an upper estimate).  So the
    widening is now nearly all of it: vdp mu = 0.1, D = 0.01: 7.7e-05, the small-noise part
    2.2e-08 (1.7e-5 of the line), against a true error of 1.0e-05 +- 3.2e-05 by a
    256-trajectory simulation; before 9.3e-05, of which the first-order transform's 1.3 %
    1.7e-05.  (A transcendental ``F``, whose expansion stops at order 2, keeps the
    first-order transform, right to O(mu).)

    The order-2 line centre likewise: with ``true_freq``, the true cycle's frequency, it
    states ``"true cycle"``: ``|frequency.cycle - true_freq|``, the error of the averaged
    cycle's frequency ``omega0 + B(a*)`` (the small-noise part of ``Omega = omega0 +
    <B>``), unless the simulation's bound is larger; without a simulation plus the whole
    noise-induced shift ``|<B> - B(a*)|`` (its own error only a simulation measures:
    counted whole, an upper estimate; van der Pol: the true cycle's frequency is ``1 - mu^2/16 + 17 mu^4/3072 +
    O(mu^6)``, order 2's ``1 - mu^2/16``, so the cycle's part is ``17 mu^4/3072``, 5.5e-07
    at mu = 0.1, and the shift at D = 0.01 is -2.2e-04, 1.5 standard errors from a
    64-trajectory simulation's; tests/test_spectrum_order2_frequency.py).  Without the
    shift, the stated error was 400 times below the shift at D/mu = 0.1.
    """
    entries = _compared(rep)
    values = {"linewidth": None, "frequency": None} if nxt is None else \
        {"linewidth": nxt.linewidth, "frequency": nxt.frequency}
    second = nxt is None and rep.get("order", 1) >= 2
    for key, entry in entries.items():
        err, source = averaged_error(entry, None, values[key])
        small = entry.get("small_noise")
        # the small-noise part's error; without a simulation (which measures the whole)
        # plus the whole noise-induced part
        cyc, whole = None, source != "simulation"
        if key == "linewidth" and second and true_small is not None and small \
                and math.isfinite(small):
            cyc = (abs(entry["averaged"]) * abs(1.0 - true_small / small)
                   + whole * abs(entry["averaged"] - small))
        elif key == "frequency" and second and true_freq is not None \
                and entry.get("cycle") is not None:
            cyc = (abs(entry["cycle"] - true_freq)
                   + whole * abs(entry["averaged"] - entry["cycle"]))
        if cyc is not None and (err is None or cyc > err):
            err, source = cyc, "true cycle"
        rep[key]["expected_error"], rep[key]["expected_error_source"] = err, source
    return rep


def write_figures(reports: list[dict], out: Path, name: str) -> list[Path]:
    """``spectrum-NAME-psd.png`` (the first report's PSD: averaged over the simulated band)
    and ``spectrum-NAME-linewidth.png`` (HWHM against D: averaged and linearised curves,
    simulated points with two standard errors)."""
    from numerics._plot import pyplot, save

    plt = pyplot()
    rep = reports[0]
    paths = []
    fig, ax = plt.subplots(figsize=(6, 4))
    ps = rep["psd"]
    w = np.asarray(ps["omega"])
    if ps["simulated"] is not None:
        ax.fill_between(w, ps["lower"], ps["upper"], color="C0", alpha=0.3,
                        label=f"simulated, {100 * ps['confidence']:.0f} % band")
        ax.plot(w, ps["simulated"], color="C0", lw=0.8, label="simulated (Welch)")
    ax.plot(w, ps["averaged"], color="C3", lw=1.2, label="averaged (Lorentzian)")
    ax.set_yscale("log")
    ax.set_xlabel(r"$\omega$")
    ax.set_ylabel(r"$S_x(\omega)$")
    ax.set_title(f"{name}: PSD near the fundamental, D = {rep['D']:g}")
    paths.append(save(fig, ax, out / f"spectrum-{name}-psd.png"))

    fig, ax = plt.subplots(figsize=(6, 4))
    Ds = np.array([r["D"] for r in reports])
    th = rep["theory"]
    grid = np.geomspace(Ds.min() / 3, Ds.max() * 3, 50)
    # D_eff is linear in D at fixed a*, lambda, g (the linearised form)
    ax.plot(grid, th["linewidth_linear"] / rep["D"] * grid, "k--", lw=1,
            label="averaged, linearised (Lax)")
    ax.plot(Ds, [r["linewidth"]["averaged"] for r in reports], "C3o-", ms=4,
            label="averaged (stationary density)")
    sim = [(r["D"], r["linewidth"]["simulated"], r["linewidth"]["stderr"]) for r in reports
           if r["linewidth"]["simulated"] is not None]
    if sim:
        d, v, e = map(np.asarray, zip(*sim))
        ax.errorbar(d, v, yerr=2 * e, fmt="C0s", ms=4, capsize=2, label="simulated (2 stderr)")
    ax.set_xscale("log")
    ax.set_yscale("log")
    from matplotlib.ticker import NullFormatter

    ax.xaxis.set_minor_formatter(NullFormatter())
    ax.set_xlabel("D")
    ax.set_ylabel("HWHM (angular)")
    ax.set_title(f"{name}: linewidth against D")
    paths.append(save(fig, ax, out / f"spectrum-{name}-linewidth.png"))
    return paths
