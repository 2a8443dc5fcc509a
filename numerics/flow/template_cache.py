"""An on-disk cache of the model templates' numerical functions (issue 39).

Building a :class:`numerics.flow.compiled.ModelTemplate` differentiates the model and
lambdifies seven functions; lambdify alone imports :mod:`scipy.special` for its namespace
(0.7 s) and prints the code.  The printed code is a fixed function of the model, so it is
kept on disk: a record holds each function's source (the code ``sympy.lambdify``
generated) and the module attribute behind every global name it uses (``math.sin``,
``numpy.sqrt``, ``scipy.special.jv``), with the parameters' order and the template's
expressions (``srepr``).  A later process imports only the modules named and runs the same
code.

The record's name is the SHA-256 of the model's canonical form (every field of the model,
expressions by ``srepr``, mappings sorted) and of what decides the code: the record
format, the versions of kbm and sympy, and the source of the modules that build the
template (:func:`template_key`).  A record that cannot be read, names another key, or
holds a name that does not resolve is rebuilt, never trusted.

The cache changes the time, never the result: the cold run builds the record and then
uses the functions made from it exactly as a warm run does (:func:`cached_template`), so
both run the same code with the same globals.  Functions whose globals are not module
attributes or numbers are not stored, and the template is used as built.  The folder is
:func:`numerics.flow.numba_cache.cache_dir` (``$KBM_CACHE_DIR``), the folder of the compiled flows.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import linecache
import os
import re
import types
from collections.abc import Callable, Mapping
from importlib import import_module
from pathlib import Path
from typing import Any, TypeVar

#: the template type (:class:`numerics.flow.compiled.ModelTemplate`, passed in by its
#: module: imported here, it would close a circle of imports)
Template = TypeVar("Template")

__all__ = ["template_key", "cached_template", "template_record", "template_from_record",
           "function_record", "function_from_record", "read_record", "write_record",
           "update_record", "FORMAT"]

#: version of the record's layout (part of the key)
FORMAT = "1"

#: the modules a stored function's globals may come from, searched in this order
_MODULES = ("math", "cmath", "builtins", "numpy", "scipy.special", "mpmath")

#: the callables of a template, in its field order
_FUNCTIONS = ("f_ext", "f_acc", "f_jac", "f_energy", "f_w0", "f_factor")

#: the source files whose code decides the template (part of the key)
_BUILDERS = ("template.py", "template_cache.py")


def _canonical(value: object) -> str:
    """A text that determines ``value``: ``srepr`` for sympy objects, sorted items for
    mappings, the canonical forms of a sequence's items, else ``repr``."""
    if isinstance(value, Mapping):
        return "{" + ",".join(f"{k!r}:{_canonical(v)}"
                              for k, v in sorted(value.items(), key=lambda kv: str(kv[0]))) + "}"
    if isinstance(value, (tuple, list)):
        return "(" + ",".join(_canonical(v) for v in value) + ")"
    if type(value).__module__.startswith("sympy"):
        from sympy import srepr

        return srepr(value)
    return repr(value)


def model_form(model: object) -> str:
    """The canonical form of a model (a dataclass): its type and each field's canonical
    text, in field order."""
    fields = [(f.name, _canonical(getattr(model, f.name)))
              for f in dataclasses.fields(model)]  # type: ignore[arg-type]
    return f"{type(model).__module__}.{type(model).__qualname__}" + repr(fields)


def _versions() -> str:
    """The versions and builder sources that decide the generated code."""
    import sympy

    from kbm._version import __version__

    here = Path(__file__).parent
    code = hashlib.sha256(b"".join((here / n).read_bytes() for n in _BUILDERS)).hexdigest()
    return f"{FORMAT}|kbm {__version__}|sympy {sympy.__version__}|{code}"


def template_key(model: object, options: str = "") -> str:
    """The name of a model's record: the SHA-256 of its canonical form (:func:`model_form`),
    of the compilation's ``options`` and of :func:`_versions` (format, kbm and sympy
    versions, the builders' source)."""
    text = f"{_versions()}|{options}|{model_form(model)}"
    return hashlib.sha256(text.encode()).hexdigest()[:32]


def _code_names(code: types.CodeType) -> set[str]:
    names = set(code.co_names)
    for c in code.co_consts:
        if isinstance(c, types.CodeType):
            names |= _code_names(c)
    return names


