"""``kbm series``: mu-series of the limit-cycle frequency and amplitude, exact or floating."""

from __future__ import annotations

import argparse

import sympy as sp

from ..errors import ParameterError
from ._common import add_command, add_model_arguments, add_options, emit_json


def register(sub) -> None:
    p = add_command(sub, "series", "Expand the limit-cycle frequency omega* and first-harmonic "
                    "amplitude a* in powers of mu: exact rationals (to mu^200), or with --float "
                    "in floating point to high order (to mu^1000; van der Pol: order 300 in about "
                    "13 s, 1000 in about 9 min CPU, with a progress bar on a terminal), with the "
                    "radius of convergence and Pade resummation.")
    add_model_arguments(p, model=dict(help="built-in model with polynomial F (e.g. vdp)"),
                        rhs=dict(help="your own polynomial F"))
    add_options(p, "order", order=dict(required=True, help="highest power of mu"))
    p.add_argument("--root", default=None, help="first-order amplitude a0 if A_1 has several "
                   "positive roots")
    p.add_argument("--method", choices=("auto", "lindstedt", "kbm"), default="auto",
                   help="exact route: Lindstedt recursion on the cycle (fast), or the root of "
                        "the KBM averaged equations (order <= 29); default: the first that "
                        "applies")
    p.add_argument("--float", action="store_true", dest="floating",
                   help="floating-point coefficients (double precision unless --digits), "
                        "with the nearest singularity and Pade values")
    add_options(p, "digits", digits=dict(help="with --float: decimal digits of an mpmath "
                                               "computation (5..1000; slow, order <= 200)"))
    p.add_argument("--at", type=float, action="append", default=[], metavar="MU",
                   help="with --float: Pade-resummed omega* and a* at this mu (repeatable; "
                        "within 10 radii of convergence, with a note beyond the radius)")
    add_options(p, "param", "json", json=dict(help="print JSON (rationals as strings)"))
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from .derive import model_from_args

    model = model_from_args(args, series=True)
    if not args.floating:
        if args.digits is not None or args.at:
            raise ParameterError("--digits and --at go with --float")
        return _exact(args, model)
    if args.method != "auto":
        raise ParameterError("--method chooses the exact route; leave it out with --float")
    return _floating(args, model)


def _exact(args, model) -> int:
    from ..slowflow.series import limit_cycle_series

    s = limit_cycle_series(model, args.order, root=args.root, method=args.method)
    if args.json:
        return emit_json({"model": model.name, "order": s.order,
                          "omega": [str(c) for c in s.omega],
                          "amplitude": [str(c) for c in s.amplitude]})
    # ascending powers of mu, as a series is read (1 - mu**2/16 + ...)
    print(f"omega* = {sp.sstr(s.omega_expr(), order='rev-lex')} + O(mu**{s.order + 1})")
    print(f"a*     = {sp.sstr(s.amplitude_expr(), order='rev-lex')} + O(mu**{s.order + 1})")
    return 0


