"""Helpers shared by the sub-commands: the shared options, ``--param`` parsing and checking
(:func:`check`, the parameter layer of every command) and JSON output.

Every option that several commands take is defined once, in :data:`OPTIONS` (its flags,
type, default, metavar and help); a command adds it with :func:`add_options`, naming what
differs there (a default, or a help that says what the option does in that command).  The
numerical commands' ensemble options (``--trajectories``, ``--seed``, ``--workers``,
``--store``, ``--resume``, ``--budget``) are in :mod:`numerics.cli.params.options`.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Iterable, Mapping
from typing import TYPE_CHECKING, Any

from ..errors import ModelError, ParameterError
from ..output.strict_json import strict_text

if TYPE_CHECKING:
    from ..parameters.values import ParameterNames

__all__ = ["OPTIONS", "ONE_DOF", "add_command", "add_options", "parse_params", "check",
           "checked_params", "emit_json", "show", "write_json", "add_model_arguments",
           "model_spec", "check_model_flags", "single_well", "table_cell"]


#: the options several commands take: name -> (flags, argparse keywords); a command names
#: what differs there (:func:`add_options`)
OPTIONS: dict[str, tuple[tuple[str, ...], dict[str, Any]]] = {
    "model": (("model",), dict(nargs="?")),
    "rhs": (("--rhs",), dict(metavar="EXPR", help="your own F (in x, xdot and parameters) "
                                                 "instead of a built-in model")),
    "omega0": (("--omega0",), dict(default=None, help="linear frequency for --rhs (default 1)")),
    "nu0": (("--nu0",), dict(default=None, metavar="NU0", help=(
        "with --rhs holding the forcing angle theta: its frequency nu = NU0 + mu sigma "
        "(theta = nu t)"))),
    "internal": (("--internal",), dict(action="append", default=[])),
    "param": (("--param", "-p"), dict(
        action="append", default=[], metavar="NAME=VALUE",
        help="set a parameter (repeatable), e.g. --param beta=1 --param mu=0.1")),
    "vary": (("--vary",), dict(action="append", default=[], metavar="NAME=FROM:TO")),
    "order": (("--order", "-n"), dict(type=int, default=None)),
    "orders": (("--orders",), dict(default="1,2")),
    "start": (("--start",), dict(default=None, help=(
        "coupled systems: the state to start from (default: the attracting orbit after a "
        "transient from x_i = 1)"))),
    "x_start": (("--x-start",), dict(type=float, default=None, metavar="X")),
    "max_points": (("--max-points",), dict(type=int, default=400, metavar="N")),
    "convergence": (("--convergence",), dict(metavar="MU1,MU2,...")),
    "a_range": (("--a-range",), dict(metavar="AMIN:AMAX", default=None)),
    "points": (("--points",), dict(type=int)),
    "tol": (("--tol",), dict(type=float, default=None)),
    "digits": (("--digits",), dict(type=int, default=None)),
    "t_end": (("--t-end",), dict(type=float, default=None)),
    "dt": (("--dt",), dict(type=float, default=None, metavar="H")),
    "no_simulation": (("--no-simulation",), dict(action="store_true")),
    "rtol": (("--rtol",), dict(type=float, default=1e-10, help="integrator tolerance")),
    "json": (("--json",), dict(action="store_true", help="print JSON")),
    "out": (("--out",), dict(metavar="DIR")),
}


def add_options(parser: argparse.ArgumentParser, *names: str,
                table: Mapping[str, tuple[tuple[str, ...], dict[str, Any]]] = OPTIONS,
                **changes: Mapping[str, Any]) -> None:
    """Add the shared options ``names`` of ``table`` (:data:`OPTIONS`), in that order.

    ``changes[name]`` holds the keywords that differ in this command (``default=``,
    ``help=``, ...); the flags, the type and the rest are the shared ones.

    Examples
    --------
    >>> p = argparse.ArgumentParser()
    >>> add_options(p, "rtol", "json", rtol=dict(default=1e-12))
    >>> p.parse_args(["--json"])
    Namespace(rtol=1e-12, json=True)
    """
    for name in names:
        flags, kw = table[name]
        parser.add_argument(*flags, **{**kw, **changes.get(name, {})})


def add_command(sub, name: str, description: str,
                summaries: Mapping[str, str] | None = None) -> argparse.ArgumentParser:
    """The parser of the command ``name``: its line in ``kbm --help`` is its entry in
    ``summaries`` (the symbolic commands' :data:`kbm.cli.SUMMARIES` by default), written
    once for the lazy help and the command's own parser."""
    if summaries is None:
        from . import SUMMARIES as summaries
    return sub.add_parser(name, help=summaries[name], description=description)


def parse_params(items: list[str]) -> dict[str, str]:
    """``["beta=1", "mu=0.1"]`` -> ``{"beta": "1", "mu": "0.1"}`` (values stay strings, read exactly)."""
    out: dict[str, str] = {}
    for item in items:
        name, sep, value = item.partition("=")
        name, value = name.strip(), value.strip()
        if not sep or not name or not value:
            raise ParameterError(f"--param takes NAME=VALUE, got {item!r}")
        if name in out:
            raise ParameterError(f"parameter {name!r} is given twice")
        out[name] = value
    return out


def checked_params(items: list[str], model: object,
                   kinds: Iterable[str] | None = None) -> dict[str, str]:
    """``-p NAME=VALUE`` options read (:func:`parse_params`) and checked (:func:`check`)
    against the names ``model`` takes (:class:`kbm.parameters.values.ParameterNames`: ``mu``, the
    physical names such as ``Delta``, ``lam``, the scaled ones such as ``delta = Delta/mu``,
    ``k = 2 pi/lam``).

    ``model`` is a model, or a built-in name; a name that is no built-in is left to the
    command, which names the unknown model, unless ``kinds`` names the kinds of built-in the
    command takes (``("one",)``, ``("one", "coupled")``): then a name of another kind or no
    built-in is refused first (:func:`kbm.parameters.names.lookup`, ``--rhs`` offered).

    Raises
    ------
    kbm.errors.ModelError
        With ``kinds``: a built-in of another kind (no traceback further on) or an unknown
        name, the built-ins the command takes listed.
    kbm.errors.ParameterError
        For an unknown name (the closest valid one and every valid one named, in ``-p``
        terms), or a scaled name given with the physical one it is computed from.
    """
    from ..model.builtins import Oscillator
    from ..parameters.names import lookup

    if isinstance(model, str) and kinds is not None:
        model = lookup(model, kinds, rhs=True)
    params = parse_params(items)
    if isinstance(model, str):
        try:
            model = lookup(model)
        except ModelError:  # the command names the unknown model in its own terms
            return params
    # a stage velocity v is left to the model, which says what takes one (a slider, in
    # kbm slide and kbm friction; these commands need the autonomous model)
    stage = isinstance(model, Oscillator)
    check(model, {n: v for n, v in params.items() if not (stage and n == "v")})
    return params


def check(model: object, params: Mapping[str, object], varied: Iterable[str] = (), *,
          extra: Iterable[str] = (), noise: bool = False, start: bool = False
          ) -> ParameterNames:
    """Refuse a name ``model`` (a tuple: any of them, ``--against``) does not take (in
    ``-p`` or ``--vary``), a name given in both (unless ``start``: a continuation starts at
    the ``-p`` value of the name it varies), and a scaled name given with its physical one;
    returns the names.

    Raises
    ------
    kbm.errors.ParameterError
        Naming the wrong name, the close valid one and every valid one.
    """
    from ..parameters.names import names_of  # sympy: on use, not at import (issue 39)
    from ..parameters.values import ParameterNames

    models = model if isinstance(model, tuple) else (model,)
    names = names_of(models[0], extra=extra, noise=noise)
    for other in models[1:]:  # --against: a name of either model
        if other == models[0]:  # --against the same model: its own names
            continue
        more = names_of(other)
        names = ParameterNames(f"{names.model} or {more.model}",
                               tuple(sorted(set(names.scaled) | set(more.scaled))),
                               {**names.physical, **more.physical}, names.extra, noise)
    names.check(params, flag="-p")
    varied = list(varied)
    names.check(varied, flag="--vary")
    both = [n for n in varied if n in params]
    if both and not start:
        raise ParameterError(f"{both[0]} is both varied (--vary) and given (-p); give it once")
    seen = set()
    for n in varied:
        if n in seen:
            raise ParameterError(f"--vary {n} is given twice")
        seen.add(n)
    names.check_both(set(params) | set(varied))
    return names


def single_well(model) -> bool:
    """Whether the force at rest of ``model`` (an autonomous oscillator of one degree of
    freedom) is ``-omega0^2 x`` plus a constant at every parameter value: ``F`` at
    ``x' = 0`` does not depend on ``x`` (van der Pol, Rayleigh).  Its potential is then the
    parabola ``omega0^2 x^2/2``, shifted: one well with no barrier, no saddle and so no
    homoclinic orbit, whatever the parameters."""
    from ..symbols import x, xdot

    return x not in model.F.subs(xdot, 0).free_symbols


def emit_json(obj: Any) -> int:
    """Print ``obj`` as strict JSON (keys in a fixed order, as built; NaN and infinities
    become ``null``, so that every JSON parser reads it); returns the exit status 0."""
    sys.stdout.write(strict_text(obj))
    return 0


def show(args: argparse.Namespace, result: Any) -> int:
    """Print ``result`` as the command line asks: its ``to_json()`` with ``--json``, else its
    ``table()``; returns the exit status 0."""
    if args.json:
        return emit_json(result.to_json())
    print(result.table())
    return 0


def write_json(path: Any, obj: Any) -> Any:
    """Write ``obj`` to ``path`` as :func:`emit_json` prints it; returns the path.

    Raises
    ------
    kbm.errors.OutputError
        If the file cannot be written (with the reason).
    """
    from ..output.files import write_file

    return write_file(path, strict_text(obj))


#: the built-ins of one degree of freedom, as the model argument's help names them
ONE_DOF = "vdp, rayleigh, sedf, cdc, ..."


def add_model_arguments(parser: argparse.ArgumentParser, models: str = ONE_DOF, *,
                        coupled: bool = False,
                        **changes: Mapping[str, Any]) -> None:
    """Add the model name, ``--rhs`` and ``--omega0`` arguments (``coupled``: ``--rhs`` is
    repeatable, one per degree of freedom, ``--omega0`` takes a comma-separated list, and
    ``--nu0`` is added); ``changes`` as in :func:`add_options`."""
    kw: dict[str, Mapping[str, Any]] = {"model": dict(help=f"built-in model ({models})")}
    if coupled:
        kw["rhs"] = dict(action="append", help=(
            "your own F (in x, xdot and parameters) instead of a built-in model; repeat it "
            "for N coupled degrees of freedom, F_i in x1..xN, xdot1..xdotN"))
        kw["omega0"] = dict(help="linear frequency for --rhs (default 1); comma-separated, one "
                                 "per degree of freedom, for several")
    add_options(parser, "model", "rhs", "omega0", *(("nu0",) if coupled else ()),
                **{**kw, **changes})


def check_model_flags(args: argparse.Namespace) -> None:
    """A model name or ``--rhs`` (not both, not neither); ``--omega0`` only with ``--rhs``.

    Raises
    ------
    kbm.errors.ModelError
        Naming the flags to change.
    """
    rhs = getattr(args, "rhs", None)
    if args.model and rhs:
        raise ModelError("give either a model name or --rhs, not both")
    if not args.model and not rhs:
        raise ModelError("name a model (e.g. vdp) or give --rhs EXPR")
    if args.model and getattr(args, "nu0", None) is not None:
        raise ModelError(f"--nu0 applies to --rhs only; the built-in model {args.model!r} "
                         "has its own forcing frequency")
    if args.model and getattr(args, "omega0", None) is not None:
        raise ModelError(f"--omega0 applies to --rhs only; the built-in model {args.model!r} "
                         "has its own linear frequency (set its parameters with --param)")


def model_spec(args: argparse.Namespace):
    """The model named on the command line (a built-in name) or the user's ``--rhs`` model.

    Raises
    ------
    kbm.errors.ModelError
        If neither or both are given, or ``--omega0`` comes with a model name.
    """
    from ..model.builtins import custom_model

    check_model_flags(args)
    if getattr(args, "rhs", None):
        rhs = args.rhs[0] if isinstance(args.rhs, list) else args.rhs
        return custom_model(rhs, omega0=1 if args.omega0 is None else args.omega0)
    return args.model


def describe_params(model, given: Mapping[str, object], resolved: Mapping[str, object]) -> str:
    """The parameters in the names the user gave, then the derived scaled ones as such.

    ``-p mu=0.1 -p Delta=3 -p beta=1 -p lam=1`` for the SEDF reads ``mu=0.1, Delta=3,
    beta=1, lam=1; derived: delta = Delta/mu = 30, k = 2*pi/lam = 6.28319; default:
    Omega=1`` (the engine works in ``delta``, ``k``; the user wrote ``Delta``, ``lam``).
    """
    import sympy as sp

    from ..model.builtins import get_model

    if isinstance(model, str):
        try:
            model = get_model(model)
        except Exception:  # noqa: BLE001 - a name the caller resolved otherwise
            model = None
    physical = dict(getattr(model, "physical", {}) or {})
    defaults = dict(getattr(model, "defaults", {}) or {})

    def val(v) -> str:
        try:
            return f"{float(v):g}"
        except (TypeError, ValueError):
            return str(v)

    parts = [f"{k}={val(resolved.get(k, v))}" if k in resolved else f"{k}={v}"
             for k, v in given.items()]
    derived = [f"{k} = {sp.sstr(expr)} = {val(resolved[k])}" for k, expr in physical.items()
               if k in resolved and k not in given]
    rest = [f"{k}={val(v)}" for k, v in resolved.items()
            if k not in given and k not in physical]
    text = ", ".join(parts)
    if derived:
        text += "; derived: " + ", ".join(derived)
    if rest:
        names = [r.split("=")[0] for r in rest]
        word = "default" if all(n in defaults for n in names) else "also"
        text += f"; {word}: " + ", ".join(rest)
    return text


def table_cell(x: float, fmt: str) -> str:
    """``x`` in ``fmt``, or ``--`` in its width where it is not a number (the JSON's ``null``:
    a sliding state has no static friction and no slips, a noisy run without slips no slip
    statistics; tables printed ``nan``)."""
    import math

    return format(x, fmt) if math.isfinite(x) else format("--", f">{fmt.split('.')[0]}")
