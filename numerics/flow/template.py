"""The model's template: its numerical functions with the parameter values as trailing
arguments (:class:`ModelTemplate`), lambdified once per model (:func:`model_template`), and
the compiled extended flow of a template (:func:`template_flow`).

Split from :mod:`numerics.flow.compiled`, which binds a template to parameter values.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import TYPE_CHECKING, Callable

from kbm.errors import ModelError

from numerics._memo import memo

if TYPE_CHECKING:  # sympy and the symbolic models imported on use (issue 39)
    import sympy as sp

    from kbm.model.builtins import Oscillator

__all__ = ["ModelTemplate", "model_template", "template_flow", "jit_memo",
           "acceleration_jacobian", "conservative_potential"]


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

    def __hash__(self) -> int:
        """The hash of the fields, computed once (the memos of the compiled flows look a
        template up at every point of a branch; hashing its expressions took 50 us)."""
        h = self.__dict__.get("_hash")
        if h is None:
            h = hash((self.model, self.names, self.f_ext, self.f_acc, self.f_jac,
                      self.f_energy, self.f_w0, self.f_factor, self.dissipation_expr,
                      self.ext_exprs, self.ext_symbols))
            object.__setattr__(self, "_hash", h)
        return h


def model_template(model: Oscillator | str) -> ModelTemplate:
    """Lambdify ``model`` once, parameters (and ``mu``) as arguments.

    Memoised by the model (hashable; :func:`numerics._memo.memo`): a cached
    template is the same function of the same expressions, so the memo changes
    the time, never the result.
    """
    if isinstance(model, str):
        from kbm.model.builtins import get_model

        model = get_model(model)
    return _template(model)


@memo(maxsize=32)
def _template(model: Oscillator) -> ModelTemplate:
    from numerics.flow.template_cache import cached_template

    return cached_template(model, _build_template, ModelTemplate)


def acceleration_jacobian(acc: sp.Expr, name: str) -> tuple[sp.Expr, sp.Expr]:
    """``(d acc/dx, d acc/dx')``: the Jacobian of ``x'' = acc(x, x')`` in the variational
    equations ``dy' = J dy`` (the template's flow and Jacobian, the nine-state flow of
    :mod:`numerics.flow.sensitivity`, the adjoint ``Z' = -J^T Z`` of
    :mod:`numerics.spectrum.floquet`, the fold system of :mod:`numerics.bifurcation`).

    Raises
    ------
    kbm.errors.ModelError
        If a derivative has no closed form (``sign(xdot)``, ``Abs(xdot)``): the message
        names model ``name`` and smooth replacements.
    """
    import sympy as sp

    from kbm.symbols import x as X, xdot as V

    dadx, dadv = sp.diff(acc, X), sp.diff(acc, V)
    for var, d in (("x", dadx), ("x'", dadv)):
        if d.has(sp.Derivative, sp.DiracDelta):
            raise ModelError(
                f"model {name!r}: the derivative of the acceleration with respect to "
                f"{var} has no closed form ({d}); the variational equations (Floquet "
                "multipliers, Newton) need a smooth F: replace non-differentiable terms such "
                "as sign(xdot) or Abs(xdot) by smooth ones, e.g. tanh(xdot/0.01) or "
                "sqrt(xdot**2 + 0.01**2)")
    return dadx, dadv


def conservative_potential(model: Oscillator) -> sp.Expr | None:
    """``-int_0^x F_c(s) ds`` of the conservative force ``F_c`` (without ``omega0^2 x``), or
    ``None`` where ``F_c`` depends on ``t``: the template's energy and the sliders' energy and
    energy audit (:mod:`numerics.sliding.driven`)."""
    import sympy as sp

    from kbm.symbols import t as T, x as X
    s = sp.Dummy("s")
    cons = model.conservative_force().subs(X, s)
    if cons.has(T):
        return None
    return -sp.integrate(cons, (s, 0, X), conds="none")


def _build_template(model: Oscillator) -> ModelTemplate:
    import sympy as sp

    from kbm.model.family import one_degree_form
    from kbm.symbols import t as T, x as X, xdot as V

    if getattr(model, "dof", 1) != 1:
        one_degree_form(model)  # raises: the engines of one degree of freedom take one
    names = tuple(sorted(set(model.parameters) | {"mu"}))
    P = [sp.Symbol(n) for n in names]
    acc = model.acceleration()
    dadx, dadv = acceleration_jacobian(acc, model.name)
    plus, minus, factor = model.dissipation_parts()
    U = model.omega0**2 * X**2 / 2 + (conservative_potential(model) or 0)
    energy_expr = V**2 / 2 + U
    y = sp.symbols("y0:9")
    es = {X: y[0], V: y[1]}
    jx, jv = dadx.subs(es), dadv.subs(es)
    ext = [y[1], acc.subs(es), y[3], jx * y[2] + jv * y[3], y[5], jx * y[4] + jv * y[5], jv,
           plus.subs(es), minus.subs(es)]
    from sympy.printing.codeprinter import PrintMethodNotImplementedError

    from numerics.flow.template_cache import lambdify_light

    try:
        return ModelTemplate(
            model=model, names=names,
            f_ext=sp.lambdify((T, y, *P), ext, modules=["math", "scipy"], cse=True),
            f_acc=sp.lambdify((T, X, V, *P), acc, modules=["math", "scipy"]),
            f_jac=sp.lambdify((T, X, V, *P), [[0, 1], [dadx, dadv]],
                              modules=["numpy", "scipy"]),
            f_energy=lambdify_light((X, V, *P), energy_expr, ["numpy", "scipy", "mpmath"]),
            f_w0=sp.lambdify(P, model.omega0, modules="math"),
            f_factor=sp.lambdify(P, factor, modules="math"),
            dissipation_expr=factor * plus - minus, ext_exprs=tuple(ext), ext_symbols=tuple(y))
    except (PrintMethodNotImplementedError, NameError, TypeError) as exc:
        raise ModelError(f"model {model.name!r} cannot be turned into numerical functions: "
                         f"{' '.join(str(exc).split()[:30])}") from None


def jit_memo(build: Callable) -> Callable:
    """``build(template)`` under :func:`~numerics._memo.memo` (32 entries) per template and
    per the state of the ``KBM_NO_JIT`` switch (:func:`numerics.flow.jit.jit_available`),
    ``None`` where it is off: the compiled flows, which change the time, never the result."""
    cached = memo(maxsize=32)(lambda template, enabled: build(template) if enabled else None)

    @functools.wraps(build)
    def flow(template):
        from numerics.flow.jit import jit_available

        return cached(template, jit_available())
    return flow


@jit_memo
def template_flow(template: ModelTemplate):
    """The compiled DOP853 flow of the template's extended system, or ``None``.

    See :mod:`numerics.flow.jit`; memoised per template and per the state of the
    ``KBM_NO_JIT`` switch (:func:`jit_memo`).
    """
    quick = getattr(template, "cached_flow", None)  # a template read from a model card
    if quick is not None:
        built = quick()
        if built is not None:
            return built
        template = template.full()
    import sympy as sp

    from kbm.symbols import t as T
    from numerics.flow.jit import jit_flow

    return jit_flow(template.ext_exprs, T, template.ext_symbols,
                    [sp.Symbol(n) for n in template.names],
                    key=f"extended|{sp.srepr(tuple(template.ext_exprs))}|{template.names}",
                    what=f"the flow of {template.model.name}")
