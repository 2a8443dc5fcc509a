"""The KBM expansion of ``N`` coupled oscillators, with internal resonances, to any order.

For ``x_i'' + omega_i**2 x_i = mu F_i(x, x')`` (i = 1..N) the expansion (Bogoliubov &
Mitropolsky 1961, ch. 5, the multi-frequency case; Nayfeh & Mook 1979, ch. 6) is

``x_i = a_i cos(psi_i) + sum_{n>=1} mu**n u_{i,n}(a, psi)``,
``da_i/dt = sum mu**n A_{i,n}(a, gamma)``, ``dpsi_i/dt = omega_i + sum mu**n B_{i,n}(a, gamma)``,

where the rates hold only the *slow* harmonics ``k`` of the declared internal resonances
(``k . omega = 0``: functions of the phase combinations ``gamma_r``), and no ``u_{i,n}``
holds a harmonic of frequency ``+-omega_i`` — so ``a_i`` is exactly the amplitude of the
component of ``x_i`` at its own frequency (``R_{i,n}``, ``L0`` and ``D_j`` as in
:mod:`kbm.expansion.recursion`).  The resonant part of ``R_{i,n}`` (harmonics ``+-e_i + k``, ``k``
slow) is ``P cos(psi_i) + Q sin(psi_i)`` with slow ``P``, ``Q``; it gives
``A_{i,n} = -Q/(2 omega_i)``, ``B_{i,n} = -P/(2 omega_i a_i)``, and every other harmonic ``h`` is
divided by ``omega_i**2 - (h . omega)**2``.  A harmonic whose divisor vanishes, or is within
``tolerance`` of vanishing, without a declared resonance raises
:class:`~kbm.expansion.resonance.UndeclaredResonanceError` with the resonance named.  ``N = 1``
reproduces the one-degree-of-freedom expansion of :mod:`kbm.expansion.one_dof` exactly.

The loop is the one recursion (:func:`kbm.expansion.recursion.kbm_recursion`); its algebra here is
the exact :class:`~kbm.algebra.coupled.CoupledAlgebra`: ``N``-angle Fourier series
(:mod:`kbm.algebra.multi_angle`) with Laurent-polynomial coefficients over Q in the
amplitudes, the parameters and the detunings.
"""

from __future__ import annotations

import sympy as sp

from ..algebra.lazy_series import Leaf
from ..errors import ModelError, OrderError
from .recursion import kbm_recursion
from ..algebra.coupled import CoupledAlgebra, MultiBuilder, coupled_rhs
from ..algebra.coupled_bessel import JacobiAnger, jacobi_anger_plan
from ..model.constants import opaque_constants, split_phases
from ..model.coupled import CoupledOscillators, positions, velocities
from .resonance import SlowLattice
from .coupled_result import CoupledKBMResult

__all__ = ["derive_coupled", "MAX_ORDER", "MAX_ORDER_ONE", "MAX_DOF_SYMBOLIC", "TOLERANCE"]

#: highest order of the coupled expansion (harmonics in N angles grow like order**N)
MAX_ORDER = 8

#: highest order for one degree of freedom, kbm.derive's (harmonics grow like the order):
#: the general engine gives the same A_n, B_n as kbm.expansion.one_dof to order 30 (vdp, duffing,
#: rayleigh; tests/test_coupled_engine.py), in four to six times its time
MAX_ORDER_ONE = 30

#: most degrees of freedom of the exact symbolic expansion (the numerics take more)
MAX_DOF_SYMBOLIC = 6

#: a harmonic whose frequency is within this fraction of omega_i (and not declared
#: resonant) is refused as a small divisor
TOLERANCE = 0.05


def lambda_symbols(n: int) -> tuple[sp.Symbol, ...]:
    """``Lambda1, .., LambdaN``: the amplitudes of the responses to a hard forcing."""
    return tuple(sp.Symbol(f"Lambda{i}") for i in range(1, n + 1))


