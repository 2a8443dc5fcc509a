"""The last step of the shooting: from a converged ``(x0, T)`` to a :class:`LimitCycle`.

- the minimal period (Newton may converge to several turns of a cycle);
- one integration of the extended system: samples, monodromy matrix (Floquet
  multipliers), Liouville's check, the dissipation, the energy residual;
- the Fourier coefficients by quadrature along the integration
  (:func:`numerics.cycles.harmonics.fourier_coefficients`; no aliasing of jumps);
- an accuracy estimate: one Newton step at a tolerance a hundred times smaller
  gives the error of ``x0`` and ``T`` (it includes the amplification of the
  integration error by ``1/|1 - multiplier|`` on a weakly attracting cycle);
- a weakly attracting cycle that double precision cannot resolve to ``1e-10`` is
  recomputed with the mpmath Taylor integrator (:mod:`numerics.cycles.highprec`),
  and the message says so;
- a non-isolated orbit (non-trivial multiplier 1: a conservative system) is an error.
"""

from __future__ import annotations

import math

import numpy as np

from numerics.shooting.floquet import floquet_multipliers
from numerics.cycles.harmonics import fourier_coefficients
from numerics.cycles.newton import check_nontrivial, newton
from numerics.cycles.result import Dissipation, LimitCycle
from numerics.errors import ConvergenceError, IntegrationError, NoCycleError
from numerics.flow import Method, extended_state, flow, stiffness

__all__ = ["final_pass", "WEAK_ACCURACY", "HIGHPREC_DIGITS"]

#: a relative accuracy of period or amplitude worse than this on a weakly attracting cycle
#: switches to the high-precision integrator
WEAK_ACCURACY = 1e-10

#: digits of that high-precision recomputation
HIGHPREC_DIGITS = 17


def _minimal_period(cm, converged, ys, meth, st):
    """The same orbit with its minimal period: Newton may converge to ``k`` turns of a cycle
    (``x(T/k) = x0``, ``x'(T/k) = 0`` for ``k = 2, 3, 4``).  ``ys`` are the samples of the
    converged orbit at equal times; a sample near ``T/k`` close to the start makes Newton
    try ``T/k``.  Returns ``(x0, T/k, it, history)`` for the smallest such ``k`` confirmed
    by Newton, else ``None``."""
    x0, T = converged[0], converged[1]
    n = len(ys) - 1
    scale = 1e-2 * max(1.0, abs(x0))  # a coarse screen: Newton confirms
    for k in (4, 3, 2):  # a cycle of period T/4 is also one of period T/2: try the shortest
        j = round(n / k)
        if max(abs(ys[j, 0] - x0), abs(ys[j, 1])) < scale:
            try:
                shorter = newton(cm, x0, T / k, meth, st.rtol, st.atol, st.max_iter, st.floor)
                check_nontrivial(cm, shorter, meth, st.rtol, st.atol, x0)
            except (ConvergenceError, IntegrationError, NoCycleError):
                continue
            return shorter
    return None


def _newton_correction(cm, x0, T, meth, rtol, atol) -> tuple[float, float]:
    """``(|dx0|, |dT|)`` of one Newton step at a tolerance a hundred times smaller (not
    below 1e-14 compiled, 3e-14 otherwise: LSODA refuses smaller ones)."""
    tight = max(rtol * 1e-2, 1e-14 if meth is Method.COMPILED else 3e-14)
    yT = flow(cm, extended_state(x0), T, 1, meth, tight, atol * tight / rtol)[-1]
    r = np.array([yT[0] - x0, yT[1]])
    J = np.array([[yT[2] - 1.0, yT[1]], [yT[3], cm.acc(T, yT[0], yT[1])]])
    try:
        dx, dT = np.linalg.solve(J, -r)
    except np.linalg.LinAlgError:
        return math.inf, math.inf
    return abs(float(dx)), abs(float(dT))


def _samples(cm, x0, T, meth, st, n_samples):
    ys = flow(cm, extended_state(x0), T, n_samples, meth, st.rtol, st.atol)
    residual = float(max(abs(ys[-1, 0] - x0), abs(ys[-1, 1])))
    return ys, residual


def _check_isolated(other: complex, x0: float, T: float, rtol: float) -> None:
    if abs(other - 1.0) < max(100 * rtol, 1e-11):
        raise NoCycleError(
            f"the periodic orbit found (x_max = {x0:.6g}, T = {T:.6g}) is not isolated: its "
            f"non-trivial Floquet multiplier is 1 within {abs(other - 1.0):.1e} (every nearby "
            "orbit is periodic too, as in a conservative system), so it is no limit cycle; "
            "if the cycle is this weakly attracting, lower rtol")


