"""``kbm derive``: the KBM expansion of a model to a given order.

Symbolic where the engine is (polynomial ``F``: any order; ``sin``/``cos`` of ``x``:
order <= 2); above that, the same expansion evaluated at numeric parameters and the
amplitudes of ``--a-range`` (:func:`kbm.derive_values`); with ``--numeric``, the numeric
backend for any smooth ``F`` (:func:`kbm.numeric_derive`).  The two evaluated routes
print tables.
"""

from __future__ import annotations

import argparse

import numpy as np

from ..errors import ParameterError
from ._common import (add_command, add_model_arguments, add_options, check_model_flags,
                      checked_params, emit_json, model_spec)


def register(sub) -> None:
    p = add_command(sub, "derive", "Derive the Krylov-Bogoliubov-Mitropolsky expansion of x'' + "
                    "omega0^2 x = mu F(x, x') to order N: symbolic for polynomial F (any order) "
                    "and sin/cos of x (order <= 2); evaluated at numeric parameters on --a-range "
                    "above that; with --numeric for any smooth F.")
    from ..model.builtins import model_names

    from ..model.coupled_builtins import coupled_model_names

    add_model_arguments(p, f"{', '.join(model_names())}; coupled: "
                           f"{', '.join(coupled_model_names())}", coupled=True)
    add_options(p, "internal", "order", "param", internal=dict(
        metavar="P:Q",
        help="declare the internal resonance omega_1 : omega_2 = P : Q (repeatable; P:Q@I,J "
             "between modes I and J); coupled systems only"),
        order=dict(required=True, help="order N >= 1"))
    p.add_argument("--numeric", action="store_true",
                   help="numeric backend for any smooth F (tanh, exp, ...): tables of A_n, "
                        "B_n on --a-range with error estimates")
    add_options(p, "a_range", "points", a_range=dict(
        help="amplitudes of the tables (0 < AMIN < AMAX); for --numeric also the interval the "
             "expansion is computed on"),
        points=dict(default=9, help="rows of the tables: equispaced amplitudes of --a-range "
                                    "(default 9)"))
    p.add_argument("--at", metavar="a1=V,a2=V,gamma1=V",
                   help="coupled systems with --numeric: the amplitudes and slow phases where "
                        "the first-order rates are evaluated (any smooth F; -p gives every "
                        "parameter's value)")
    add_options(p, "tol", tol=dict(help="tolerance of the evaluated routes (relative; default "
                                        "1e-10 with --numeric, 1e-14 for the Bessel harmonics)"))
    fmt = p.add_mutually_exclusive_group()
    add_options(fmt, "json", json=dict(help="print JSON (strings sympy can parse)"))
    fmt.add_argument("--latex", action="store_true", help="print LaTeX")
    p.set_defaults(func=run)


def model_from_args(args: argparse.Namespace, *, series: bool = False):
    """The model named on the command line (with ``--param`` values), or the user's ``--rhs``.

    The expansion is in powers of ``mu``, so ``-p mu`` only converts a physical name
    (``Delta`` to ``delta = Delta/mu``); alone it is refused, not ignored (``series``: the
    message points to ``--float --at MU``).

    Raises
    ------
    kbm.errors.ParameterError
        For an unknown name (:func:`kbm.cli._common.checked_params`) or ``-p mu`` that
        sets nothing.
    """
    from ..model.builtins import get_model
    from ..parameters.names import names_of

    spec = model_spec(args)  # a built-in's name, or the --rhs model
    # a forced built-in is of another kind, not unknown
    params = checked_params(args.param, spec, ("one",) if series else ("one", "coupled"))
    model = (get_model(spec, params) if isinstance(spec, str)
             else spec.substitute(params) if params else spec)
    _mu_sets_something(names_of(spec), params, series)
    return model


