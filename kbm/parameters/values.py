"""Parameter values and names: exact reading of user input (:func:`parameter_value`), the
read-only mapping models hold (:class:`FrozenMap`), the names a model's values may be given in
(:class:`ParameterNames`: scaled, physical, noise ``D`` or ``T = D/mu``) and the one binding
layer of every model, :func:`scaled_values` (physical names turned into scaled ones)."""

from __future__ import annotations

import difflib
import numbers
from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..errors import NonFiniteError, ParameterError

if TYPE_CHECKING:  # imported on use: FrozenMap is read without sympy (issue 39)
    import sympy as sp

__all__ = ["FrozenMap", "parameter_value", "NOISE_NAMES", "ParameterNames", "closest",
           "scaled_values"]


class FrozenMap(Mapping):
    """A read-only, hashable mapping (items kept in the order given).

    Used for the mappings held by frozen model objects, so that an
    :class:`Oscillator` or a :class:`BoundModel` can be a dictionary key.
    """

    __slots__ = ("_items", "_dict")

    def __init__(self, items: Mapping | None = None):
        d = dict(items or {})
        object.__setattr__(self, "_dict", d)
        object.__setattr__(self, "_items", tuple(d.items()))

    def __getitem__(self, key):
        return self._dict[key]

    def __iter__(self) -> Iterator:
        return iter(self._dict)

    def __len__(self) -> int:
        return len(self._dict)

    def __hash__(self) -> int:
        return hash(frozenset(self._items))

    def __eq__(self, other) -> bool:
        return isinstance(other, Mapping) and dict(self._items) == dict(other.items())

    def __repr__(self) -> str:
        return f"FrozenMap({self._dict!r})"

    def __setattr__(self, name, value):
        raise AttributeError("FrozenMap is read-only")

    def __reduce__(self):
        return (FrozenMap, (self._dict,))


def parameter_value(name: str, raw: object) -> sp.Expr:
    """Read a parameter value exactly: ``"0.1"`` and ``0.1`` both give ``1/10``."""
    import sympy as sp

    from ..symbols import parse

    try:
        if isinstance(raw, numbers.Real) and not isinstance(raw, (int, sp.Basic)):
            raw = float(raw)  # also numpy floats
            val = sp.Rational(repr(raw)) if raw == raw and abs(raw) != float("inf") else sp.nan
        elif isinstance(raw, str):
            try:
                val = sp.Rational(raw.strip())
            except ZeroDivisionError:
                val = sp.nan  # "1/0": refused below as not finite
            except (TypeError, ValueError):
                try:
                    val = parse(raw)
                except NonFiniteError:
                    val = sp.nan  # refused below as not finite
        else:  # numbers and sympy objects only: strict, never through str()
            val = sp.sympify(raw, strict=True)
    except Exception as exc:  # noqa: BLE001 - reported with the name
        raise ParameterError(f"parameter {name}: cannot read the value {raw!r} ({exc})") from None
    if not (isinstance(val, sp.Expr) and val.is_number and val.is_real and val.is_finite):
        raise ParameterError(f"parameter {name} must be a finite real number, got {raw!r}")
    return val


#: the noise intensity ``D`` of ``sqrt(2 D) xi`` and the temperature ``T = D/mu``
NOISE_NAMES = ("D", "T")


def closest(name: str, choices: Iterable[str]) -> str | None:
    """The valid name nearest to a misspelt one (``lamda`` -> ``lam``, ``Mu`` -> ``mu``),
    or ``None`` when none is close."""
    choices = list(choices)
    for c in choices:  # a difference of case only
        if c.lower() == name.lower():
            return c
    near = difflib.get_close_matches(name, choices, n=1, cutoff=0.7)
    return near[0] if near else None


