"""Turn a symbolic :class:`kbm.Oscillator` into numerical functions, once per computation.

The model is defined once, in :mod:`kbm`; here its acceleration
``x'' = -omega0^2 x + mu F(x, x') + drive(t)`` is differentiated symbolically
(Jacobian, divergence) and lambdified together with the dissipation integrand
and the potential energy, for given parameter values.
"""

from __future__ import annotations

from collections.abc import Mapping
from collections import OrderedDict
from dataclasses import dataclass
from typing import Callable

import numpy as np
import sympy as sp

from kbm.errors import ModelError, ParameterError
from kbm.models import Oscillator, get_model
from kbm.symbols import t as T, x as X, xdot as V

__all__ = ["CompiledModel", "ModelTemplate", "compile_model", "model_template"]


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
        The parameter values as given (exact where they were exact).
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
    exact_values: Mapping[str, object]

    @property
    def acceleration_expr(self) -> sp.Expr:
        """The acceleration at these parameter values, symbolic in ``t, x, x'``."""
        return self.template.model.acceleration().subs(self._subs())

    @property
    def dissipation_expr(self) -> sp.Expr:
        """The integrand of the dissipation ``Gamma`` at these parameter values."""
        return self.template.dissipation_expr.subs(self._subs())

    def _subs(self) -> dict:
        return {sp.Symbol(k): v for k, v in self.exact_values.items()}


def _split_dissipation(model: Oscillator) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """``-D x'`` with D the dissipative force, split by the sign of its terms' coefficients.

    Returns ``(plus, minus, factor)`` with ``-D x' = factor*plus - minus``; a
    parameter ``beta`` that multiplies the whole positive part is pulled out
    (the paper's eq. 11: ``Gamma = beta Gamma_+ - Gamma_-``).
    """
    integrand = sp.expand(-model.dissipative_force() * V)
    plus, minus = [], []
    for term in sp.Add.make_args(integrand):
        coeff = term.as_coeff_Mul()[0]
        (plus if coeff > 0 else minus).append(term)
    plus_e, minus_e = sp.Add(*plus), -sp.Add(*minus)
    factor = sp.Integer(1)
    beta = sp.Symbol("beta")
    if plus and all(beta in t.free_symbols and sp.degree(t, beta) == 1 for t in plus):
        factor = beta
        plus_e = sp.expand(plus_e / beta)
    return plus_e, minus_e, factor


@dataclass(frozen=True)
class ModelTemplate:
    """The model's numerical functions with the parameter values as trailing arguments.

    Lambdifying is the expensive step; a template is built once per model and
    bound to many parameter sets by :func:`compile_model` (as in a sweep).
    """

    model: Oscillator
    names: tuple[str, ...]
    f_ext: Callable
    f_acc: Callable
    f_jac: Callable
    f_energy: Callable
    f_w0: Callable
    f_factor: Callable
    dissipation_expr: sp.Expr
    ext_exprs: tuple[sp.Expr, ...] = ()
    ext_symbols: tuple[sp.Symbol, ...] = ()


def model_template(model: Oscillator | str, v: object | None = None) -> ModelTemplate:
    """Lambdify ``model`` once, parameters (and ``mu``) as arguments.

    Templates are kept in a small LRU cache keyed by the model's symbolic content
    (``F``, ``omega0``, drive): a cached template is the same function of the same
    expressions, so the cache changes the time, never the result.
    """
    if isinstance(model, str):
        model = get_model(model, {"v": v} if v is not None else None)
    key = (model.name, sp.srepr(model.F), sp.srepr(model.omega0), sp.srepr(model.drive))
    tpl = _TEMPLATES.get(key)
    if tpl is None:
        tpl = _build_template(model)
        _TEMPLATES[key] = tpl
        while len(_TEMPLATES) > 32:
            _TEMPLATES.popitem(last=False)
    return tpl


#: memo of lambdified templates (bounded; it changes the time, never the result)
_TEMPLATES: "OrderedDict[tuple, ModelTemplate]" = OrderedDict()


