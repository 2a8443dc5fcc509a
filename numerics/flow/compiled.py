"""Turn a symbolic :class:`kbm.Oscillator` into numerical functions, once per computation.

The model is defined once, in :mod:`kbm`; here its acceleration
``x'' = -omega0^2 x + mu F(x, x') + drive(t)`` is differentiated symbolically
(Jacobian, divergence) and lambdified together with the dissipation integrand
and the potential energy, for given parameter values.

The template (:class:`~numerics.flow.template.ModelTemplate`,
:func:`~numerics.flow.template.model_template`) lives in :mod:`numerics.flow.template`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cached_property
from typing import TYPE_CHECKING, Callable

import numpy as np

from kbm.errors import ParameterError

from numerics.flow.template import ModelTemplate, model_template

if TYPE_CHECKING:  # sympy and the symbolic models imported on use (issue 39)
    import sympy as sp

    from kbm.parameters.bound import BoundModel
    from kbm.model.builtins import Oscillator

__all__ = ["CompiledLine", "CompiledModel", "compile_model", "extended_state"]


def extended_state(x0: float, v0: float = 0.0) -> list[float]:
    """The extended initial state at ``(x0, v0)``: identity fundamental matrix, zero integrals."""
    return [float(x0), float(v0), 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0]


@dataclass(frozen=True)
class CompiledModel:
    """Numerical functions of one model at fixed parameter values.

    Attributes
    ----------
    name, values
        The model's name and every parameter value used (floats, incl. ``mu``).
    acc
        ``acc(t, x, v)``: the acceleration (scalar, :mod:`math` speed).
    rhs
        ``rhs(t, y)`` for ``y = (x, v)``.
    rhs_ext
        ``rhs_ext(t, y)`` for ``y = (x, v, Phi11, Phi21, Phi12, Phi22, int div f,
        G_plus, G_minus)``: the state, its variational equations (fundamental
        matrix ``Phi``), the divergence and the two parts of the dissipation.
    jac
        ``jac(t, y)``: the 2x2 Jacobian of ``rhs`` (for implicit methods).
    energy
        ``energy(x, v)`` = ``v^2/2 + U(x)`` (vectorised), with
        ``U = omega0^2 x^2/2 - int_0^x (conservative part of mu F) dx``.
    plus_factor
        ``Gamma = plus_factor * G_plus - G_minus`` (the paper's eq. 11 has
        ``plus_factor = beta``; 1 for models without it).
    stiffness
        ``stiffness(x, v)``: the largest modulus of the Jacobian's eigenvalues.
    autonomous
        Whether the model has no explicit time dependence.
    template, pvec
        The :class:`ModelTemplate` and the parameter values in its order
        (``template.names``), for :func:`template_flow`.
    exact_values
        The parameter values as given (exact where they were exact; a property).
    bound
        The :class:`kbm.parameters.bound.BoundModel` these functions evaluate (a property: a
        continuation along a parameter binds it only when asked).
    acceleration_expr, dissipation_expr
        Symbolic acceleration and dissipation integrand at these values (properties).
    """

    name: str
    values: Mapping[str, float]
    omega0: float
    acc: Callable
    rhs: Callable
    rhs_ext: Callable
    jac: Callable
    energy: Callable
    plus_factor: float
    stiffness: Callable
    autonomous: bool
    template: ModelTemplate
    pvec: tuple[float, ...]
    binding: Callable[[], BoundModel] = field(repr=False, compare=False)

    @cached_property
    def bound(self) -> BoundModel:
        """The :class:`kbm.parameters.bound.BoundModel` these functions evaluate."""
        return self.binding()

    @property
    def exact_values(self) -> Mapping[str, object]:
        """The parameter values as given (exact where they were exact)."""
        return dict(self.bound.values)

    @property
    def acceleration_expr(self) -> sp.Expr:
        """The acceleration at these parameter values, symbolic in ``t, x, x'``."""
        return self.template.model.acceleration().subs(self._subs())

    @property
    def dissipation_expr(self) -> sp.Expr:
        """The integrand of the dissipation ``Gamma`` at these parameter values."""
        return self.template.dissipation_expr.subs(self._subs())

    def _subs(self) -> dict:
        import sympy as sp

        return {sp.Symbol(k): v for k, v in self.exact_values.items()}


def compile_model(model: Oscillator | str | BoundModel,
                  params: Mapping[str, object] | None = None, *,
                  template: ModelTemplate | None = None) -> CompiledModel:
    """Numerical functions of ``model`` at the given parameter values (physical or scaled names).

    Parameters
    ----------
    model, params
        A bound model, or a model (or built-in name) and its parameter values
        (:func:`kbm.parameters.bound.bind`).
    template
        A :class:`ModelTemplate` of the same model, to skip the lambdification.

    Raises
    ------
    kbm.errors.ParameterError
        If a parameter is missing or not a finite real number.
    """
    from kbm.parameters.bound import bind

    bound = bind(model, params)
    model = bound.model
    if template is None or template.model != model:
        template = model_template(model)
    vals = bound.values
    bound.require(template.names, what="the numerical functions")
    fvals = {k: float(vals[k]) for k in template.names}
    return _assemble(lambda: bound, bound.model.name, template, fvals, model.is_autonomous)