def _mu_sets_something(names, params: dict, series: bool) -> None:
    """Refuse ``-p mu`` where no physical name needs it (the expansion is in powers of mu)."""
    if "mu" not in params or set(params) & set(names.physical_names):
        return
    where = ("kbm series expands in powers of mu; for values at one mu give --float --at MU"
             if series else "the expansion A_n, B_n, u_n is in powers of mu and does not "
             "depend on it")
    phys = names.physical_names
    use = (f" (-p mu only converts {', '.join(phys)} to the scaled names)" if phys else "")
    raise ParameterError(f"-p mu sets nothing here: {where}{use}; leave -p mu out")


def _amplitudes(args: argparse.Namespace, why: str) -> tuple[tuple[float, float], np.ndarray]:
    from ..backend.sampling import parse_a_range

    if args.a_range is None:
        raise ParameterError(f"{why}: give the amplitudes with --a-range AMIN:AMAX "
                             "(e.g. --a-range 0.1:4) and a value for every parameter "
                             "(--param NAME=VALUE)")
    lo, hi = parse_a_range(args.a_range)
    if args.points < 2:
        raise ParameterError(f"--points must be >= 2, got {args.points}")
    return (lo, hi), np.linspace(lo, hi, args.points)


def _linear(omega0: float) -> str:
    """The linear term ``x`` (``omega0 = 1``) or ``omega0^2 x``."""
    return "x" if float(omega0) == 1 else f"{float(omega0):g}^2 x"


def _print_table(title: list[str], a: np.ndarray, order: int, A, B, errors=None) -> None:
    """The title lines, then the columns ``A_n = A[n]``, ``B_n = B[n]`` (n = 1..order) at the
    amplitudes ``a``; ``errors``: ``(A_error, B_error)`` alike, the last row."""
    for line in title:
        print(line)

    def columns(A, B) -> dict:
        return {f"{k}_{n}": X[n] for k, X in (("A", A), ("B", B)) for n in range(1, order + 1)}

    cols = columns(A, B)
    errors = None if errors is None else columns(*errors)
    names = list(cols)
    print(f"{'a':>10s} " + " ".join(f"{n:>22s}" for n in names))
    for i, ai in enumerate(a):
        print(f"{ai:10.6g} " + " ".join(f"{cols[n][i]:22.14e}" for n in names))
    if errors is not None:
        print(f"{'error est.':>10s} " + " ".join(f"{errors[n]:22.1e}" for n in names))


def _run_numeric(args, model) -> int:
    from ..backend.one_dof import DEFAULT_TOL, numeric_derive

    if args.latex:
        raise ParameterError("--latex prints symbolic results; --numeric gives tables "
                             "(drop --latex, or use --json)")
    (lo, hi), a = _amplitudes(args, "--numeric computes on an amplitude interval")
    res = numeric_derive(model, args.order, (lo, hi),
                         tol=DEFAULT_TOL if args.tol is None else args.tol)
    if args.json:
        return emit_json(res.to_json(a))
    tab = res.table(a)
    P, M = res.resolution
    _print_table([f"KBM expansion of {res.model.name}: x'' + {_linear(res.omega0)} = "
                  f"mu*({res.model.F}), order {args.order}, numeric backend",
                  f"grid: {P} Chebyshev points on a in [{lo:g}, {hi:g}] (and a margin), "
                  f"{M} phases; tol {res.tol:.0e}; error estimates (absolute) in the last row"],
                 a, args.order, dict(enumerate(tab["A"], 1)), dict(enumerate(tab["B"], 1)),
                 (res.A_error, res.B_error))
    return 0


def _run_values(args, model, limit: int) -> int:
    from ..backend.pointwise import DEFAULT_TOL, derive_values

    if args.latex:
        raise ParameterError(f"order {args.order} of {model.name!r} is evaluated, not "
                             f"symbolic (the Bessel sums stay symbolic to order {limit}); "
                             "drop --latex, or ask for order <= 2")
    why = (f"order {args.order} of {model.name!r} is evaluated at numeric values, not kept "
           f"symbolic (with sin/cos of x the Bessel sums stay symbolic to order {limit}; "
           f"order 3 would need sums over three indices)")
    _, a = _amplitudes(args, why)
    res = derive_values(model, args.order, a, tol=DEFAULT_TOL if args.tol is None else args.tol)
    if args.json:
        return emit_json(res.to_json())
    _print_table([f"KBM expansion of {res.model.name}: F = {res.model.F}, order {args.order}",
                  f"note: {why}.",
                  f"Jacobi-Anger series with exact a-derivatives, harmonics up to "
                  f"{res.harmonics} (truncation below {res.tol:.0e} relative)"],
                 a, args.order, res.A, res.B)
    return 0