@dataclass(frozen=True)
class ParameterNames:
    """The names a model's values may be given in.

    Attributes
    ----------
    model
        The model's name.
    scaled
        The model's own (scaled) parameters, e.g. ``delta, k, Omega`` of the CDC.
    physical
        ``{scaled: expression in physical names and mu}``, e.g. ``{"delta": Delta/mu}``.
    extra
        Further names the command takes (``v``, the stage velocity of a slider).
    noise
        Whether ``D`` and ``T = D/mu`` are taken.
    """

    model: str
    scaled: tuple[str, ...]
    physical: Mapping[str, sp.Expr]
    extra: tuple[str, ...] = ()
    noise: bool = False

    @property
    def physical_names(self) -> tuple[str, ...]:
        """The physical names (``Delta``, ``lam``), ``mu`` left out."""
        import sympy as sp

        names = {s.name for e in self.physical.values() for s in sp.sympify(e).free_symbols}
        return tuple(sorted(names - {"mu"}))

    @property
    def valid(self) -> tuple[str, ...]:
        """Every valid name: ``mu``, the physical ones, the scaled ones, the command's extra
        ones and the noise ``D``, ``T`` (in that order, each group sorted)."""
        groups = (("mu",), self.physical_names, self.scaled, tuple(sorted(self.extra)),
                  NOISE_NAMES if self.noise else ())
        out: list[str] = []
        for g in groups:
            out += [n for n in g if n not in out]
        return tuple(out)

    def listing(self) -> str:
        """The valid names as a sentence: ``mu, Delta, lam (or the scaled delta = Delta/mu,
        k = 2*pi/lam), Omega, v, D or T = D/mu (noise)``."""
        import sympy as sp

        parts = ["mu"] + list(self.physical_names)
        if self.physical:
            parts[-1] += " (or the scaled " + ", ".join(
                f"{k} = {sp.sstr(sp.sympify(v))}" for k, v in self.physical.items()) + ")"
        parts += [n for n in self.scaled if n not in self.physical and n != "mu"]
        parts += [n for n in sorted(self.extra) if n not in parts and n not in self.scaled]
        if self.noise:
            parts.append("D or T = D/mu (the noise sqrt(2 D) xi)")
        return ", ".join(parts)

    def check(self, names: Iterable[str], *, flag: str = "-p") -> None:
        """Refuse any name that is not valid, with the list of the valid ones.

        Raises
        ------
        kbm.errors.ParameterError
            ``unknown parameter 'Mu' for cdc (did you mean mu?); its parameters are ...``.
        """
        valid = self.valid
        for name in names:
            if name in valid:
                continue
            near = closest(name, valid)
            hint = f" (did you mean {near}?)" if near else ""
            noise = "" if self.noise or name not in NOISE_NAMES else \
                " (this command has no noise)"
            what = (f"cannot vary {name!r}: it is not a parameter of {self.model}"
                    if flag == "--vary" else f"unknown parameter {name!r} for {self.model}")
            raise ParameterError(f"{what}{hint}{noise} (in {flag} {name}=...); its parameters "
                                 f"are {self.listing()}")

    def check_both(self, names: Iterable[str]) -> None:
        """Refuse a scaled name given with the physical ones it is computed from
        (``delta`` with ``Delta``), and ``D`` with ``T``."""
        import sympy as sp

        names = set(names)
        for scaled, expr in self.physical.items():
            phys = {s.name for s in sp.sympify(expr).free_symbols} - {"mu"}
            if scaled in names and phys & names:
                raise ParameterError(f"give either {scaled} or {', '.join(sorted(phys & names))}"
                                     f" ({scaled} = {sp.sstr(sp.sympify(expr))}), not both")
        if {"D", "T"} <= names:
            raise ParameterError("give the noise as D or as T = D/mu, not both")


def scaled_values(model, values: Mapping[str, object] | None = None, *,
                  use_defaults: bool = True) -> dict[str, sp.Expr]:
    """Exact values of a model's own (scaled) parameters and ``mu`` from the given ones: the
    one binding layer of every instance of the model type (its ``resolve``,
    :func:`kbm.parameters.bound.bind`).  The names are checked as a command checks them
    (:meth:`ParameterNames.check`); the physical names are converted by the model's
    ``physical`` map (``delta = Delta/mu``, ``k = 2 pi/lam``; an input may come from the
    defaults), and the defaults are filled in (none of them with ``use_defaults=False``:
    then a scaled parameter none of whose inputs is given is left out).

    Raises
    ------
    kbm.errors.ParameterError
        For an unknown name (the valid ones listed), a value that is not a finite number, a
        scaled and a physical value of the same parameter, a physical one without ``mu``, or
        one at which the scaled value is undefined (``Delta/mu`` at ``mu = 0``).

    Examples
    --------
    >>> from kbm.model.builtins import get_model
    >>> scaled_values(get_model("sedf"), {"mu": "0.1", "Delta": 2, "lam": 1})["delta"]
    20
    """
    import sympy as sp

    values = dict(values or {})
    names = ParameterNames(model.name, tuple(model.parameters), dict(model.physical))
    names.check(values)
    names.check_both(values)  # not delta with Delta
    given = {k: parameter_value(k, v) for k, v in values.items()}
    for scaled, expr in model.physical.items():  # e.g. delta = Delta/mu from Delta and mu
        needs = {s.name for s in expr.free_symbols}
        inputs = needs - {"mu"}
        if scaled in given:
            continue
        defaults = model.defaults if use_defaults else {}
        if not inputs or not inputs <= set(given) | set(defaults):
            continue
        vals = {n: given.get(n, defaults.get(n)) for n in sorted(needs)}
        missing = [n for n, v in vals.items() if v is None]
        if missing:
            raise ParameterError(f"{scaled} = {expr} needs a value of {', '.join(missing)} "
                                 f"(-p {missing[0]}=VALUE)")
        value = sp.sympify(expr).subs({sp.Symbol(n): v for n, v in vals.items()})
        if not (value.is_finite and value.is_real):
            zero = [n for n, v in vals.items() if v == 0]
            raise ParameterError(f"{scaled} = {expr} is undefined for "
                                 + ", ".join(f"{n} = {v}" for n, v in vals.items())
                                 + (f": give {' and '.join(zero)} != 0" if zero else ""))
        given[scaled] = value
    own = set(model.parameters) | {"mu"}
    out = {k: v for k, v in given.items() if k in own}
    if use_defaults:
        for name, v in model.defaults.items():
            if name in own:
                out.setdefault(name, sp.sympify(v))
    return out
