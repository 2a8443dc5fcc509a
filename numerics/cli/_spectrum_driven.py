"""``kbm spectrum`` for forced and coupled models: response spectra and phase-slip rates.

:func:`run_driven` (a forced model: the noise spectra about every stable state at each
detuning, :mod:`numerics.spectrum.driven_sim`) and :func:`run_slips` (an autonomous coupled
pair: the slip rate, :mod:`numerics.spectrum.slips`) take the ``argparse`` namespace of
``kbm spectrum`` (``model``, ``param``, ``vary``, ``json``, ``out``, ``trajectories``,
``duration``, ``seed``, ``workers``, ``store``, ``resume``, ``order``; a missing attribute
is its default).  The parameters go through the one layer (:mod:`numerics.cli.params.values`):
unknown names refused, ``D`` or ``T = D/mu``.
"""

from __future__ import annotations

from pathlib import Path

from kbm.errors import ParameterError

__all__ = ["run_driven", "run_slips", "DEFAULT_TRAJECTORIES", "DEFAULT_DETUNINGS"]

#: trajectories of a run without --trajectories
DEFAULT_TRAJECTORIES = 32
#: detunings of a range ``--vary sigma=A:B`` without ``:N``
DEFAULT_DETUNINGS = 3
#: detunings of one run at most: each is a whole ensemble, and the stable states of every
#: detuning are found before the first is simulated (``--vary sigma=0.8:1.1:5000`` ran on
#: without a word)
MAX_DETUNINGS = 200


def _opt(args, name, default=None):
    value = getattr(args, name, default)
    return default if value is None else value


def _bind(args, kind: str):
    """``(model name, params without D and the detuning, D, detuning name, detunings)``."""
    from kbm.parameters.names import lookup
    from kbm.parameters.values import parameter_value
    from numerics.cli.params.values import check, given, noise_params, parse_vary, without_noise
    from numerics.noise.coupled import NOISE_NEED

    if _opt(args, "rhs") or not _opt(args, "model"):
        names = "duffing-forced, parametric, duffing-1-3, ..." if kind == "forced" else \
            "coupled-vdp"
        raise ParameterError(f"the {'response spectra' if kind == 'forced' else 'slip rate'} "
                             f"take a built-in model ({names}); a custom --rhs is not "
                             "supported here")
    lookup(args.model, (kind,))
    params = given(_opt(args, "param", []))
    vary = _opt(args, "vary", [])
    vary = [vary] if isinstance(vary, str) else list(vary)
    if len(vary) > 1:
        raise ParameterError("--vary takes one detuning range here (e.g. --vary sigma=0.5:1.5)")
    if kind == "forced":
        from kbm.model.coupled_builtins import get_coupled_model

        name = get_coupled_model(args.model).nu_detuning or "sigma"
    else:
        name = "sigma"
    v = parse_vary(vary[0]) if vary else None
    if v is not None and v.name != name:
        raise ParameterError(f"--vary {v.name}: vary the detuning {name} (--vary "
                             f"{name}=FROM:TO)")
    check(args.model, params, [v.name] if v else [], noise=True,
          extra=(name,) if kind == "forced" else ())
    params, _ = noise_params(params)
    params, D = without_noise(params, NOISE_NEED)
    if v is not None:
        values = [float(x) for x in v.values(DEFAULT_DETUNINGS)]
        if len(values) > MAX_DETUNINGS:
            raise ParameterError(f"--vary {v.text}: {len(values)} detunings, each a whole "
                                 f"ensemble of trajectories; the limit is {MAX_DETUNINGS}: give "
                                 "fewer values")
    elif name in params:
        values = [float(params[name])]
    else:
        raise ParameterError(f"give the detuning: -p {name}=VALUE or --vary {name}=FROM:TO")
    params.pop(name, None)
    if "mu" not in params:
        raise ParameterError("give the small parameter: -p mu=VALUE")
    return args.model, {k: float(parameter_value(k, x)) for k, x in params.items()}, D, name, \
        values


