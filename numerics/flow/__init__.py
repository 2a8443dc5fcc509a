"""Floor 1 of :mod:`numerics`: a model turned into numbers and trajectories.

- :mod:`numerics.flow.compiled`: the model's numerical functions at bound
  parameter values (:class:`CompiledModel`), lambdified once per model
  (:class:`ModelTemplate`, :mod:`numerics.flow.template`);
- :mod:`numerics.flow.template_cache`: the templates' functions kept on disk under the
  model's canonical form (a warm run does not lambdify);
- :mod:`numerics.flow.card`: model cards, what ``kbm cycle`` needs of a bound built-in
  model, kept on disk (a warm run builds no symbolic model and imports no sympy);
- :mod:`numerics.flow.line_card`: line cards, a built-in model bound along one parameter
  (:class:`CompiledLine`) kept on disk for the warm ``kbm branch``;
- :mod:`numerics.flow.jit`: the extended flow printed from the model's
  expressions and compiled with numba (an adaptive DOP853);
- :mod:`numerics.flow.numba_cache`: the cache folder of the generated modules, their
  import, and the first-run notice of numba's compilation;
- :mod:`numerics.flow.aot`: the same flows compiled ahead of time into extension
  modules, which a warm run imports without numba;
- :mod:`numerics.flow.integrate`: the method enum, the one stiffness policy and
  the doors :func:`flow`, :func:`solve`, :func:`integrate`;
- :mod:`numerics.flow.coupled_flow`: the compiled flow of ``N`` coupled oscillators with its
  variational equations (:func:`~numerics.flow.coupled_flow.coupled_flow`: state, monodromy,
  divergence);
- :mod:`numerics.flow.forced_system`: a forced model compiled once, ``sigma`` free, as a
  flow over one response period (:class:`~numerics.flow.forced_system.ForcedSystem`).
"""

from numerics.flow.compiled import CompiledLine, CompiledModel, compile_model, extended_state
from numerics.flow.template import ModelTemplate, model_template, template_flow
from numerics.flow.integrate import (JIT_METHOD, JIT_STIFF_THRESHOLD, STIFF_THRESHOLD, Method,
                                     choose_method, flow, integrate, solve, stiffness)
from numerics.flow.jit import FlowResult, jit_available, jit_flow

__all__ = ["CompiledLine", "CompiledModel", "ModelTemplate", "compile_model", "model_template",
           "template_flow", "extended_state", "Method", "choose_method", "flow", "solve",
           "integrate", "stiffness", "STIFF_THRESHOLD", "JIT_STIFF_THRESHOLD", "JIT_METHOD",
           "FlowResult", "jit_available", "jit_flow"]
