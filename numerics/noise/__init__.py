"""Thermal noise: the paper's eq. (1) with ``eta = sqrt(2 D) xi(t)``.

Convention, everywhere: ``x'' + ... = sqrt(2 D) xi(t)`` with ``<xi(t) xi(t')> =
delta(t - t')`` and unit mass; for linear damping ``mu`` the temperature is
``kT = D/mu``; ``D = 0`` is the deterministic model.

:mod:`numerics.noise.langevin` compiles a model's Langevin equation (weak order 2);
:mod:`numerics.noise.ensemble` runs ensembles of trajectories on the executor and
estimates stationary moments and densities with their standard errors;
:mod:`numerics.noise.extrapolate` extrapolates stationary moments over the step
(Richardson, BAOAB at ``h`` and ``h/2``); :mod:`numerics.noise.invariant` computes the exact
stationary averages of the BAOAB chain (its weak error without sampling);
:mod:`numerics.noise.coupled` is the noisy system of ``N`` forced or coupled oscillators and
its compiled ensemble paths (the same scheme and streams).  The compiled
source: :mod:`numerics.noise.codegen` prints the model, :mod:`numerics.noise._kernels`,
:mod:`numerics.noise._passage_kernels` (first passages, pulled sliders) and
:mod:`numerics.noise._pair_kernels` hold the kernels, :mod:`numerics.noise.lanes` prints the
loops of ``final_states``, ``first_passages`` and ``slip_stats`` over several trajectories at
once, :mod:`numerics.noise.seeds`
holds the streams, :mod:`numerics.noise._pilot` the measured default step (the step pilot);
:mod:`numerics.noise.validity` the gap averaged - simulated in standard errors and its flag
``|z| > 4`` and the expected error of an averaged number (``kbm noise``, ``kbm spectrum``);
:mod:`numerics.noise.budget` the step budget every noisy command shares.
"""

from kbm._lazy import lazy_names

__all__ = ["LangevinSystem", "langevin_system", "split_noise", "trajectory_states"]

#: the public names, each imported from its module on first use (PEP 562): the command
#: line's option table reads :mod:`numerics.noise.budget` without sympy and numba
_LAZY = {**dict.fromkeys(("LangevinSystem", "langevin_system", "split_noise"),
                         "numerics.noise.langevin"),
         "trajectory_states": "numerics.noise.seeds"}

__getattr__, __dir__ = lazy_names(__name__, globals(), _LAZY)