def _hard_shifted(model: CoupledOscillators) -> list[list[sp.Expr]]:
    """``F_i`` of the shifted state ``y_j = x_j - Lambda_j cos(theta)`` (``Lambda_j`` symbols,
    ``Lambda_j = K_j/(omega_j^2 - nu^2)``), with ``nu = nu0 + mu sigma`` in the velocities'
    shift: the coefficients of ``mu**k``, as the one-degree-of-freedom forced engine
    (:meth:`kbm.model.forced.ForcedOscillator.shifted`) for ``N = 1``.

    Raises
    ------
    kbm.errors.ParameterError
        For a hard forcing at the frequency of its mode (``Lambda`` infinite).
    """
    from ..errors import ParameterError

    n = model.dof
    theta = sp.Symbol("theta")
    nu = model.nu0 + (sp.Symbol("mu") * sp.Symbol(model.nu_detuning)
                      if model.nu_detuning else 0)
    lams = lambda_symbols(n)
    shift = {}
    for j, (k, w) in enumerate(zip(model.hards, model.omegas)):
        if k == 0:
            continue
        if w == model.nu0:
            raise ParameterError(f"the hard forcing K{j + 1} cos(theta) of {model.name!r} is "
                                 f"resonant at nu = omega{j + 1} (Lambda = K/(omega^2 - "
                                 "nu^2) is infinite): write it as a weak forcing "
                                 "mu*h*cos(theta) in F")
        shift[positions(n)[j]] = positions(n)[j] + lams[j] * sp.cos(theta)
        shift[velocities(n)[j]] = velocities(n)[j] - lams[j] * nu * sp.sin(theta)
    out = []
    for f in model.rhs:
        g = sp.Poly(sp.expand(f.xreplace(shift)), sp.Symbol("mu"))
        out.append([sp.expand(g.coeff_monomial(sp.Symbol("mu") ** k))
                    for k in range(g.degree() + 1)])
    return out


