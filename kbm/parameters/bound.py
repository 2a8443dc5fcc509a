"""A model bound to its parameter values: :class:`BoundModel` and :func:`bind`.

The parameter values of a computation are read, converted (physical to scaled
names) and validated once, at the boundary of the library, into a hashable
object that every numerical function takes.
"""

from __future__ import annotations

import functools
from collections.abc import Mapping
from dataclasses import dataclass
from fractions import Fraction
from typing import TYPE_CHECKING

import sympy as sp

from ..errors import ParameterError
from ..model.builtins import MODELS, Oscillator, _drive_variant, get_model
from .rational_values import line_floats, line_rates, rational_tree, tree_value
from .values import FrozenMap, parameter_value

if TYPE_CHECKING:  # the coupled package imports this module
    from ..model.coupled import CoupledOscillators

__all__ = ["BoundModel", "ParameterLine", "bind"]


@dataclass(frozen=True)
class BoundModel:
    """A model with its parameter values resolved and validated once.

    Created at the boundary of the library (:func:`bind`, :meth:`BoundModel.of`)
    and passed to every numerical function, so that a parameter set is read once,
    has an identity (it is hashable) and prints the same way everywhere.

    Attributes
    ----------
    model
        An instance of the one model type :class:`kbm.model.coupled.CoupledOscillators`: an
        :class:`Oscillator` (its drive may hold a stage velocity), a
        :class:`kbm.model.forced.ForcedOscillator` or a
        :class:`kbm.model.coupled.CoupledOscillators` (``bind("coupled-vdp", ...)``).
    values
        Exact values by name: the model's own (scaled) parameters, ``mu`` when
        given, and the defaults (:meth:`Oscillator.resolve`).

    Examples
    --------
    >>> b = bind("sedf", {"mu": "0.1", "Delta": 1.5, "beta": 1, "lam": 1})
    >>> b.floats["delta"], b.mu
    (15.0, 0.1)
    >>> hash(b) == hash(bind("sedf", {"mu": 0.1, "delta": 15, "beta": 1, "lam": 1}))
    True
    """

    model: "CoupledOscillators"
    values: FrozenMap

    @classmethod
    def of(cls, model: "CoupledOscillators", values: Mapping[str, object] | None = None
           ) -> "BoundModel":
        """Resolve ``values`` for ``model`` (its ``resolve``: physical names converted,
        defaults filled in)."""
        vals = model.resolve(values)
        for w in model.omegas:  # a frequency named by a parameter (the sliders' Omega)
            w0 = sp.sympify(w).subs({sp.Symbol(k): v for k, v in vals.items()})
            if w0.is_number and not (w0.is_real and w0.is_finite and w0 > 0):
                raise ParameterError(f"the linear frequency omega0 = {w} of "
                                     f"{model.name!r} must be > 0, got {w0}")
        return cls(model, FrozenMap(vals))

    @property
    def name(self) -> str:
        """The model's name."""
        return self.model.name

    @property
    def floats(self) -> dict[str, float]:
        """The values as floats."""
        return {k: float(v) for k, v in self.values.items()}

    @property
    def mu(self) -> float | None:
        """The small parameter, or ``None`` if it was not given."""
        return float(self.values["mu"]) if "mu" in self.values else None

    def missing(self, names=None) -> list[str]:
        """Names among ``names`` (default: the model's parameters and ``mu``) without a value."""
        names = (*self.model.parameters, "mu") if names is None else names
        return [n for n in names if n not in self.values]

    def require(self, names=None, *, what: str = "this computation") -> "BoundModel":
        """Raise :class:`ParameterError` naming what is missing; returns ``self``."""
        miss = self.missing(names)
        if miss:
            asked = [_physical_name(self.model, n) for n in miss]
            forms = [f"{n} = {sp.sstr(sp.sympify(self.model.physical[n]))}" for n in miss
                     if n in (getattr(self.model, "physical", None) or {})]
            example = ", ".join(f"{n!r}: 1" if n != "mu" else f"{n!r}: 0.1"
                                for n in dict.fromkeys(asked))
            raise ParameterError(f"model {self.name!r} needs values for "
                                 f"{', '.join(dict.fromkeys(asked))}"
                                 + f" ({'; '.join(forms + [''])}e.g. params={{{example}}})"
                                 f" for {what}")
        return self

    def subs(self) -> dict[sp.Symbol, sp.Expr]:
        """``{Symbol(name): value}`` for substitution into the model's expressions."""
        return {sp.Symbol(k): v for k, v in self.values.items()}


