"""The parameter layer: the names a model's values are given in, and the binding of them.

- :mod:`~kbm.parameters.names`: the names of a model's parameters, physical and scaled,
  and the noise ``D`` or ``T = D/mu``;
- :mod:`~kbm.parameters.values`: exact reading of user input, the read-only mapping models
  hold, :class:`~kbm.parameters.values.ParameterNames` and
  :func:`~kbm.parameters.values.scaled_values`;
- :mod:`~kbm.parameters.bound`: a model bound to its values
  (:func:`~kbm.parameters.bound.bind`, :class:`~kbm.parameters.bound.BoundModel`);
- :mod:`~kbm.parameters.rational_values`: exact values along a line without sympy.
"""
