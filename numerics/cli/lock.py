"""``kbm lock``: the locking region of coupled self-excited oscillators, averaged against true."""

from __future__ import annotations

import argparse

from kbm.cli._common import emit_json, write_json
from kbm.errors import ParameterError
from numerics.cli.params.options import command, options

#: the names a coupling parameter goes by (the others varied are detunings); a model's
#: couplings are those of its parameters that no physical name sets
#: (:func:`numerics.locking.mutual.coupling_names`: the sliders' ``k = 2 pi/lam`` is none)
COUPLINGS = ("c", "k", "kappa")


def register(sub) -> None:
    p = command(sub, "lock", "The edges of the frequency-locking region of a coupled system with "
                "one internal resonance (coupled-vdp): from the averaged slow flow at orders 1..N "
                "(the fold of its locked fixed point) and from the true locked cycle (where it "
                "ceases to exist, by continuation and bisection).", "internal", "param", "vary",
                "order", models="a coupled built-in with one internal resonance: coupled-vdp",
                coupled=True, internal=dict(
        metavar="P:Q",
        help="with --rhs: the declared resonance (e.g. 1:1); F not polynomial (sin, tanh "
             "coupling): the averaged flow is order 1, numeric"), vary=dict(
        required=True, default=None,
        help="the detuning and the interval its edges are looked for in (e.g. --vary "
             "sigma=-1:1); a second --vary gives the coupling's values (c=0.05:0.5 for "
             "--points values, c=0.05:0.5:N, or c=0.1,0.2,0.4), else the coupling is the -p "
             "value"), order=dict(
        help="highest averaged order (default 2, or 1 for F not polynomial; orders 1..N are "
             "given)"))
    options(p, "points", "tol", points=dict(
        default=7, help="coupling values on the second --vary range (default 7)"),
        tol=dict(default=1e-7, help="bisection bracket of the true edges (default 1e-7)"))
    options(p, "json", "out", out=dict(help="write lock.json and the tongue figure lock.png"))
    p.set_defaults(func=run)


def _split(varies, model) -> tuple:
    """``(detuning, coupling or None)`` among the ``--vary`` (in either order): the
    coupling is the one named as one of the model's couplings (c, k or kappa, unless a
    physical name sets it: the sliders' wavenumber k = 2 pi/lam is followed like lam)."""
    from numerics.locking.mutual import coupling_names

    names = coupling_names(model) or COUPLINGS
    couplings = [v for v in varies if v.name in names]
    detunings = [v for v in varies if v.name not in names]
    if not detunings:
        with_c = (f", with --vary {couplings[0].text} for the coupling's values"
                  if couplings else "")
        sigma = [p for p in model.parameters if p.startswith("sigma")]
        if sigma or not [p for p in model.parameters if p not in names]:
            det = (sigma or ["sigma"])[0]
            raise ParameterError(f"kbm lock looks for the edges of the locking region in a "
                                 f"detuning: give its interval, --vary {det}=FROM:TO (e.g. "
                                 f"{det}=-1:1)" + with_c)
        # identical oscillators (sedf-dimer): no detuning; a parameter's interval around
        # its value is followed instead (docs/coupled.rst: the dimer's in-phase state in beta)
        other = next(p for p in model.parameters if p not in names)
        raise ParameterError(f"{model.name} has no detuning (its oscillators are identical): "
                             f"give the interval of the parameter its locked state is "
                             f"followed in, e.g. --vary {other}=0.5:1.5" + with_c)
    if len(detunings) > 1 or len(couplings) > 1:
        raise ParameterError("give one --vary for the detuning (its interval) and at most one "
                             f"for the coupling ({', '.join(names)}); got "
                             f"{', '.join(v.name for v in varies)}")
    return detunings[0], (couplings[0] if couplings else None)