def _assemble(binding: Callable[[], BoundModel], name: str, template: ModelTemplate,
              fvals: dict[str, float], autonomous: bool) -> CompiledModel:
    """The :class:`CompiledModel` of ``binding()`` from its template and float values."""
    for k, val in fvals.items():
        if not np.isfinite(val):
            raise ParameterError(f"parameter {k} = {val} is not finite")
    pv = tuple(fvals[k] for k in template.names)
    f_ext, f_acc, f_jac, f_en = template.f_ext, template.f_acc, template.f_jac, template.f_energy

    def rhs(t, yy):
        return [yy[1], f_acc(t, yy[0], yy[1], *pv)]

    def rhs_ext(t, yy):
        return f_ext(t, yy, *pv)

    def acc(t, xx, vv):
        return f_acc(t, xx, vv, *pv)

    def jac(t, yy):
        return np.array(f_jac(t, yy[0], yy[1], *pv), dtype=float)

    def stiffness(xv, vv):
        J = np.array(f_jac(0.0, xv, vv, *pv), dtype=float)
        # J = [[0, 1], [a, b]]: eigenvalues (b +- sqrt(b^2 + 4a))/2
        a, b = float(J[1, 0]), float(J[1, 1])
        disc = b * b + 4.0 * a
        if not math.isfinite(disc):
            return float(np.max(np.abs(np.linalg.eigvals(J))))  # raises for a non-finite J
        if disc < 0:
            return math.sqrt(-a)  # a complex pair: |lambda|^2 = det J = -a
        r = math.sqrt(disc)
        return 0.5 * max(abs(b + r), abs(b - r))

    return CompiledModel(
        name=name, values=fvals, omega0=float(template.f_w0(*pv)), acc=acc,
        rhs=rhs, rhs_ext=rhs_ext, jac=jac,
        energy=lambda xv, vv: np.asarray(f_en(xv, vv, *pv), dtype=float),
        plus_factor=float(template.f_factor(*pv)), stiffness=stiffness,
        autonomous=autonomous, template=template, pvec=pv, binding=binding)


class CompiledLine:
    """:func:`compile_model` along one parameter: ``line(p)`` equals
    ``compile_model(model, {**params, vary: p})``.

    The model is bound (:class:`kbm.parameters.bound.ParameterLine`), lambdified and checked once;
    per value only the entries that depend on ``vary`` are converted, which a
    continuation does thousands of times.

    Examples
    --------
    >>> line = CompiledLine("sedf", {"mu": 0.1, "beta": 1, "lam": 1}, "Delta", 1.5)
    >>> line(3.0).pvec == compile_model("sedf", {"mu": 0.1, "beta": 1, "lam": 1,
    ...                                          "Delta": 3.0}).pvec
    True
    """

    def __init__(self, model, params: Mapping[str, object] | None, vary: str, at: float):
        from kbm.parameters.bound import ParameterLine

        self.line = ParameterLine(model, params, vary, at)
        base = self.line.base
        self.template = model_template(base.model)
        base.require(self.template.names, what="the numerical functions")
        self._floats = {k: float(base.values[k]) for k in self.template.names}
        self._autonomous = base.model.is_autonomous
        self._recent: dict[float, CompiledModel] = {}
        #: the line card's name and whether the field is odd for every value (set where the
        #: line comes from :func:`numerics.flow.line_card.compiled_line`; else ``None``)
        self.card_key: str | None = None
        self.odd: bool | None = None

    def __call__(self, value: float) -> CompiledModel:
        """The compiled model at ``vary = value`` (the last 64 values are kept: Newton
        returns to the same value several times; an equal object, time only)."""
        cm = self._recent.get(value)
        if cm is None:
            if len(self._recent) >= 64:
                self._recent.clear()
            cm = self._recent[value] = self._compile(value)
        return cm

    def _compile(self, value: float) -> CompiledModel:
        new = self.line.floats(value)  # exact rationals without sympy where possible
        binding = (lambda: self.line(value))
        if new is None:
            bound = self.line(value)
            if bound.model is not self.line.base.model:  # a stage velocity: a new model
                return compile_model(bound)
            new = {k: float(bound.values[k]) for k in self.line.changed}
            binding = (lambda: bound)
        fvals = dict(self._floats)
        for k in self.line.changed:
            if k in fvals:
                fvals[k] = new[k]
        return _assemble(binding, self.line.base.name, self.template, fvals,
                         self._autonomous)

    def with_values(self, value: float, others: Mapping[str, float],
                    binding: Callable[[], BoundModel]) -> CompiledModel | None:
        """The compiled model at ``vary = value`` with the float values ``others`` (names
        of the template that do not depend on ``vary``: a second parameter's) in place;
        ``binding`` its bound model.  ``None`` where the values at ``value`` need sympy."""
        new = self.line.floats(value)
        if new is None:
            return None
        fvals = {**self._floats, **{k: new[k] for k in self.line.changed if k in self._floats},
                 **{k: float(v) for k, v in others.items() if k in self._floats}}
        return _assemble(binding, self.line.base.name, self.template, fvals, self._autonomous)

    def rates(self, value: float) -> np.ndarray | None:
        """``d pvec/d vary`` at ``vary = value`` in the template's order (the parameter
        sensitivities' inhomogeneity, :mod:`numerics.flow.sensitivity`), or ``None`` when
        ``vary`` changes the model itself (a stage velocity)."""
        try:
            r = self.line.rates(value)
        except ParameterError:
            return None
        return np.array([r.get(k, 0.0) for k in self.template.names])
