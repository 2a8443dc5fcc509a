"""A model bound to its parameter values: :class:`BoundModel` and :func:`bind`.

The parameter values of a computation are read, converted (physical to scaled
names) and validated once, at the boundary of the library, into a hashable
object that every numerical function takes.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import sympy as sp

from .errors import ParameterError
from .models import Oscillator, _drive_variant, get_model
from .values import FrozenMap

__all__ = ["BoundModel", "bind"]


@dataclass(frozen=True)
class BoundModel:
    """A model with its parameter values resolved and validated once.

    Created at the boundary of the library (:func:`bind`, :meth:`Oscillator.bind`)
    and passed to every numerical function, so that a parameter set is read once,
    has an identity (it is hashable) and prints the same way everywhere.

    Attributes
    ----------
    model
        The :class:`Oscillator` (symbolic; its drive holds a stage velocity).
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

    model: Oscillator
    values: FrozenMap

    @classmethod
    def of(cls, model: Oscillator, values: Mapping[str, object] | None = None) -> "BoundModel":
        """Resolve ``values`` for ``model`` (:meth:`Oscillator.resolve`)."""
        vals = model.resolve(values)
        w0 = sp.sympify(model.omega0).subs({sp.Symbol(k): v for k, v in vals.items()})
        if w0.is_number and not (w0.is_real and w0.is_finite and w0 > 0):
            raise ParameterError(f"the linear frequency omega0 = {model.omega0} of "
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
            raise ParameterError(f"model {self.name!r} needs values for {', '.join(miss)} "
                                 f"(e.g. params={{{miss[0]!r}: 0.1}}) for {what}")
        return self

    def subs(self) -> dict[sp.Symbol, sp.Expr]:
        """``{Symbol(name): value}`` for substitution into the model's expressions."""
        return {sp.Symbol(k): v for k, v in self.values.items()}


def bind(model: "Oscillator | str | BoundModel", params: Mapping[str, object] | None = None,
         ) -> BoundModel:
    """A :class:`BoundModel` from a model (or built-in name) and parameter values.

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
        v = params.pop("v", None)
        model = get_model(model, None if v is None else {"v": v})
    elif "v" in params and "v" not in model.parameters:
        model = _drive_variant(model, params.pop("v"))
    return BoundModel.of(model, params)
