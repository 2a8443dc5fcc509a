"""The extended flow with the state's sensitivity to one parameter, compiled once per model.

Newton's method on the shooting problem of a branch of cycles needs ``dR/dp``, the
derivative of the return map in the varied parameter.  A central difference costs two
more integrations per iteration; instead the sensitivity ``s = d(x, x')/dp`` is integrated
with the state (the forward sensitivity equations, e.g. Hairer, Norsett and Wanner,
*Solving Ordinary Differential Equations I*, 2nd ed., sec. I.14):

``s' = J(t, x, x') s + sum_k (d acc/d p_k) (d p_k/d p) e_2``,

with ``J`` the Jacobian of the field and ``p_k`` the template's parameter values (the
scaled ones: varying ``Delta`` moves ``delta = Delta/mu`` at the rate ``1/mu``).  The
rates ``d p_k/d p`` are passed with the values, so one compiled flow serves every
parameter of the model.  The nine states are the first seven of
:func:`~numerics.flow.compiled.extended_state` (state, fundamental matrix, divergence
integral; the dissipation integrals are not needed along a branch) and ``(dx/dp, dx'/dp)``.

Only the compiled DOP853 carries them (:func:`sensitivity_flow` is ``None`` otherwise);
callers fall back to differences.  The equations are checked against central differences
of the flow itself and against the closed form of the linear oscillator in
``tests/test_sensitivity.py``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from numerics.errors import IntegrationError
from numerics.flow.compiled import CompiledModel
from numerics.flow.template import ModelTemplate
from numerics.flow.template import acceleration_jacobian, jit_memo

__all__ = ["N_SENSITIVITY", "sensitivity_flow", "sensitivity_state", "flow_with_sensitivity",
           "shooting_corrector"]

#: the compiled Newton corrector of a branch of cycles, appended to the module (a real file)
_CORRECTOR = Path(__file__).with_name("_shooting_corrector.py").read_text()

#: the state, the fundamental matrix, the divergence integral and ``(dx/dp, dx'/dp)``
N_SENSITIVITY = 9


def sensitivity_state(x0: float, v0: float = 0.0) -> list[float]:
    """The initial state at ``(x0, v0)`` with a fixed start: identity fundamental matrix, zero
    divergence integral and zero sensitivity (the start does not move with ``p``)."""
    return [float(x0), float(v0), 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0]


@jit_memo
def sensitivity_flow(template: ModelTemplate):
    """The compiled flow of the nine states, or ``None`` (no numba, ``KBM_NO_JIT``, or a
    function of the model without a :mod:`math` form).

    Its parameter vector is the template's values followed by their rates
    ``d p_k/d p`` (the same order, :attr:`ModelTemplate.names`).  Memoised per template
    and per the state of the ``KBM_NO_JIT`` switch (:func:`numerics.flow.template.jit_memo`).
    """
    key = getattr(template, "sensitivity_key", None)  # a template read from a line card
    if key is not None:
        from numerics.flow.jit import cached_flow

        built = cached_flow(key, 2, _CORRECTOR)  # jit_flow below: n_state 2
        if built is not None:
            return built
    if hasattr(template, "full"):  # a card's template: the symbolic one
        template = template.full()
    import sympy as sp

    from kbm.symbols import t as T, x as X, xdot as V
    from numerics.flow.jit import jit_flow
    from numerics.flow.numba_cache import COMPILE_SECONDS

    names = [sp.Symbol(n) for n in template.names]
    rates = [sp.Symbol(f"rate_{n}") for n in template.names]
    y = sp.symbols(f"y0:{N_SENSITIVITY}")

    def exprs():
        acc = template.model.acceleration()
        es = {X: y[0], V: y[1]}
        jx, jv = (d.subs(es) for d in acceleration_jacobian(acc, template.model.name))
        forcing = sum((sp.diff(acc, p).subs(es) * r for p, r in zip(names, rates)),
                      sp.Integer(0))
        ext = [e.xreplace(dict(zip(template.ext_symbols, y))) for e in template.ext_exprs[:7]]
        return ext + [y[8], jx * y[7] + jv * y[8] + forcing]

    return jit_flow(exprs, T, y, names + rates,
                    key=f"sensitivity-9|{sp.srepr(tuple(template.ext_exprs))}|{template.names}",
                    extra=_CORRECTOR, what=f"the nine-state flow of {template.model.name} and its "
                    "Newton corrector (continuation)", seconds=COMPILE_SECONDS["shooting"])


def shooting_corrector(template: ModelTemplate):
    """The compiled Newton corrector of a cycle's shooting problem
    (``numerics/flow/_shooting_corrector.py``: ``shoot_correct``) on the nine-state flow of
    ``template``, or ``None`` where :func:`sensitivity_flow` is ``None``."""
    fl = sensitivity_flow(template)
    return None if fl is None else fl.module.shoot_correct


def flow_with_sensitivity(cm: CompiledModel, rates: np.ndarray, y0, t_end: float, n_out: int,
                          rtol: float, atol: float, max_steps: int = 10**6) -> np.ndarray:
    """States of the nine-state system at ``t_k = k t_end/n_out``, shape ``(n_out + 1, 9)``.

    ``rates`` are ``d p_k/d p`` in the template's order
    (:meth:`numerics.flow.CompiledLine.rates`).  The caller has checked that
    :func:`sensitivity_flow` is not ``None``.

    Raises
    ------
    numerics.errors.IntegrationError
        If the integration fails (with the time and the reason).
    """
    fl = sensitivity_flow(cm.template)
    res = fl(y0, t_end, np.concatenate([cm.pvec, rates]), rtol, atol, n_out, max_steps)
    if res.status:
        raise IntegrationError(f"DOP853 (compiled) failed before t = {t_end:.6g} after "
                               f"{res.steps} steps: {res.message}")
    if not np.all(np.isfinite(res.y[-1])):
        raise IntegrationError(f"the state became non-finite before t = {t_end:.6g}")
    return res.y