def _where(value: object) -> list[str] | None:
    """``[module, attribute]`` of a global, ``["number", repr]`` for a float or int, or
    ``None`` when it is neither (then the function is not stored)."""
    if isinstance(value, types.ModuleType):
        return ["module", value.__name__]
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return ["number", repr(value)]
    name = getattr(value, "__name__", None)
    if not isinstance(name, str):
        return None
    for mod in _MODULES:
        try:
            if getattr(import_module(mod), name, None) is value:
                return [mod, name]
        except ImportError:
            continue
    return None


def function_record(fn: Callable) -> dict | None:
    """The source and globals of a lambdified function, or ``None`` if it cannot be stored."""
    code = getattr(fn, "__code__", None)
    if code is None or not code.co_filename.startswith("<lambdifygenerated"):
        return None
    source = "".join(linecache.getlines(code.co_filename))
    if not source:
        return None
    # lambdify names the unpacked arguments ``_Dummy_N`` by a counter of the process:
    # numbered in order of appearance, the record is the same bytes in every process
    order: dict[str, str] = {}
    source = re.sub(r"\b_Dummy_\d+\b",
                    lambda m: order.setdefault(m.group(), f"_Dummy_{len(order)}"), source)
    names = {}
    for n in sorted(_code_names(code)):
        if n in fn.__globals__:
            where = _where(fn.__globals__[n])
            if where is None:
                return None
            names[n] = where
    return {"name": code.co_name, "source": source, "globals": names}


#: modules whose import costs more than a warm command's work (mpmath 0.1-0.2 s with gmpy2,
#: scipy.special 0.2-0.4 s): a function that needs one is made on its first call
_HEAVY = ("mpmath", "scipy.special")


def lambdify_light(args: Any, expr: Any, modules: list[str]) -> Callable:
    """:func:`sympy.lambdify` with the rationals printed as floats (``1/2``, not
    ``mpf(1)/mpf(2)``) where the function then needs nothing of :mod:`mpmath` (``modules``
    holds it for a user's ``hyper``), else lambdify's own function: a stored energy of a
    built-in model imports no mpmath (0.1 s of a warm ``kbm branch``, issue 39).

    The same numbers: a quotient of integers below ``2**53`` is the correctly rounded one
    either way (mpmath's default precision is the double's 53 bits, rounded to nearest),
    and so is each operation on it; larger integers keep mpmath's form, and so does a power
    with a fractional exponent (mpmath's power is not the C library's).
    """
    import sympy as sp
    from sympy.printing.pycode import MpmathPrinter

    class FloatRationalPrinter(MpmathPrinter):
        exact = 0  # inside a power with a fractional exponent: mpmath's numbers

        def _print_Rational(self, e):
            if not self.exact and max(abs(int(e.p)), int(e.q)) < 2**53:
                return f"{int(e.p)}/{int(e.q)}"
            return super()._print_Rational(e)

        _print_Half = _print_Rational

        def _print_Pow(self, expr, rational=False):
            fractional = expr.exp.is_Rational and not expr.exp.is_Integer
            self.exact += fractional
            try:
                return super()._print_Pow(expr, rational=rational)
            finally:
                self.exact -= fractional

    printer = FloatRationalPrinter({"fully_qualified_modules": False, "inline": True,
                                    "allow_unknown_functions": True, "user_functions": {}})
    fn = sp.lambdify(args, expr, modules=modules, printer=printer)
    glob = fn.__globals__
    found = [_where(glob[n]) for n in _code_names(fn.__code__) if n in glob]
    if any(w is None or "mpmath" in w for w in found):
        return sp.lambdify(args, expr, modules=modules)
    return fn


def function_from_record(rec: Mapping) -> Callable:
    """The function of a record (raises on anything that does not resolve).

    Where a global comes from a module of :data:`_HEAVY` that is not imported yet (SEDF's
    energy holds ``mpf(1)/mpf(2)``), the function is made on its first call (the same
    code, the same globals; the module must exist): a process that never calls it never
    imports the module (issue 39).
    """
    import sys

    heavy = {kind for kind, _ in rec["globals"].values()
             if kind in _HEAVY and kind not in sys.modules}
    if heavy:
        from importlib.util import find_spec

        for mod in sorted(heavy):
            if find_spec(mod) is None:
                raise ImportError(f"no module {mod!r} for a stored function")
        made: list = []

        def on_call(*args):
            if not made:
                made.append(_function_now(rec))
            return made[0](*args)
        return on_call
    return _function_now(rec)