def _weak_highprec(cm, x0, T, other, rel):
    """High-precision period, maximum and first harmonic of a weakly attracting cycle, or
    ``None`` (with the reason) when that path does not apply or fails."""
    contraction = abs(1.0 - abs(other))
    if max(rel["period"], rel["amplitude_max"]) <= WEAK_ACCURACY or contraction > 1e-2:
        return None, ""
    note = (f"the cycle attracts (or repels) weakly (non-trivial multiplier "
            f"{abs(other):.10f}): the integration error of the shooting is amplified by "
            f"1/|1 - multiplier| = {1 / max(contraction, 1e-300):.2g}, to a relative error "
            f"~{max(rel['period'], rel['amplitude_max']):.1e}")
    if stiffness(cm, abs(x0)) * T > 1e3:
        return None, note + " (too stiff for the high-precision integrator; ask digits=)"
    from numerics.cycles.highprec import limit_cycle_mp  # mpmath and sympy on use (issue 39)

    try:
        mp = limit_cycle_mp(cm.acceleration_expr, HIGHPREC_DIGITS, x0, T)
    except (ConvergenceError, IntegrationError) as exc:
        return None, note + f" (the high-precision integrator failed: {exc})"
    return mp, note + (f"; period and amplitudes recomputed with the {HIGHPREC_DIGITS}-digit "
                       "Taylor integrator")


def final_pass(cm, converged, meth, source, st, digits, n_samples, n_harmonics) -> LimitCycle:
    """One more integration of the converged orbit: samples, monodromy, dissipation,
    harmonics and the accuracy of the results (see the module's description)."""
    rtol, atol, floor = st.rtol, st.atol, st.floor
    x0, T, it, history = converged
    ys, residual = _samples(cm, x0, T, meth, st, n_samples)
    shorter = _minimal_period(cm, converged, ys, meth, st)
    if shorter is not None:  # k turns of the cycle: keep one
        x0, T, it2, h2 = shorter
        it, history = it + it2, history + h2
        ys, residual = _samples(cm, x0, T, meth, st, n_samples)
    if not source.startswith("transient") and x0 < np.max(ys[:-1, 0]) - 1e-6 * max(1.0, abs(x0)):
        # the guess led to a point that is not the maximum of x: restart at the maximum
        i = int(np.argmax(ys[:-1, 0]))
        x0, T, it2, h2 = newton(cm, float(ys[i, 0]), T, meth, rtol, atol, st.max_iter, floor)
        it, history = it + it2, history + h2
        ys, residual = _samples(cm, x0, T, meth, st, n_samples)
    yT = ys[-1]
    tt = np.linspace(0.0, T, n_samples + 1)[:-1]
    Phi = np.array([[yT[2], yT[4]], [yT[3], yT[5]]])
    trivial, other = floquet_multipliers(Phi, yT[6])  # the non-trivial one from Liouville
    _check_isolated(other, x0, T, rtol)
    gp, gm = float(yT[7]), float(yT[8])
    total = cm.plus_factor * gp - gm
    coeffs, cerr = fourier_coefficients(cm, x0, T, meth, rtol, n_harmonics)
    first = float(2 * abs(coeffs[1]))
    dx, dT = _newton_correction(cm, x0, T, meth, rtol, atol)
    rel = {"period": dT / T, "amplitude_max": dx / max(abs(x0), 1e-300),
           "amplitude_first_harmonic": (2 * float(cerr[1]) + dx) / max(first, 1e-300)}
    rel["frequency"] = rel["period"]
    mp: dict = {}
    if digits is not None:
        from numerics.cycles.highprec import limit_cycle_mp

        mp = limit_cycle_mp(cm.acceleration_expr, int(digits), x0, T)
    success = residual < 1e3 * floor
    msg = (f"converged in {it} Newton iterations from the {source} ({meth.label}, rtol "
           f"{rtol:g}); |(x(T) - x0, x'(T))| = {residual:.2e}; trivial multiplier "
           f"{trivial.real:.12f}")
    if not success:
        msg = (f"Newton stalled: |(x(T) - x0, x'(T))| = {residual:.2e} after {it} iterations "
               f"(floor {floor:.1e})")
    hp, note = _weak_highprec(cm, x0, T, other, rel) if digits is None else (None, "")
    if hp is not None:
        x0, T, first = float(hp["amplitude_max"]), float(hp["period"]), \
            float(hp["amplitude_first_harmonic"])
        rel = {k: 10.0 ** -(HIGHPREC_DIGITS - 1) for k in rel}
    if note:
        msg += "; " + note
    return LimitCycle(
        success=bool(success), message=msg, model=cm.name, params=dict(cm.values),
        period=float(T), frequency=2 * math.pi / float(T), amplitude_max=float(x0),
        amplitude_first_harmonic=first, harmonics=coeffs, t=tt, x=ys[:-1, 0],
        xdot=ys[:-1, 1], floquet_multipliers=(trivial, other), stable=bool(abs(other) < 1.0),
        liouville=(float(np.linalg.det(Phi)), float(math.exp(yT[6]))),
        dissipation=Dissipation(total=float(total), gamma_plus=gp, gamma_minus=gm,
                                plus_factor=cm.plus_factor),
        energy_residual=float(cm.energy(ys[0, 0], 0.0) - cm.energy(yT[0], yT[1]) - total),
        iterations=it, residual=float(residual), history=tuple(history), method=meth.label,
        digits=None if digits is None else int(digits), mp=mp,
        accuracy={k: float(v) for k, v in rel.items()})