def run_driven(args) -> int:
    """``kbm spectrum FORCED-MODEL -p ... -p D=... [--vary sigma=A:B]``: the averaged,
    Floquet and simulated noise spectra about every stable state at each detuning."""
    from numerics.cli.params.options import stored
    from numerics.spectrum.driven_sim import response_spectra

    model, params, D, name, detunings = _bind(args, "forced")
    order = _opt(args, "order", 1)
    if order != 1:
        raise ParameterError(f"--order {order}: the response spectra are first order (the "
                             "averaged route) and exact (Floquet); give --order 1")
    with stored(args) as store:
        specs = response_spectra(model, params, D, detunings, simulate=True,
                                 trajectories=int(_opt(args, "trajectories",
                                                       DEFAULT_TRAJECTORIES)),
                                 duration=_opt(args, "duration"), seed=int(_opt(args, "seed", 0)),
                                 workers=_opt(args, "workers"), store=store,
                                 progress=not _opt(args, "json", False),
                                 resolution=_opt(args, "resolution"))
    from numerics.noise.validity import averaged_error, joined_validity

    first = specs[0]
    # the response frequency ratio * nu of the first stable state (no simulated value
    # and no second order of the response spectra: the rule's "none")
    frequency = {"averaged": first.Omega, "simulated": None, "stderr": None,
                 "averaged_order": 1}
    frequency["expected_error"], frequency["expected_error_source"] = averaged_error(frequency)
    rep = {"model": model, "params": params, "D": D, "detuning": name,
           "detunings": detunings, "kind": "forced",
           "response_spectra": [s.to_json() for s in specs],
           "linewidth": None, "frequency": frequency,
           "psd": {"omega": list(map(float, first.omega)),
                   "averaged": list(map(float, first.averaged)),
                   "floquet": None if first.floquet is None else list(map(float, first.floquet)),
                   "simulated": list(map(float, first.simulated)),
                   "lower": list(map(float, first.lower)),
                   "upper": list(map(float, first.upper))}}
    checks = [r["validity"] for r in rep["response_spectra"]]  # (ResponseSpectrum.validity)
    flagged = [v for v in checks if v is not None and v["flagged"]]
    if all(v is not None for v in checks):  # (specs[0] exists: checks is not empty)
        rep["validity"] = joined_validity(checks, [v["z_rms"] for v in checks], key="z_rms")
    if _opt(args, "out"):
        rep["figures"] = [str(p) for p in _figures_driven(specs, model, Path(args.out))]
    lines = _lines_driven(rep, specs) + [f"  WARNING: {v['advice']}" for v in flagged]
    return _emit(args, rep, lines)


def _lines_driven(rep, specs) -> list[str]:
    import numpy as np

    out = [f"noise spectra of {rep['model']} about its stable steady states, D = {rep['D']:g} "
           f"(one-sided PSD of x - x_p, angular frequency)"]
    for s in specs:
        lam = ", ".join(f"{e.real:.4g}{e.imag:+.4g}i" for e in s.state.eigenvalues)
        mult = "--" if s.orbit is None else ", ".join(f"{abs(m):.4f}" for m in
                                                     s.orbit.multipliers)
        out.append(f"  {rep['detuning']} = {s.detuning:g}: amplitude "
                   f"{s.state.amplitudes()[0]:.5g}, response frequency {s.Omega:.6g}; "
                   f"averaged eigenvalues {lam}; |Floquet multipliers| {mult}")
        z = (s.floquet - s.simulated) / np.where(s.stderr > 0, s.stderr, np.inf)
        za = (s.averaged - s.simulated) / np.where(s.stderr > 0, s.stderr, np.inf)
        k = int(np.argmax(s.simulated))
        out.append(f"    peak: simulated {s.simulated[k]:.4g} +- {s.stderr[k]:.2g} at "
                   f"{s.omega[k]:.5g}; Floquet {s.floquet[k]:.4g}, averaged "
                   f"{s.averaged[k]:.4g}")
        out.append(f"    over {len(s.omega)} bins: (Floquet - simulated)/stderr mean "
                   f"{np.mean(z):+.2f}, rms {np.sqrt(np.mean(z**2)):.2f}; (averaged - "
                   f"simulated)/stderr rms {np.sqrt(np.mean(za**2)):.2f}")
        cs = s.extra["coherent_shift"]
        out.append(f"    noise-induced shift of the response at {s.Omega:.5g} (removed before "
                   f"the PSD): amplitude {cs['amplitude']:.3g} +- {cs['stderr']:.2g}")
        out.append(f"    {s.extra['trajectories']} trajectories x {s.extra['duration']:.6g} "
                   f"after {s.extra['burn_in']:.4g}, dt {s.extra['dt']:.4g}, resolution "
                   f"{s.extra['resolution']:.3g}, seed {s.extra['seed']}")
    return out


def _figures_driven(specs, model, out: Path) -> list[Path]:
    from numerics._plot import pyplot as _plt, save as _save

    plt = _plt()
    paths = []
    for j, s in enumerate(specs):
        fig, ax = plt.subplots(figsize=(6.4, 4.2))
        ax.fill_between(s.omega, s.lower, s.upper, color="0.8", label="simulated, 95 % band")
        ax.plot(s.omega, s.simulated, "k.", ms=3, label="simulated")
        if s.floquet is not None:
            ax.plot(s.omega, s.floquet, "C0-", label="Floquet (exact linearisation)")
        ax.plot(s.omega, s.averaged, "C1--", label="averaged (first order)")
        ax.set_yscale("log")
        ax.set_xlabel("angular frequency omega")
        ax.set_ylabel("one-sided PSD of x - x_p")
        ax.set_title(f"{model}: noise spectrum at detuning {s.detuning:g}, amplitude "
                     f"{s.state.amplitudes()[0]:.3g}")
        paths.append(_save(fig, ax, out / f"spectrum-{model}-{j}.png"))
    return paths