def bind(model: "CoupledOscillators | str | BoundModel",
         params: Mapping[str, object] | None = None) -> BoundModel:
    """A :class:`BoundModel` from a model (or built-in name) and parameter values.

    Every instance of the one model type binds here, as it is: a one-degree-of-freedom
    model, a forced one, a coupled system (a built-in name of
    :mod:`kbm.model.coupled_builtins` gives its
    :class:`~kbm.model.coupled.CoupledOscillators`); the physical names are turned into the
    scaled ones by the model's ``resolve`` (:func:`kbm.parameters.values.scaled_values` for the
    general type).

    A stage velocity ``v`` among ``params`` (sliders ``sedf``, ``cdc``) selects the
    driven variant (:meth:`Oscillator.with_stage_velocity`).  A model that is
    already bound is returned as is (then ``params`` must be empty).

    Raises
    ------
    kbm.errors.ParameterError
        For unknown names or values that are not finite real numbers.
    """
    if isinstance(model, BoundModel):
        if params:
            raise ParameterError("the model is already bound to parameter values; pass "
                                 "params=None")
        return model
    params = dict(params or {})
    if isinstance(model, str):
        if model not in MODELS:  # a one-degree-of-freedom name first: the others import slowly
            from .names import builtin_model

            found = builtin_model(model)
            if found is not None:
                return BoundModel.of(found, params)
        v = params.pop("v", None)
        model = get_model(model, None if v is None else {"v": v})
    elif isinstance(model, Oscillator) and "v" in params and "v" not in model.parameters:
        model = _drive_variant(model, params.pop("v"))
    return BoundModel.of(model, params)