def _floating(args, model) -> int:
    import mpmath

    from ..slowflow.numeric_series import numeric_cycle_series

    import sys

    from tqdm.auto import tqdm

    # the recursion's step to mu**n costs about n times the first (van der Pol in double
    # precision: order 300 in ~13 s, 1000 in 563 s CPU, 99.5 % the recursion, 65 % numpy's
    # convolutions of its Cauchy products): a bar on stderr, on a terminal only
    with tqdm(total=args.order + 1, file=sys.stderr, unit="order", desc="kbm series",
              disable=None, leave=False) as bar:
        s = numeric_cycle_series(model, args.order, digits=args.digits, root=args.root,
                                 progress=bar.update)
    shown = 17 if args.digits is None else args.digits

    def fmt(v) -> str:
        return mpmath.nstr(mpmath.mpf(v), shown, min_fixed=0, max_fixed=0)

    try:
        sing = s.singularity()
    except ValueError:  # too few coefficients for an estimate
        sing = None
    reach = {mu: _pade_reach(s, sing, mu) for mu in args.at}  # refuses beyond PADE_REACH
    pades = {mu: _pade(s, mu) for mu in args.at}
    if args.json:
        return emit_json({
            "model": model.name, "order": s.order, "digits": args.digits,
            "variable": s.variable,
            "omega": [fmt(c) for c in s.omega], "amplitude": [fmt(c) for c in s.amplitude],
            "singularity": None if sing is None else {
                "radius": sing.radius, "angle": sing.angle, "radius_last": sing.radius_last,
                "pole_radius": sing.pole_radius, "pole_angle": sing.pole_angle},
            "pade": [{"mu": mu, "omega": fmt(w.value), "omega_error": float(w.error),
                      "amplitude": fmt(a.value), "amplitude_error": float(a.error),
                      "radius_multiple": reach[mu]}
                     for mu, (w, a) in pades.items()]})
    prec = "double precision" if args.digits is None else f"{args.digits} digits"
    print(f"{model.name}: mu-series to order {s.order} ({prec}), in {s.variable}")
    for name, coeffs in (("omega*", s.omega), ("a*", s.amplitude)):
        step = 2 if s.even else 1
        head = ", ".join(fmt(c) for c in coeffs[:9:step])
        which = "c_0, c_2, c_4, ... (odd powers vanish)" if s.even else "c_0, c_1, c_2, ..."
        print(f"{name:7s} = sum of c_k mu^k; {which} = {head}, ..., "
              f"c_{s.order} = {fmt(coeffs[s.order])}")
    if sing is not None:
        pole = "" if sing.pole_radius is None else (
            f"; nearest Pade pole |{s.variable}| = {sing.pole_radius:.4f} at angle "
            f"+-{sing.pole_angle:.4f}")
        print(f"nearest singularities of omega*: |{s.variable}| = {sing.radius:.4f} at angle "
              f"+-{sing.angle:.4f} rad (ratio estimates extrapolated){pole}")

    def pm(err) -> str:
        """The error column: the agreement of successive approximants, or why there is none."""
        return "+- unmeasured" if mpmath.isinf(err) else f"+- {mpmath.nstr(err, 2)}"
    for mu, (w, a) in pades.items():
        print(f"mu = {mu:g}: Pade omega* = {fmt(w.value)} ({pm(w.error)}), "
              f"a* = {fmt(a.value)} ({pm(a.error)})")
        if mpmath.isinf(w.error) or mpmath.isinf(a.error):
            print(f"  the +- is unmeasured: at --order {s.order} one Pade degree is formed, "
                  "and the error is the agreement of two; raise --order")
        if reach[mu] is not None and reach[mu] > 1:
            print(f"  beyond the radius of convergence ({s.variable} = {reach[mu]:.3g} times "
                  f"{sing.radius:.4g}): the +- is the agreement of successive Pade "
                  "approximants, which can understate the error there by orders of "
                  "magnitude (van der Pol at mu = 5, 7.3 radii, against the true cycle: 7 "
                  "times at order 40, 1.3e4 at 80, 13 at 160, 15 at 300)")
    return 0


#: how far beyond the radius of convergence ``R`` (in the series' variable) ``--at`` goes:
#: the Pade continuation is checked against the true cycles to ``mu = 5``, ``mu^2 = 7.3 R``
#: for van der Pol (docs/theory.rst).  Measured there (order 300 against numerics'
#: cycles): its error is 7, 15, 26, 43, 91 and 160 times the stated one (the approximants'
#: agreement) at ``mu^2`` = 2.6, 7.3, 14, 29, 117 and 731 ``R`` (mu = 3, 5, 7, 10, 20, 50),
#: 2 % at mu = 10; at mu = 5, 7 times at order 40, 1.3e4 at 80 (6.7e-4 against a stated
#: 5.2e-8), 13 at 160.  The approximants tend to a constant as ``mu -> oo`` (0.1757 for
#: ``omega*`` at order 300), where the true ``omega*`` falls like
#: ``2 pi/((3 - 2 ln 2) mu)``.
PADE_REACH = 10.0