def coupled_mu(params, what: str) -> None:
    """Refuse ``-p mu`` <= 0 for a coupled system (``kbm lock``, ``kbm diagram``'s locking
    tongue): ``what`` names the command's object.

    Raises
    ------
    kbm.errors.ParameterError
        ``"mu = VALUE: WHAT of x_i'' + omega_i^2 x_i = mu F_i with the small parameter mu >
        0 ...; give -p mu=VALUE > 0"``.
    """
    if "mu" not in params:
        return
    from kbm.parameters.values import parameter_value

    if not parameter_value("mu", params["mu"]) > 0:
        raise ParameterError(f"mu = {params['mu']}: {what} of x_i'' + omega_i^2 x_i = mu F_i "
                             "with the small parameter mu > 0 (mu = 0 leaves the oscillators "
                             "uncoupled); give -p mu=VALUE > 0")


def run(args: argparse.Namespace) -> int:
    from kbm.output.files import output_folder
    from numerics.cli.params.values import within
    from numerics.locking.mutual import locking_region, plot_locking

    if len(args.vary) > 2:
        raise ParameterError("give at most two --vary: the detuning, then the coupling")
    from kbm.cli.derive import coupled_model

    model = coupled_model(args)
    if not isinstance(model.F, (tuple, list)) or len(model.F) < 2:
        # a one-degree-of-freedom built-in came here as itself (vdp: a TypeError traceback)
        raise ParameterError(f"kbm lock needs coupled oscillators; {model.name} has one degree "
                             "of freedom: choose a coupled built-in (coupled-vdp, sedf-dimer) "
                             "or give one --rhs per oscillator")
    if args.internal:
        model = model.with_internal(args.internal)
    if args.order is None:  # the numeric backend of a smooth F is first order
        args.order = 2 if all(f.is_polynomial(*model.state) for f in model.F) else 1
    within(args.order, "--order", 1, 4)
    within(args.points, "--points", 2, 200)
    within(args.tol, "--tol", 1e-12, 1e-2)
    from numerics.cli.params.values import check, given, parse_vary

    params = given(args.param)
    varies = [parse_vary(text) for text in args.vary]
    check(model, params, [v.name for v in varies])
    coupled_mu(params, "kbm lock follows the locked cycles")  # was searched, then "ask
    # another interval"
    dv, cv = _split(varies, model)
    dv.interval("the search for the edges", points=False)
    if dv.name == "mu":
        raise ParameterError("mu is the small parameter, not a detuning: vary the detuning "
                             "(e.g. --vary sigma=-1:1) and give -p mu=VALUE")
    det = (dv.name, *dv.bounds())
    coupling = None
    if cv is not None:
        values = cv.values(default=args.points)
        coupling = (cv.name, [float(f"{v:.12g}") for v in values])
    region = locking_region(model, params, det, coupling, tuple(range(1, args.order + 1)),
                            args.tol)
    data = {**region.to_json(), "params_given": params}
    if args.out:
        folder = output_folder(args.out)
        write_json(folder / "lock.json", data)
        plot_locking(region, folder / "lock.png")
    if args.json:
        return emit_json(data)
    shown = [f"{k}={v:g}" for k, v in region.params.items() if k != (coupling or ("",))[0]]
    if coupling is not None:
        cs = coupling[1]
        shown.append(f"{coupling[0]} from {cs[0]:g} to {cs[-1]:g}, {len(cs)} values")
    print(f"locking region of {region.model} ({', '.join(shown)})")
    print(f"edges in {region.detuning}:")
    for cv in sorted({c for c, _ in region.true} | {c for pts in region.averaged.values()
                                                     for c, _ in pts}):
        row = [f"  {region.coupling or 'c'} = {cv:.6g}:"]
        for n, pts in sorted(region.averaged.items()):
            row.append(f"order {n} " + ", ".join(f"{s:+.8f}" for c, s in pts if c == cv))
        row.append("true " + ", ".join(f"{s:+.8f}" for c, s in region.true if c == cv))
        print("  ".join(row))
    for d, at in zip(region.death, region.starts):
        print(f"  amplitude death at {region.coupling} = {d['coupling']:g}, "
              f"{region.detuning} = {at:g}: {'yes' if d['dead'] else 'no'} (largest real part of "
              f"the origin's eigenvalues {d['eigenvalues'][0][0]:+.4g})")
    if args.out:
        print(f"wrote {args.out}/lock.json and {args.out}/lock.png")
    return 0