def derive_coupled(model: CoupledOscillators | str, order: int,
                   params: dict | None = None, *, internal=(),
                   tolerance: float = TOLERANCE) -> CoupledKBMResult:
    """KBM expansion of ``x_i'' + omega_i**2 x_i = mu F_i(x, x')`` to order ``order``.

    Parameters
    ----------
    model
        A :class:`~kbm.model.coupled.CoupledOscillators`, a one-degree-of-freedom
        :class:`~kbm.model.builtins.Oscillator` (the case ``N = 1``) or a built-in's name.
    order
        Highest power of ``mu`` kept (``A_{i,1..N}``, ``B_{i,1..N}``, ``u_{i,1..N}``).
    params
        Exact parameter values substituted first (``"0.1"`` is ``1/10``).
    internal
        Internal resonances declared beyond the model's own (``"1:3"``, ``"1:1@2,3"`` or
        :class:`~kbm.expansion.resonance.InternalResonance`).
    tolerance
        A harmonic whose frequency is within this fraction of ``omega_i`` without a
        declared resonance is refused.

    Returns
    -------
    CoupledKBMResult

    Raises
    ------
    kbm.errors.OrderError
        For an order outside ``1..MAX_ORDER`` (``1..MAX_ORDER_ONE`` for one degree of
        freedom).
    kbm.errors.CostError
        For one degree of freedom, an expansion above :data:`kbm.expansion.cost.COST_BUDGET`.
    kbm.expansion.resonance.UndeclaredResonanceError
        For a (near) resonance that was not declared (it is named).
    kbm.errors.ModelError
        For more than :data:`MAX_DOF_SYMBOLIC` degrees of freedom, or right-hand sides that
        are not polynomials with rational coefficients.

    Examples
    --------
    Two van der Pol oscillators in 1:1 resonance, coupled dissipatively:

    >>> r = derive_coupled("coupled-vdp", 1)
    >>> r.A[0][1]
    -a1*(a1**2 + 4*c - 4)/8 + a2*c*cos(gamma1)/2
    """
    from ..model.coupled_builtins import get_coupled_model

    if isinstance(model, str):
        model = get_coupled_model(model)
    fixed = model.with_frequencies(params)  # the sliders' Omega: exact frequencies
    if fixed is not model:
        params = {k: v for k, v in (params or {}).items() if k not in model.parameters
                  or k in fixed.parameters}
        model = fixed
    stage = model.stage_parameters()
    model = model.at_rest(params)  # a stage at rest (given or default v = 0) is autonomous
    params = {k: v for k, v in (params or {}).items() if k not in stage}
    if params:
        model = model.substitute(params)  # physical names converted, mu passed over
    if internal:
        model = model.with_internal(internal)
    limit = MAX_ORDER_ONE if model.dof == 1 else MAX_ORDER
    if not isinstance(order, int) or isinstance(order, bool) or not 1 <= order <= limit:
        raise OrderError(f"the order must be an integer from 1 to {limit} for {model.dof} "
                         f"degree{'s' if model.dof > 1 else ''} of freedom, got {order!r}")
    if model.dof == 1:  # the one-degree-of-freedom engine's bound on the size, before any work
        from .cost import check_cost
        from ..symbols import x, xdot

        x1, v1 = positions(1)[0], velocities(1)[0]
        check_cost(model.rhs[0].subs({x1: x, v1: xdot}, simultaneous=True), order)
    if any(f.has(sp.Symbol("nu")) for f in model.rhs):
        raise ModelError(f"{model.name!r} holds the forcing frequency nu in F (nu = nu0 + mu "
                         "sigma puts mu into F): the exact coupled expansion takes F free of "
                         "nu; its true responses are numerics (kbm response, kbm cycle), its "
                         "averaging the numeric backend kbm.backend.forced")
    if model.dof > MAX_DOF_SYMBOLIC:
        raise ModelError(f"{model.dof} degrees of freedom are above the limit "
                         f"{MAX_DOF_SYMBOLIC} of the exact symbolic averaging (its Fourier "
                         f"series are in {model.dof} angles); simulate the system instead "
                         "(kbm cycle, kbm friction take any N)")
    n = model.dof
    F = _hard_shifted(model) if model.hards else [[f] for f in model.rhs]
    detunings = []
    for r in model.internal:
        if r.detuning:  # omega_j -> omega_j + mu sigma, exactly
            sig = sp.Symbol(r.detuning)
            detunings.append(sig)
            xj = positions(n)[r.j - 1]
            wj = model.omegas[r.j - 1]
            Fj = F[r.j - 1]
            Fj[0] = Fj[0] - 2 * wj * sig * xj
            Fj.append(-sig**2 * xj)
    F = split_phases(F, positions(n))  # sin(c x + d) = sin(c x) cos d + cos(c x) sin d
    F, constants = opaque_constants(F, model.state)  # sqrt(2), pi, cos(phi): generators
    syms = set().union(*[f.free_symbols for row in F for f in row]) - set(model.state) \
        - {sp.Symbol("theta"), sp.Symbol("mu")} - set(constants)
    if model.forced and model.nu_detuning:
        syms.add(sp.Symbol(model.nu_detuning))
    bessel = jacobi_anger_plan(F, model, order, tolerance)  # sin, cos of positions
    gens = sorted(syms | set(detunings), key=lambda s: s.name)
    gens += sorted(constants, key=lambda s: s.name) + (bessel.generators() if bessel else [])
    lattice = SlowLattice(n + (1 if model.forced else 0), model.internal)
    alg = CoupledAlgebra(model, lattice, gens, tolerance)
    A, B, U = kbm_recursion(alg, coupled_rhs(
        alg, F, lambda al, leaves: MultiBuilder(al, leaves, bessel)), order)
    result = CoupledKBMResult.from_series(model, order, lattice, A, B, U)
    if not bessel:
        return result.substituted(constants) if constants else result
    return result.substituted({**constants, **bessel.substitution()},
                              _bessel_tails(alg, F, bessel))


def _bessel_tails(alg: CoupledAlgebra, F: list[list[sp.Expr]], bessel: JacobiAnger
                  ) -> list[sp.Expr]:
    """The parts of the ``u_{i,1}`` above the Jacobi-Anger cut
    (:meth:`kbm.algebra.coupled_bessel.JacobiAnger.tail`), one per degree of freedom."""
    n = alg.dof
    angles = tuple(sp.Symbol(f"psi{i}") for i in range(1, n + 1)) \
        + ((sp.Symbol("theta"),) if alg.forced else ())
    first = MultiBuilder(alg, {**{xi: Leaf(alg.zero, alg.x0(i))
                                  for i, xi in enumerate(positions(n))},
                               **{vi: Leaf(alg.zero, alg.L0(alg.x0(i)))
                                  for i, vi in enumerate(velocities(n))}})
    return [bessel.tail(alg, F[i][0], i, angles, lambda e: first.build(e).coeff(0))
            for i in range(n)]