def _pade_reach(s, sing, mu: float) -> float | None:
    """``|t|/R`` of ``--at mu`` (``t`` the series' variable, ``R`` the ratio estimates'
    radius); ``None`` without an estimate of ``R``.

    Raises
    ------
    kbm.errors.ParameterError
        Beyond :data:`PADE_REACH` radii, or for a ``mu`` that is not finite.
    """
    import math

    if not math.isfinite(mu):
        raise ParameterError(f"--at must be a finite number, got {mu}")
    import mpmath

    t = mpmath.mpf(abs(mu)) ** (2 if s.even else 1)  # mu = 1e300: no float overflow
    if sing is None or not (math.isfinite(sing.radius) and sing.radius > 0):
        _within_terms(s, mu, t)
        return None
    ratio = t / sing.radius
    if ratio > PADE_REACH:
        top = (PADE_REACH * sing.radius) ** (0.5 if s.even else 1)
        raise ParameterError(
            f"--at {mu:g}: {s.variable} = {mpmath.nstr(t, 3)} is {mpmath.nstr(ratio, 3)} "
            f"times the series' radius of convergence {sing.radius:.4g}; the Pade "
            f"continuation is checked to {PADE_REACH:g} times it (van der Pol against the true "
            "cycle: its error 15 times the stated at mu = 5, 2 % at mu = 10 with 0.05 % "
            "stated, and it tends to a constant as mu grows): give --at with |MU| <= "
            f"{top:.3g}, or kbm cycle for the true cycle")
    return float(ratio)


def _within_terms(s, mu: float, t) -> None:
    """Refuse ``--at`` far beyond where the series' own terms shrink, when its radius of
    convergence cannot be estimated (too few coefficients for
    :func:`kbm.slowflow.resum.nearest_singularity`): the reach of :data:`PADE_REACH` radii
    was then not checked at all.  ``kbm series vdp --order 5 --float --at 1e9`` printed
    omega* = 0.294 "+- unmeasured", where the true omega* is about 3.9e-9 (``2 pi/((3 - 2
    ln 2) mu)``), though ``--order 80`` refuses the same ``--at``.

    In place of the radius, the ratio estimate of the last two nonzero coefficients ``c_i,
    c_j`` in the series' variable, ``|c_i/c_j|^(1/(j - i))``, the smaller of omega*'s and
    a*'s (van der Pol: 11.3 at order 5, 2.43 at order 12, the radius 3.42); a series with
    fewer than two nonzero coefficients has none.  Within its reach the values are printed
    as before: at mu = 10 (8.9 such radii) order 5 gives omega* = 0.366 against the true
    0.329 (numerics' cycle); at order 12 mu = 10 (41 of them) is refused, where the value
    was 0.58 +- 0.22.

    Raises
    ------
    kbm.errors.ParameterError
        With the largest ``--at`` taken and what to do.
    """
    import mpmath

    bounds = []
    for which in ("omega", "amplitude"):
        nz = [(k, mpmath.mpf(c)) for k, c in enumerate(s.coefficients(which)) if c != 0]
        if len(nz) >= 2:
            (i, ci), (j, cj) = nz[-2:]
            bounds.append((abs(ci / cj) ** (mpmath.mpf(1) / (j - i)), i, j))
    if not bounds or t <= PADE_REACH * min(bounds)[0]:
        return
    bound, i, j = min(bounds)
    top = (PADE_REACH * bound) ** (0.5 if s.even else 1)
    raise ParameterError(
        f"--at {mu:g}: at --order {s.order} the series has too few coefficients to estimate "
        f"its radius of convergence; the ratio of its last two (of {s.variable} to the "
        f"powers {i} and {j}) puts it near |{s.variable}| = {mpmath.nstr(bound, 3)}, and "
        f"{s.variable} = {mpmath.nstr(t, 3)} is {mpmath.nstr(t / bound, 3)} times that, "
        f"beyond the {PADE_REACH:g} radii the Pade continuation is checked to: give --at "
        f"with |MU| <= {mpmath.nstr(top, 3)}, raise --order until the radius is printed, or "
        "use kbm cycle for the true cycle")


def _pade(s, mu: float) -> tuple:
    """The Pade values of omega* and a* at ``mu``; too few coefficients for any diagonal
    approximant ``[M/M]``, ``M >= 1`` (``--order 3`` of van der Pol: ``c_0, c_2`` only),
    refused (an ``ArithmeticError`` traceback before).

    Raises
    ------
    kbm.errors.ParameterError
    """
    try:
        return s.pade(mu, "omega"), s.pade(mu, "amplitude")
    except ArithmeticError:
        raise ParameterError(f"--at {mu:g}: at --order {s.order} no Pade approximant of the "
                             f"series in {s.variable} can be formed (it needs at least three "
                             "coefficients, not all of them zero): raise --order") from None