def is_coupled(args: argparse.Namespace) -> bool:
    """Whether the command line names a coupled system: several ``--rhs``, several
    frequencies, ``--internal``, ``--nu0`` (a forced system in the general form), or a
    coupled built-in."""
    rhs = getattr(args, "rhs", None) or []
    name = args.model
    return (len(rhs) > 1 or bool(getattr(args, "internal", None))
            or getattr(args, "nu0", None) is not None
            or (bool(rhs) and "," in str(args.omega0 or ""))
            or (isinstance(name, str) and (name in COUPLED_NAMES
                                           or name.startswith("sedf-chain-"))))


#: the names of the coupled built-ins (:data:`kbm.model.coupled_builtins.COUPLED_MODELS`, whose
#: systems are built with sympy at import): :func:`is_coupled` of a one-degree-of-freedom
#: command then imports no sympy (issue 39); ``tests/test_template_cache.py`` checks the
#: list against the catalogue
COUPLED_NAMES = frozenset({"coupled-vdp", "duffing-1-3", "quadratic-1-2", "sedf-chain",
                           "sedf-dimer"})


def coupled_model(args: argparse.Namespace):
    """The coupled system of the command line: a built-in (coupled, or one degree of
    freedom as ``N = 1``) or the ``--rhs`` list with ``--omega0``."""
    from ..model.coupled_builtins import coupled_custom, get_coupled_model

    check_model_flags(args)
    if args.rhs:
        return coupled_custom(args.rhs, args.omega0, nu0=getattr(args, "nu0", None))
    return get_coupled_model(args.model)


def _run_coupled(args: argparse.Namespace) -> int:
    from ..expansion.coupled import derive_coupled

    if args.numeric:
        return _run_coupled_numeric(args)
    if args.a_range is not None or args.at is not None:
        raise ParameterError("--a-range is for one degree of freedom, --at for --numeric; the "
                             "coupled expansion is exact for polynomial right-hand sides")
    model = coupled_model(args)
    return _emit(derive_coupled(model, args.order, checked_params(args.param, model),
                                internal=args.internal), args)