#: the keys of ``slip_rate`` and ``frequency_difference`` in the report's top level
_SLIP_KEYS = ("averaged", "simulated", "stderr", "averaged_order", "expected_error",
              "expected_error_source")


def run_slips(args) -> int:
    """``kbm spectrum coupled-vdp -p ... -p D=... [--vary sigma=A:B]``: the phase-slip rate
    and the effective frequency difference, Stratonovich's formula against counts."""
    from numerics.cli.params.options import stored
    from numerics._show import cell
    from numerics.noise.validity import joined_validity
    from numerics.spectrum.slips import slip_report

    model, params, D, name, detunings = _bind(args, "coupled")
    with stored(args) as store:
        rows = slip_report(model, params, D, detunings, order=int(_opt(args, "order", 1)),
                           detuning=name, duration=_opt(args, "duration"),
                           trajectories=int(_opt(args, "trajectories", DEFAULT_TRAJECTORIES)),
                           seed=int(_opt(args, "seed", 0)), workers=_opt(args, "workers"),
                           store=store, progress=not _opt(args, "json", False))
    one = len(rows) == 1

    def col(key, sub):
        vals = [r[key][sub] for r in rows]
        return vals[0] if one else vals

    rep = {"model": model, "params": params, "D": D, "detuning": name,
           "detunings": detunings, "kind": "coupled", "slips": rows,
           "slip_rate": {k: col("slip_rate", k) for k in _SLIP_KEYS},
           "frequency_difference": {k: col("frequency_difference", k) for k in _SLIP_KEYS},
           "linewidth": None, "frequency": None, "psd": None}
    flagged = [r for r in rows if r.get("validity", {}).get("flagged")]
    if all("validity" in r for r in rows):  # (each detuning's in "slips"; here the first
        # flagged one's advice and every detuning's gap, as the other columns)
        rep["validity"] = joined_validity([r["validity"] for r in rows], col("validity", "z"))
    if _opt(args, "out"):
        rep["figures"] = [str(_figure_slips(rows, model, name, Path(args.out)))]
    lines = [f"phase slips of {model}, D = {D:g} on each mode (net slips per unit time, "
             f"Stratonovich's formula for the reduced Adler equation vs counts by its mean "
             f"phase; slips +/-: forward/backward turns counted)",
             f"  {name:>8} {'locked':>7} {'averaged':>11} {'simulated':>11} {'stderr':>9} "
             f"{'z':>6}  {'<dgamma/dt> avg':>15} {'simulated':>11} {'slips +/-':>11}"]
    for r in rows:
        s, f, sim = r["slip_rate"], r["frequency_difference"], r["simulation"]
        # the validity record's gap (none without spread, or where no turn was counted: the
        # spread is then the motion in the well)
        z = cell(r["validity"]["z"], "+6.2f")
        counts = f"{sim['forward_slips']}/{sim['backward_slips']}"
        lines.append(f"  {r['detuning']:8.4g} {'yes' if r['locked'] else 'no':>7} "
                     f"{s['averaged']:11.4g} {s['simulated']:11.4g} {s['stderr']:9.2g} {z:>6}  "
                     f"{f['averaged']:15.4g} {f['simulated']:11.4g} {counts:>11}")
    lines += [f"  WARNING: {r['validity']['advice']}" for r in flagged]
    return _emit(args, rep, lines)


def _figure_slips(rows, model, name, out: Path) -> Path:
    from numerics._plot import pyplot as _plt, save as _save

    plt = _plt()
    fig, ax = plt.subplots(figsize=(6, 4))
    x = [r["detuning"] for r in rows]
    ax.plot(x, [r["slip_rate"]["averaged"] for r in rows], "C0o-",
            label="averaged (Stratonovich)")
    ax.errorbar(x, [r["slip_rate"]["simulated"] for r in rows],
                yerr=[2 * r["slip_rate"]["stderr"] for r in rows], fmt="ks", ms=4,
                label="simulated counts (2 stderr)")
    ax.set_xlabel(f"detuning {name}")
    ax.set_ylabel("net slip rate (slips per unit time)")
    ax.set_title(f"{model}: phase slips")
    return _save(fig, ax, out / f"slips-{model}.png")


def _emit(args, rep, lines) -> int:
    from kbm.cli._common import emit_json, write_json

    if _opt(args, "out"):
        out = Path(args.out)
        out.mkdir(parents=True, exist_ok=True)
        write_json(out / f"spectrum-{rep['model']}.json", rep)
    if _opt(args, "json", False):
        return emit_json(rep)
    print("\n".join(lines))
    if _opt(args, "out"):
        for p in rep.get("figures", []):
            print(f"  wrote {p}")
    return 0