def _build_template(model: Oscillator) -> ModelTemplate:
    names = tuple(sorted(set(model.parameters) | {"mu"}))
    P = [sp.Symbol(n) for n in names]
    acc = model.acceleration()
    dadx, dadv = sp.diff(acc, X), sp.diff(acc, V)
    for name, d in (("x", dadx), ("x'", dadv)):
        if d.has(sp.Derivative, sp.DiracDelta):
            raise ModelError(
                f"model {model.name!r}: the derivative of the acceleration with respect to "
                f"{name} has no closed form ({d}); the variational equations (Floquet "
                "multipliers, Newton) need a smooth F: replace non-differentiable terms such "
                "as sign(xdot) or Abs(xdot) by smooth ones, e.g. tanh(xdot/0.01) or "
                "sqrt(xdot**2 + 0.01**2)")
    plus, minus, factor = _split_dissipation(model)
    s = sp.Dummy("s")
    cons = model.conservative_force().subs(X, s)
    if cons.has(T):
        U = model.omega0**2 * X**2 / 2
    else:
        U = model.omega0**2 * X**2 / 2 - sp.integrate(cons, (s, 0, X), conds="none")
    energy_expr = V**2 / 2 + U
    y = sp.symbols("y0:9")
    es = {X: y[0], V: y[1]}
    jx, jv = dadx.subs(es), dadv.subs(es)
    ext = [y[1], acc.subs(es), y[3], jx * y[2] + jv * y[3], y[5], jx * y[4] + jv * y[5], jv,
           plus.subs(es), minus.subs(es)]
    from sympy.printing.codeprinter import PrintMethodNotImplementedError

    try:
        return ModelTemplate(
            model=model, names=names,
            f_ext=sp.lambdify((T, y, *P), ext, modules=["math", "scipy"], cse=True),
            f_acc=sp.lambdify((T, X, V, *P), acc, modules=["math", "scipy"]),
            f_jac=sp.lambdify((T, X, V, *P), [[0, 1], [dadx, dadv]],
                              modules=["numpy", "scipy"]),
            f_energy=sp.lambdify((X, V, *P), energy_expr, modules=["numpy", "scipy", "mpmath"]),
            f_w0=sp.lambdify(P, model.omega0, modules="math"),
            f_factor=sp.lambdify(P, factor, modules="math"),
            dissipation_expr=factor * plus - minus, ext_exprs=tuple(ext), ext_symbols=tuple(y))
    except (PrintMethodNotImplementedError, NameError, TypeError) as exc:
        raise ModelError(f"model {model.name!r} cannot be turned into numerical functions: "
                         f"{' '.join(str(exc).split()[:30])}") from None


def template_flow(template: ModelTemplate):
    """The compiled DOP853 flow of the template's extended system, or ``None``.

    See :mod:`numerics._jit`; memoised per template (it changes the time, never
    the result).
    """
    key = id(template)
    hit = _FLOWS.get(key)
    if hit is not None and hit[0] is template:
        return hit[1]
    from ._jit import jit_flow

    fl = jit_flow(template.ext_exprs, T, template.ext_symbols,
                  [sp.Symbol(n) for n in template.names])
    _FLOWS[key] = (template, fl)
    while len(_FLOWS) > 32:
        _FLOWS.pop(next(iter(_FLOWS)))
    return fl


#: memo of compiled flows by template (bounded; time only)
_FLOWS: dict = {}


def compile_model(model: Oscillator | str, params: Mapping[str, object] | None = None, *,
                  template: ModelTemplate | None = None) -> CompiledModel:
    """Numerical functions of ``model`` at the given parameter values (physical or scaled names).

    Parameters
    ----------
    template
        A :class:`ModelTemplate` of the same model, to skip the lambdification.

    Raises
    ------
    kbm.errors.ParameterError
        If a parameter is missing or not a finite real number.
    """
    params = dict(params or {})
    if isinstance(model, str):
        v = params.pop("v", None)
        model = get_model(model, {"v": v} if v is not None else None)
    if template is None or template.model.name != model.name \
            or template.model.F != model.F or template.model.drive != model.drive:
        template = model_template(model)
    vals = model.resolve(params)
    missing = [p for p in template.names if p not in vals]
    if missing:
        raise ParameterError(f"model {model.name!r} needs values for {', '.join(missing)} "
                             f"(e.g. --param {missing[0]}=0.1)")
    fvals = {k: float(vals[k]) for k in template.names}
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
        return float(np.max(np.abs(np.linalg.eigvals(J))))

    return CompiledModel(
        name=model.name, values=fvals, omega0=float(template.f_w0(*pv)), acc=acc, rhs=rhs,
        rhs_ext=rhs_ext, jac=jac,
        energy=lambda xv, vv: np.asarray(f_en(xv, vv, *pv), dtype=float),
        plus_factor=float(template.f_factor(*pv)), stiffness=stiffness,
        autonomous=model.is_autonomous, template=template, pvec=pv,
        exact_values=dict(vals))