class ParameterLine:
    """One model bound along one parameter: ``line(p)`` is ``bind(model, {**params, vary: p})``.

    A continuation binds the model at every value of the varied parameter it tries
    (thousands on one branch).  :func:`bind` reads the model and all its values
    each time; a line reads them once, and per value only replaces what depends on
    ``vary``: its own entry (a parameter of the model, or ``mu``) and the scaled
    parameters computed from it (``delta = Delta/mu`` when ``Delta`` or ``mu`` is
    varied and the physical name was given).  The result equals :func:`bind`'s (a
    test compares them); a stage velocity ``v``, which changes the model itself,
    goes through :func:`bind` every time.

    Parameters
    ----------
    model
        An :class:`Oscillator` or a built-in name.
    params
        The other values; ``vary`` may be among them (it is replaced).
    vary
        The parameter that varies (scaled, physical or ``mu``).
    at
        A value of ``vary`` at which the model can be bound (checks the names once).

    Examples
    --------
    >>> line = ParameterLine("sedf", {"mu": 0.1, "beta": 1, "lam": 1}, "Delta", 1.5)
    >>> line(3.0) == bind("sedf", {"mu": 0.1, "beta": 1, "lam": 1, "Delta": 3.0})
    True
    """

    def __init__(self, model: "Oscillator | str", params: Mapping[str, object] | None,
                 vary: str, at: float):
        self.model, self.vary = model, vary
        self.params = dict(params or {})  # the order of bind's values is kept
        base = bind(model, {**self.params, vary: at})
        self.base = base
        m = base.model
        self._slow = vary == "v" or isinstance(model, BoundModel)
        given = {k: parameter_value(k, v) for k, v in self.params.items()
                 if k not in ("v", vary)}
        self._given = given
        self._direct = vary in m.parameters or vary == "mu"
        self._derived: list[tuple[str, sp.Expr, tuple[str, ...]]] = []
        for scaled, expr in m.physical.items():
            expr = sp.sympify(expr)
            need = tuple(sorted(s.name for s in expr.free_symbols))
            names = set(given) | {vary}
            if vary in need and scaled not in given and set(need) & names - {"mu"} \
                    and set(need) <= names:
                self._derived.append((scaled, expr, need))
        #: the names whose values change with ``vary``
        self.changed = tuple(([vary] if self._direct else [])
                             + [d[0] for d in self._derived])
        # exact rational arithmetic without sympy, where every value and expression allows it
        w0 = sp.sympify(m.omega0)
        self._w0 = w0 if w0.free_symbols & set(map(sp.Symbol, self.changed)) else None
        exact = [e for _, e, _ in self._derived] + ([w0] if self._w0 is not None else [])
        needed = {s.name for e in exact for s in e.free_symbols} - {vary}
        known = {**self.base.values, **given}
        trees = [rational_tree(e) for e in exact]
        self._fractions = None
        #: ``(scaled, tree)`` of the derived values
        #: (:func:`kbm.parameters.rational_values.rational_tree`) where :meth:`floats` computes
        #: them exactly without sympy, and the linear frequency's
        self._trees, self._w0_tree = [], None
        if not self._slow and all(t is not None for t in trees) and \
                all(isinstance(known.get(n), sp.Rational) for n in needed):
            self._fractions = {n: Fraction(int(known[n].p), int(known[n].q)) for n in needed}
            self._trees = [(scaled, t) for (scaled, _, _), t in zip(self._derived, trees)]
            self._w0_tree = trees[-1] if self._w0 is not None else None
        sym = sp.Symbol(vary)
        self._rates = [(scaled, sp.lambdify([sp.Symbol(n) for n in need],
                                            sp.diff(expr, sym), "math"), need)
                       for scaled, expr, need in self._derived]

    @functools.cached_property
    def affine(self) -> bool:
        """Whether every value that changes is affine in ``vary`` (``delta = Delta/mu`` in
        ``Delta``, not in ``mu``), with constant :meth:`rates`, and the linear frequency
        does not change: the values at ``p`` are then those at a reference point plus
        ``(p - p_ref)`` times the rates (a compiled continuation uses it)."""
        if self._slow or self._w0 is not None:
            return False
        sym = sp.Symbol(self.vary)
        return all(sp.diff(expr, sym, 2) == 0 for _, expr, _ in self._derived)

    def floats(self, value: float) -> dict[str, float] | None:
        """The float values of the names in :attr:`changed` at ``vary = value``, equal to
        ``float`` of :meth:`__call__`'s exact values, or ``None`` where that needs sympy.

        Where every value is rational and every derived expression a rational function with
        rational coefficients (``delta = Delta/mu``), the exact values are computed with
        :class:`fractions.Fraction` (correctly rounded to float, as sympy's): a continuation
        evaluates this thousands of times.

        Raises
        ------
        kbm.errors.ParameterError
            As :meth:`__call__`: a value that is not finite, a derived value that is
            undefined, a linear frequency that is not positive.
        """
        if self._fractions is None:
            return None
        exprs = {scaled: expr for scaled, expr, _ in self._derived}

        def undefined(scaled: str):
            raise ParameterError(f"{scaled} = {exprs[scaled]} is undefined for {self.vary} = "
                                 f"{value}") from None

        out, env = line_floats(self.vary, value, self._fractions, self._direct, self._trees,
                               undefined)
        if self._w0 is not None:
            try:
                ok = tree_value(self._w0_tree, env) > 0
            except ZeroDivisionError:
                ok = False
            if not ok:
                self(value)  # raises the exact path's message
        return out

    def rates(self, value: float) -> dict[str, float]:
        """``d(value)/d(vary)`` of each name in :attr:`changed` at ``vary = value`` (floats):
        1 for ``vary`` itself, the derivative of a derived expression (``delta = Delta/mu``
        gives ``1/mu`` in ``Delta``).  For the parameter sensitivities of a flow.

        Raises
        ------
        kbm.errors.ParameterError
            If ``vary`` changes the model itself (a stage velocity).
        """
        if self._slow:
            raise ParameterError(f"{self.vary} changes the model itself; its rates are not "
                                 "those of parameter values")
        return line_rates(self.vary, value, {k: float(v) for k, v in self._given.items()},
                          self._direct, self._rates)

    def __call__(self, value: float) -> BoundModel:
        """The model bound with ``vary = value`` (the other values as given)."""
        if self._slow:
            return bind(self.model, {**self.params, self.vary: value})
        val = parameter_value(self.vary, value)
        vals = dict(self.base.values)
        if self._direct:
            vals[self.vary] = val
        env = {**self._given, self.vary: val}
        for scaled, expr, need in self._derived:
            new = expr.xreplace({sp.Symbol(n): env[n] for n in need})  # exact, as bind's
            if not (new.is_finite and new.is_real):
                raise ParameterError(f"{scaled} = {expr} is undefined for {self.vary} = {value}")
            vals[scaled] = new
        w0 = sp.sympify(self.base.model.omega0)
        if w0.free_symbols:
            w0 = w0.xreplace({sp.Symbol(k): v for k, v in vals.items()})
            if w0.is_number and not (w0.is_real and w0.is_finite and w0 > 0):
                raise ParameterError(f"the linear frequency omega0 = {self.base.model.omega0} "
                                     f"of {self.base.name!r} must be > 0, got {w0}")
        return BoundModel(self.base.model, FrozenMap(vals))


def _physical_name(model, name: str) -> str:
    """The physical name a scaled parameter is given by (``delta = Delta/mu`` -> ``Delta``),
    else the name itself."""
    expr = (getattr(model, "physical", None) or {}).get(name)
    if expr is None:
        return name
    inputs = sorted(s.name for s in sp.sympify(expr).free_symbols if s.name != "mu")
    return inputs[0] if len(inputs) == 1 else name
