"""The one parameter and option layer of the ``kbm`` commands (issue 35).

- :mod:`numerics.cli.params.values`: ``-p NAME=VALUE`` and ``--vary`` read, checked against
  the model's names (physical and scaled, ``D`` or ``T = D/mu``) and parsed by one grammar,
  with errors in command-line terms;
- :mod:`numerics.cli.params.options`: the options of the numerical commands defined once
  (the command's parser, the ensemble options, their checks, the store of a run);
- :mod:`numerics.cli.params.noise`: the values of the commands with noise (``kbm noise``,
  ``escape``, ``spectrum``) and the noise as an axis, ``--vary D=`` or ``--vary T=``, its
  refusals naming the ``--vary`` typed;
- :mod:`numerics.cli.params.forced`: the forced model of ``kbm response`` and its values,
  the detuning's range and the amplitude window;
- :mod:`numerics.cli.params.plane`: the two ``--vary`` axes of a forced or coupled
  ``kbm diagram`` in the model's own (scaled) names.

The names themselves (``kbm.parameters.values.ParameterNames``, ``kbm.parameters.names``) and the options
shared with the symbolic commands (``kbm.cli._common``) live in :mod:`kbm`.
"""