def _run_coupled_numeric(args: argparse.Namespace) -> int:
    """The rates of a coupled system with any smooth F at one point: order 1 by the FFT
    average on the torus, higher orders by the recursion on jets (kbm.backend.jets)."""
    import math

    from ..backend.jets import MAX_ORDER_JETS
    from ..backend.coupled import numeric_average

    if not 1 <= args.order <= MAX_ORDER_JETS:
        raise ParameterError(f"the numeric backend of coupled systems takes --order 1 to "
                             f"{MAX_ORDER_JETS}, not {args.order}")
    refused = [f for f, on in (("--latex", args.latex), ("--a-range", args.a_range is not None))
               if on]
    if refused:
        raise ParameterError(f"{' and '.join(refused)} {'is' if len(refused) == 1 else 'are'} "
                             "not for the coupled numeric backend (its rates are numbers at "
                             "the point --at)")
    if not args.at:
        raise ParameterError("give the point: --at a1=1,a2=1,gamma1=0 (the amplitudes and "
                             "the slow phases of the declared resonances)")
    point = {}
    for item in args.at.split(","):
        name, sep, val = item.partition("=")
        try:
            point[name.strip()] = float(val)
        except ValueError:
            raise ParameterError(f"--at takes NAME=VALUE,..., got {item!r}") from None
        if not sep or not math.isfinite(point[name.strip()]):
            raise ParameterError(f"--at takes NAME=VALUE with a finite value, got {item!r}")
    model = coupled_model(args)
    na = numeric_average(model, checked_params(args.param, model), internal=args.internal)
    n = na.model.dof
    names_a = [f"a{i}" for i in range(1, n + 1)]
    names_g = [f"gamma{r}" for r in range(1, len(na.gammas) + 1)]
    extra = sorted(set(point) - set(names_a) - set(names_g))
    missing = [k for k in names_a + names_g if k not in point]
    if extra or missing:
        raise ParameterError(f"--at needs exactly {', '.join(names_a + names_g)}"
                             + (f"; missing {', '.join(missing)}" if missing else "")
                             + (f"; unknown {', '.join(extra)}" if extra else ""))
    amps, phases = [point[k] for k in names_a], [point[k] for k in names_g]
    if args.order == 1:
        A1, B1, tail = na.rates(amps, phases)
        A = [[float(A1[i])] for i in range(n)]
        B = [[float(B1[i])] for i in range(n)]
    else:
        ex = na.expansion(amps, phases, args.order)
        A, B, tail = [list(r) for r in ex.A], [list(r) for r in ex.B], ex.tail
    gam = [_combination(g, n) for g in na.gammas]
    if args.json:
        return emit_json({"model": na.model.name, "order": args.order, "numeric": True,
                          "point": point, "A": [[None, *A[i]] for i in range(n)],
                          "B": [[None, *B[i]] for i in range(n)],
                          "gammas": [[f"gamma{r + 1}", g] for r, g in enumerate(gam)],
                          "nodes": na.nodes, "tail": tail})
    what = "first-order rates" if args.order == 1 else f"rates to order {args.order}"
    print(f"{what} of {na.model.name} at "
          + ", ".join(f"{k} = {v:g}" for k, v in point.items())
          + f" (grid {na.nodes}^{len(na.gammas[0]) if na.gammas else n} on the torus; "
          f"outer coefficients {tail:.1e})")
    for r, g in enumerate(gam, 1):
        print(f"  gamma{r} = {g}")
    for i in range(n):
        for m in range(args.order):
            print(f"  A_{i + 1},{m + 1} = {A[i][m]:.15g}    B_{i + 1},{m + 1} = {B[i][m]:.15g}")
    return 0


def _combination(g: tuple[int, ...], n: int) -> str:
    """``(-3, 1)`` -> ``"psi2 - 3*psi1"`` (the forcing angle of a forced system is
    ``theta``), positive terms first."""
    terms = sorted(((v, f"psi{i + 1}" if i < n else "theta") for i, v in enumerate(g) if v),
                   key=lambda t: -t[0])
    out = ""
    for v, name in terms:
        mag = "" if abs(v) == 1 else f"{abs(v)}*"
        out += (" - " if v < 0 else " + ") + mag + name if out else ("-" if v < 0 else "") + mag + name
    return out


def _emit(res, args: argparse.Namespace) -> int:
    """Print a symbolic result as JSON, LaTeX or plain text."""
    if args.json:
        emit_json(res.to_json())
    elif args.latex:
        print(res.latex())
    else:
        print(res.pretty())
    return 0


def run(args: argparse.Namespace) -> int:
    from ..expansion.one_dof import MAX_ORDER, derive, symbolic_order_limit
    from ..expansion.cost import check_cost

    if is_coupled(args):
        return _run_coupled(args)
    if args.at is not None:  # one degree of freedom: --at would be ignored silently
        raise ParameterError("--at is the point of a coupled system's --numeric rates; for "
                             "one degree of freedom give the amplitudes with --a-range "
                             "AMIN:AMAX (with --numeric, or above the symbolic order limit)")
    model = model_from_args(args)
    if args.numeric:
        return _run_numeric(args, model)
    if 1 <= args.order <= MAX_ORDER:
        check_cost(model.F, args.order)  # before anything is expanded
    limit = symbolic_order_limit(model)
    if limit < args.order <= MAX_ORDER:
        return _run_values(args, model, limit)
    if args.a_range is not None:
        raise ParameterError("--a-range makes tables of the evaluated routes: use it with "
                             "--numeric, or with an order above the symbolic limit")
    return _emit(derive(model, args.order), args)