def _function_now(rec: Mapping) -> Callable:
    """:func:`function_from_record`, the globals imported now."""
    namespace: dict = {}
    for n, (kind, what) in rec["globals"].items():
        if kind == "module":
            namespace[n] = import_module(what)
        elif kind == "number":
            try:
                namespace[n] = int(what)
            except ValueError:
                namespace[n] = float(what)
        else:
            namespace[n] = getattr(import_module(kind), what)
    exec(compile(rec["source"], f"<kbm-template {rec['name']}>", "exec"), namespace)  # noqa: S102
    return namespace[rec["name"]]


def template_record(template: Any, key: str) -> dict | None:
    """The record of ``template`` under ``key``, or ``None`` if a function cannot be stored."""
    from sympy import srepr

    funcs = {}
    for f in _FUNCTIONS:
        rec = function_record(getattr(template, f))
        if rec is None:
            return None
        funcs[f] = rec
    return {"format": FORMAT, "key": key, "names": list(template.names), "functions": funcs,
            "dissipation_expr": srepr(template.dissipation_expr),
            "ext_exprs": [srepr(e) for e in template.ext_exprs],
            "ext_symbols": [srepr(s) for s in template.ext_symbols]}


def template_from_record(model: object, record: Mapping,
                         template_type: type[Template]) -> Template:
    """The template (a ``template_type``, :class:`numerics.flow.compiled.ModelTemplate`) of
    ``model`` from its record (raises if the record is malformed)."""
    import sympy

    ns = vars(sympy)

    def expr(text: str):
        return eval(text, dict(ns))  # noqa: S307 - srepr written by this module

    return template_type(
        model=model, names=tuple(record["names"]),
        **{f: function_from_record(record["functions"][f]) for f in _FUNCTIONS},
        dissipation_expr=expr(record["dissipation_expr"]),
        ext_exprs=tuple(expr(e) for e in record["ext_exprs"]),
        ext_symbols=tuple(expr(s) for s in record["ext_symbols"]))


def _path(key: str, kind: str = "template") -> Path:
    from numerics.flow.numba_cache import cache_dir

    return cache_dir() / f"kbm_{kind}_{key}.json"


def read_record(key: str, kind: str = "template") -> dict | None:
    """The stored record of ``key`` (a record of ``kind``: ``template``, the first-order
    guess's ``rates``, ...), or ``None`` (missing, unreadable, another key or format)."""
    try:
        record = json.loads(_path(key, kind).read_text())
    except (OSError, ValueError):
        return None
    if not isinstance(record, dict) or record.get("format") != FORMAT or record.get("key") != key:
        return None
    return record


def write_record(key: str, record: Mapping, kind: str = "template") -> None:
    """Store ``record`` under ``key`` (atomically; an unwritable cache costs time only)."""
    path = _path(key, kind)
    try:
        tmp = path.with_suffix(f".{os.getpid()}.tmp")
        tmp.write_text(json.dumps(record, sort_keys=True, indent=1))
        os.replace(tmp, path)
    except OSError:
        pass  # an unwritable cache costs time only


def update_record(key: str | None, more: Mapping, kind: str = "template",
                  valid: Callable[[dict], bool] | None = None) -> None:
    """Add the entries ``more`` to the stored record of ``key`` (nothing where there is
    none, or where ``valid`` refuses it: another layout)."""
    record = None if key is None else read_record(key, kind)
    if record is not None and (valid is None or valid(record)):
        write_record(key, {**record, **more}, kind)


def cached_template(model: object, build: Callable[[object], Template],
                    template_type: type[Template]) -> Template:
    """The template of ``model``: from its record when one is stored under its key, else
    ``build(model)`` stored and read back (so a cold and a warm run use the same code);
    ``template_type`` makes it from the record (:class:`numerics.flow.compiled.ModelTemplate`).

    A stored record that is malformed or does not resolve is rebuilt and replaced.
    """
    try:
        key = template_key(model)
    except TypeError:  # not a dataclass: no canonical form, so nothing is stored
        return build(model)
    record = read_record(key)
    if record is not None:
        try:
            return template_from_record(model, record, template_type)
        except Exception:  # noqa: BLE001 - a damaged record is rebuilt, never trusted
            pass
    built = build(model)
    record = template_record(built, key)
    if record is None:
        return built
    record = json.loads(json.dumps(record))  # the record as it is read back
    template = template_from_record(model, record, template_type)
    write_record(key, record)
    return template
