"""First-order averaging of coupled systems with any smooth ``F`` (the numeric backend).

For ``x_i'' + omega_i^2 x_i = mu F_i(x, x', theta)`` with ``x_i = a_i cos psi_i``,
``x_i' = -a_i omega_i sin psi_i``, the first-order rates of the KBM expansion are the
averages over the fast angles

``A_{i,1} = -<F_i sin psi_i>/omega_i``,  ``B_{i,1} = -<F_i cos psi_i>/(omega_i a_i)``,

where the declared resonances keep their combinations ``gamma_r = g_r . psi`` fixed
(Bogoliubov & Mitropolsky 1961, ch. 5).  They are the first order of the one recursion
(:func:`kbm.expansion.recursion.kbm_recursion`) on the sampled algebra of the numeric backend
(:class:`kbm.algebra.coupled_jets.JetAlgebra`, jets of degree 0 at the first order;
:func:`kbm.backend.jets.first_order`): ``F_i`` is sampled on an ``M^D`` grid of the torus
(``D = N``, and one more angle ``theta`` for a forced system), its multi-angle Fourier
coefficients ``c_k`` come from one FFT, and the averages keep the wavevectors ``q`` of the
slow lattice (the integer combinations of the ``g_r``):

``<F_i e^{-/+ i psi_i}> = sum_{q in L} c_{q +/- e_i} e^{i q . psi}``,  ``q . psi = sum_r n_r gamma_r``.

Above the first order :meth:`NumericAverage.expansion` runs the same recursion on jets of
higher degree (:func:`kbm.backend.jets.jet_expansion`).

For a polynomial ``F`` of degree ``d`` the grid is exact once ``M > 2 (d + 1)``; for a smooth
``F`` the error falls faster than any power of ``1/M`` (the result states the size of the
last harmonics kept, and ``tests/test_coupled_numeric.py`` compares with the exact engine and
with a Bessel closed form).  It is the same expansion as
:func:`kbm.expansion.coupled.derive_coupled` at order 1, for ``F`` that the exact engine does not
take (``sin(x1 - x2)``, ``tanh``, ...).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError
from ..model.coupled_builtins import get_coupled_model
from .jets import JetExpansion, check_nodes, check_weak, first_order, jet_expansion, symbolic_rhs
from ..model.coupled import CoupledOscillators
from ..expansion.resonance import SlowLattice

__all__ = ["NumericAverage", "numeric_average", "DEFAULT_NODES", "MAX_NODES_TOTAL"]

#: grid points per angle (polynomial F of degree below 15 is exact)
DEFAULT_NODES = 32
#: bound on the grid's size M^D (memory and time of one evaluation)
MAX_NODES_TOTAL = 2**21


@dataclass(frozen=True)
class NumericAverage:
    """The first-order rates of a coupled system at numeric parameter values.

    Call :meth:`rates` with the amplitudes and the slow phases.  ``gammas`` are the slow
    phase combinations, in the order of the model's declared resonances (as
    :attr:`kbm.expansion.coupled_result.CoupledKBMResult.gammas`).
    """

    model: CoupledOscillators
    values: Mapping[str, float]
    nodes: int
    gammas: tuple[tuple[int, ...], ...]

    def at(self, **values: float) -> "NumericAverage":
        """The same averaging at other values of some parameters (no new lambdification:
        the parameters are arguments of the sampled functions)."""
        from dataclasses import replace

        unknown = sorted(set(values) - set(self.values))
        if unknown:
            raise ParameterError(f"{', '.join(unknown)}: not parameters of {self.model.name!r}")
        return replace(self, values={**dict(self.values),
                                     **{k: float(v) for k, v in values.items()}})

    def rates(self, amplitudes: Sequence[float], gammas: Sequence[float] = ()
              ) -> tuple[np.ndarray, np.ndarray, float]:
        """``(A_1, B_1, tail)``: the amplitude and phase rates of every degree of freedom
        (to be multiplied by ``mu``) and the largest Fourier coefficient on the grid's
        outer shell (a measure of the truncation; ~1e-16 when the grid resolves ``F``).

        Raises
        ------
        kbm.errors.ParameterError
            For a count of amplitudes or phases that does not match, or an amplitude that
            is not positive and finite.
        kbm.expansion.resonance.UndeclaredResonanceError
            For a harmonic of ``F`` at an exact resonance that was not declared (as
            :func:`kbm.expansion.coupled.derive_coupled`).
        """
        return first_order(self.model, self.values, amplitudes, gammas, self.nodes)

    def expansion(self, amplitudes: Sequence[float], gammas: Sequence[float] = (),
                  order: int = 2, gradient: bool = False) -> "JetExpansion":
        """``A_{i,n}``, ``B_{i,n}`` for ``n = 1..order`` at the point, for the same ``F``
        (:func:`kbm.backend.jets.jet_expansion`: the exact engine's recursion on Taylor
        jets in the amplitudes, on this grid of the torus).

        Raises
        ------
        kbm.errors.ModelError
            For a forcing frequency ``nu`` in ``F`` above the first order (it puts ``mu``
            into ``F``), or an undeclared resonance (named).
        """
        return jet_expansion(self.model, self.values, order, amplitudes, gammas,
                             nodes=self.nodes, gradient=gradient)

    def _detuning(self) -> float:
        """The forcing's detuning ``sigma`` (0 unforced or without one)."""
        if self.model.forced and self.model.nu_detuning:
            return self.values.get(self.model.nu_detuning, 0.0)
        return 0.0

    def slow_flow_jacobian(self, mu: float, amplitudes: Sequence[float],
                           gammas: Sequence[float] = (), order: int = 2
                           ) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`slow_flow` at ``order`` (by the jets, every order) and its Jacobian in
        ``(a_1, .., a_N, gamma_1, ..)``: the amplitude derivatives from the jets, exact, the
        phase derivatives from the slow Fourier series (no differences)."""
        n, gens = self.model.dof, self.gammas
        ex = self.expansion(amplitudes, gammas, order, gradient=True)
        powers = [mu ** k for k in range(1, order + 1)]
        f = [sum(p * ex.A[i][k] for k, p in enumerate(powers)) for i in range(n)]
        J = [[sum(p * ex.dA[i][k][c] for k, p in enumerate(powers))
              for c in range(n + len(gens))] for i in range(n)]
        sig = self._detuning()
        for g in gens:
            rate = sum(g[i] * sum(p * ex.B[i][k] for k, p in enumerate(powers))
                       for i in range(n))
            f.append(rate + (mu * g[n] * sig if self.model.forced else 0.0))
            J.append([sum(g[i] * sum(p * ex.dB[i][k][c] for k, p in enumerate(powers))
                          for i in range(n)) for c in range(n + len(gens))])
        return np.array(f), np.array(J)

    def slow_flow(self, mu: float, amplitudes: Sequence[float], gammas: Sequence[float] = (),
                  order: int = 1) -> np.ndarray:
        """``(a_1', .., a_N', gamma_1', ..)``: ``sum_n mu**n A_{i,n}``, and for each slow
        phase ``gamma_r = g_r . psi`` its rate ``sum_n mu**n sum_i g_{r,i} B_{i,n}`` plus
        ``mu g_{r,theta} sigma`` (the resonance is exact at ``mu = 0``; ``sigma`` is the
        forcing's detuning).  Order 1 by the FFT average (:meth:`rates`), above it by
        :meth:`expansion`."""
        n = self.model.dof
        if order == 1:
            A, B, _ = self.rates(amplitudes, gammas)
        else:
            ex = self.expansion(amplitudes, gammas, order)
            A = [sum(mu ** (k - 1) * ex.A[i][k - 1] for k in range(1, order + 1))
                 for i in range(n)]
            B = [sum(mu ** (k - 1) * ex.B[i][k - 1] for k in range(1, order + 1))
                 for i in range(n)]
        sig = self._detuning()
        out = [mu * v for v in A]
        for g in self.gammas:
            rate = sum(g[i] * B[i] for i in range(n))
            if self.model.forced:
                rate += g[n] * sig
            out.append(mu * rate)
        return np.array(out)


def numeric_average(model: CoupledOscillators | str, values: Mapping[str, object] | None = None,
                    *, internal: Sequence[object] = (), nodes: int = DEFAULT_NODES
                    ) -> NumericAverage:
    """The first-order averaging of ``model`` at numeric parameter values (any smooth ``F``).

    Parameters
    ----------
    model
        A :class:`~kbm.model.coupled.CoupledOscillators` or a built-in name.
    values
        A value for every parameter that ``F`` holds without a default (``mu`` is not
        needed; physical names such as ``Delta`` are converted as :func:`kbm.parameters.bound.bind`
        does, then ``mu`` is).
    internal
        Further declared resonances (``"1:3"``, ...), as :func:`derive_coupled`'s.
    nodes
        Grid points per angle (even, at least 8).

    Raises
    ------
    kbm.errors.ParameterError
        For a grid too small or too large, or a parameter without a value.
    kbm.errors.ModelError
        For a model that depends on ``t`` (a pulled stage).
    """
    if isinstance(model, str):
        model = get_coupled_model(model)
    if internal:
        model = model.with_internal(internal)
    # the family's bound form: physical names converted, defaults filled in
    exact = model.resolve(values)
    vals = {k: float(v) for k, v in exact.items()}
    if any(not math.isfinite(v) for v in vals.values()):
        raise ParameterError("parameter values must be finite")
    stage = model.stage_parameters()
    model = model.at_rest(exact)  # a stage at rest (v = 0) is autonomous
    vals = {k: v for k, v in vals.items() if k not in stage}
    check_weak(model)
    check_nodes(nodes)
    D = model.dof + (1 if model.forced else 0)
    if nodes ** D > MAX_NODES_TOTAL:
        raise ParameterError(f"{nodes}^{D} grid points exceed the limit {MAX_NODES_TOTAL}: "
                             f"take nodes <= {int(MAX_NODES_TOTAL ** (1 / D)) // 2 * 2}")
    missing = sorted({r.detuning for r in model.internal
                      if r.detuning and not r.forcing} - set(vals))
    if missing:
        raise ParameterError(f"give values for the detunings {', '.join(missing)}")
    gens = tuple(SlowLattice(D, model.internal).generators)
    free = sorted(set(symbolic_rhs(model, False)[1]) - set(vals))
    if free:
        raise ParameterError(f"give values for {', '.join(free)} (-p NAME=VALUE"
                             + "".join(model.physical_hint(n) for n in free) + ")")
    return NumericAverage(model, vals, nodes, gens)
