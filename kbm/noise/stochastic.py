"""First-order stochastic averaging of the amplitude and phase (Stratonovich-Khasminskii).

The noisy oscillator (the paper's eq. 1 with unit mass and ``eta = sqrt(2 D) xi``)

``x'' + omega0^2 x = mu F(x, x') + sqrt(2 D) xi(t)``,  ``<xi(t) xi(t')> = delta(t - t')``,

with ``D`` of order ``mu``, is written ``x = a cos psi``, ``x' = -a omega0 sin psi``,
``psi = omega0 t + phi``.  Ito's formula for ``a^2 = x^2 + x'^2/omega0^2`` and for ``phi``,
averaged over ``psi`` (the limit theorem of Stratonovich and Khasminskii), gives the Ito
equations

``da   = [mu A_1(a) + D/(2 omega0^2 a)] dt + (sqrt(D)/omega0) dW_1``,
``dphi = mu B_1(a) dt + (sqrt(D)/(omega0 a)) dW_2``,

with ``W_1, W_2`` independent Wiener processes and ``A_1 = -<F sin psi>/omega0``,
``B_1 = -<F cos psi>/(a omega0)`` the first-order KBM coefficients (:func:`kbm.derive`):
the deterministic parts are the KBM equations, the noise adds the drift ``D/(2 omega0^2
a)`` (the Ito correction of ``a = sqrt(a^2)``) and the diffusions.  The amplitude's
Fokker-Planck equation has the constant diffusion ``s = D/omega0^2``; its stationary
solution with zero flux is

``P(a) = a exp( (2 omega0^2 mu / D) int_0^a A_1(s) ds ) / Z``,

in closed form whenever ``A_1`` integrates (always for polynomial ``F``, exactly, in
rationals).  For linear damping ``F = -2 zeta x'`` it is Rayleigh's density with ``<a^2> =
D/(mu zeta omega0^2)``, twice the exact ``<x^2> = kT/omega0^2``.

References
----------
R. L. Stratonovich, *Topics in the Theory of Random Noise*, vol. 2 (Gordon and Breach,
1967), ch. 9 (the van der Pol oscillator with noise); R. Z. Khasminskii, Theory Probab.
Appl. 11 (1966) 390; J. B. Roberts and P. D. Spanos, Int. J. Non-Linear Mech. 21 (1986)
111 (stochastic averaging, eqs. 19-24).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import mpmath
import numpy as np
import sympy as sp

from ..expansion.one_dof import derive
from ..errors import ModelError, ParameterError
from ..output.latex import latex
from ..parameters.names import noise_intensity
from ..model.builtins import Oscillator, get_model
from ..symbols import a, mu

__all__ = ["StochasticAveraging", "stochastic_average", "NOISE", "noisy_model"]

#: the noise intensity of ``sqrt(2 D) xi``
NOISE = sp.Symbol("D", positive=True)
_s = sp.Dummy("s", positive=True)


@dataclass(frozen=True)
class StochasticAveraging:
    """The averaged amplitude-phase diffusion of a noisy weakly nonlinear oscillator.

    Attributes
    ----------
    model : kbm.model.builtins.Oscillator
    drift_a, diffusion_a : sympy.Expr
        Ito drift ``mu A_1 + D/(2 omega0^2 a)`` and variance rate ``D/omega0^2`` of ``a``.
    drift_phase, diffusion_phase : sympy.Expr
        ``mu B_1`` and ``D/(omega0^2 a^2)`` of the phase ``phi`` (``psi = omega0 t + phi``).
    log_density : sympy.Expr or None
        ``ln a + (2 omega0^2 mu/D) int_0^a A_1``: the stationary ``ln P(a)`` up to a constant;
        ``None`` when there is no stationary density (the reason in :attr:`reason`).
    reason : str
        Why there is no stationary density, else ``""``.
    """

    model: Oscillator
    drift_a: sp.Expr
    diffusion_a: sp.Expr
    drift_phase: sp.Expr
    diffusion_phase: sp.Expr
    log_density: sp.Expr | None
    reason: str = ""

    def __repr__(self) -> str:
        return (f"StochasticAveraging({self.model.name}: da = [{self.drift_a}] dt + "
                f"sqrt({self.diffusion_a}) dW)")

    # -- output -----------------------------------------------------------------------
    def latex(self) -> str:
        """The Ito equations and the stationary density as ``align`` lines (same bytes
        for the same model, whatever ``PYTHONHASHSEED``)."""
        w0 = self.model.omega0
        noise_a = r"\sqrt{D}" if w0 == 1 else r"\frac{\sqrt{D}}{" + latex(w0) + "}"
        noise_p = (r"\frac{\sqrt{D}}{a}" if w0 == 1
                   else r"\frac{\sqrt{D}}{" + latex(w0) + r"\,a}")

        def drift(e):
            return "" if e == 0 else r"\Bigl[" + latex(e) + r"\Bigr]\,\mathrm{d}t + "

        lines = [r"\mathrm{d}a &= " + drift(self.drift_a) + noise_a + r"\,\mathrm{d}W_1",
                 r"\mathrm{d}\varphi &= " + drift(self.drift_phase) + noise_p
                 + r"\,\mathrm{d}W_2"]
        if self.log_density is not None:
            lines.append(r"\ln P(a) &= " + latex(self.log_density).replace(r"\log", r"\ln")
                         + r" + \mathrm{const}")
        return " \\\\\n".join(lines)

    # -- numbers ----------------------------------------------------------------------
    def _values(self, params: Mapping[str, object]) -> dict:
        import math

        vals = {}
        for k, v in dict(params).items():
            if k == "D":
                vals[NOISE] = sp.Float(noise_intensity(v, "a stationary density needs noise"),
                                       30)
                continue
            try:
                val = float(v)  # "inf" and "nan" are numbers, refused below
            except (TypeError, ValueError):
                try:
                    val = float(sp.sympify(v))
                except (sp.SympifyError, TypeError, ValueError):
                    val = None
            if val is None:
                raise ParameterError(f"{k} = {v!r} is not a number") from None
            if not math.isfinite(val):
                raise ParameterError(f"{k} = {v!r} must be a finite number")
            vals[sp.Symbol(k)] = sp.Float(val, 30)
        if NOISE not in vals:
            raise ParameterError("give the noise intensity D (x'' + ... = sqrt(2 D) xi)")
        if mu in vals and not vals[mu] > 0:
            raise ParameterError(f"mu = {vals[mu]} must be > 0 (mu < 0 turns the damping "
                                 "into a drive: no stationary density)")
        return vals

    def _log_density_of(self, params):
        if self.log_density is None:
            raise ModelError(f"no stationary amplitude density for {self.model.name!r}: "
                             f"{self.reason}")
        return amplitude_function(self.log_density.subs(self._values(params)), self.model.name)

    def moment(self, k: int, params: Mapping[str, object]) -> float:
        """``<a^k>`` of the normalised stationary density (mpmath quadrature, 30 digits).

        Parameters
        ----------
        k : int
        params : mapping
            ``mu``, ``D`` and the model's parameters.
        """
        f = self._log_density_of(params)
        with mpmath.workdps(30):
            Z, m = quadratures(f, [lambda x: x**0, lambda x: x**k])
            return float(m / Z)

    def density(self, grid, params: Mapping[str, object]) -> np.ndarray:
        """The normalised stationary density ``P(a)`` on ``grid`` (numpy array)."""
        return density_on(grid, self._log_density_of(params))

    def numpy_functions(self):
        """``(drift_a, diffusion_a, drift_phase, diffusion_phase)`` as vectorised numpy
        functions of ``(a, mu, D, *parameters)`` (parameters in :attr:`parameters` order)."""
        args = [a, mu, NOISE, *[sp.Symbol(n) for n in self.parameters]]
        return tuple(sp.lambdify(args, e, modules="numpy") for e in
                     (self.drift_a, self.diffusion_a, self.drift_phase, self.diffusion_phase))

    @property
    def parameters(self) -> tuple[str, ...]:
        """The model's parameter names in the functions' argument order."""
        syms = set().union(*[e.free_symbols for e in (self.drift_a, self.drift_phase)])
        return tuple(sorted(s.name for s in syms - {a, mu, NOISE}))


def _confines(A1: sp.Expr) -> tuple[bool, str]:
    """Whether ``int_0^a A_1`` tends to ``-oo`` (the density is normalisable)."""
    if sp.simplify(A1) == 0:
        return False, ("the averaged drift mu A_1 is 0 (a conservative F): the noise feeds "
                       "energy in and nothing takes it out")
    if A1.free_symbols - {a}:
        return True, ""  # decided at numeric values (moment/density raise if it does not)
    try:
        lim = sp.limit(A1, a, sp.oo)
    except (NotImplementedError, ValueError):
        return True, ""
    if lim in (sp.oo,) or (lim.is_number and lim.is_finite and lim >= 0):
        limit = "+infinity" if lim == sp.oo else str(lim)
        return False, (f"the averaged drift mu A_1 = mu*({A1}) tends to {limit} at large "
                       "amplitude: it does not confine the noisy amplitude")
    return True, ""


def noisy_model(model: Oscillator | str, params: Mapping[str, object] | None,
                what: str) -> tuple[Oscillator, dict]:
    """The autonomous model of a noise averaging (``what``) and the values substituted
    before it (``mu`` and ``D`` left symbolic); raises as :func:`stochastic_average`."""
    m = get_model(model) if isinstance(model, str) else model
    if "D" in m.parameters:
        raise ParameterError(f"model {m.name!r} has a parameter named D, the noise intensity's "
                             "name; rename it")
    m.require_autonomous(what)
    return m, {k: v for k, v in dict(params or {}).items() if k not in ("mu", "D")}


def _support(f) -> tuple[list, object]:
    """``(points, max ln P)`` of a log-density ``f``: the quadrature's break points ``0,
    peak/2, peak, (peak + end)/2, end``, past ``end`` the density below ``exp(-80)`` of its
    peak."""
    top = mpmath.mpf(8)
    while True:
        grid = [top * i / 512 for i in range(1, 513)]
        vals = [f(g) for g in grid]
        i = int(np.argmax([float(v) for v in vals]))
        if vals[-1] < vals[i] - 80:
            peak, end = float(grid[i]), float(top)
            return [0, peak / 2, peak, (peak + end) / 2, end], vals[i]
        top *= 2
        if top > 1e6:
            if i < len(grid) - 1 and vals[-1] < vals[i]:
                raise ModelError(f"the stationary amplitude density peaks at a = "
                                 f"{float(grid[i]):.3g} and is still above exp(-80) of its "
                                 "peak at a = 1e6, beyond what the quadrature covers; lower "
                                 "the noise D")
            raise ModelError("the stationary amplitude density does not decay up to "
                             "a = 1e6: it is not normalisable at these values, or it peaks "
                             "beyond a = 1e6 (then lower the noise D)")


def amplitude_function(expr: sp.Expr, model: str):
    """``expr`` as an mpmath function of ``a`` (the amplitude densities of both orders of the
    averaging), or a :class:`ParameterError` naming the values it still needs."""
    free = expr.free_symbols - {a}
    if free:
        raise ParameterError(f"model {model!r} needs values for "
                             f"{', '.join(sorted(s.name for s in free))}")
    return sp.lambdify(a, expr, modules="mpmath")


def quadratures(f, weights) -> list:
    """``int_0^inf w(a) exp(f(a) - max f) da`` for each ``w`` of ``weights``, ``f`` the log of
    an amplitude density (mpmath quadrature at 30 digits, cut where it is ``exp(-80)`` of
    its peak); the moments of both orders of the averaging."""
    with mpmath.workdps(30):
        pts, fmax = _support(f)
        return [mpmath.quad(lambda s, w=w: w(s) * mpmath.exp(f(s) - fmax), pts)
                for w in weights]


def density_on(grid, f, h=lambda s: 1) -> np.ndarray:
    """The normalised density ``h exp(f)`` on ``grid`` (0 at ``a <= 0``), as
    :func:`quadratures` integrates it."""
    with mpmath.workdps(30):
        pts, fmax = _support(f)
        Z = mpmath.quad(lambda s: h(s) * mpmath.exp(f(s) - fmax), pts)
        g = np.asarray(grid, float)
        out = [float(h(mpmath.mpf(float(s))) * mpmath.exp(f(mpmath.mpf(float(s))) - fmax) / Z)
               if s > 0 else 0.0 for s in g.ravel()]
    return np.asarray(out).reshape(g.shape)


def stochastic_average(model: Oscillator | str,
                       params: Mapping[str, object] | None = None) -> StochasticAveraging:
    """First-order stochastic averaging of ``x'' + omega0^2 x = mu F + sqrt(2 D) xi``.

    Parameters
    ----------
    model : str or kbm.model.builtins.Oscillator
        An autonomous model (a slider's stage velocity ``v`` must be 0).
    params : mapping, optional
        Parameter values substituted exactly before the averaging (``mu`` and ``D`` are
        kept symbolic; give them to :meth:`StochasticAveraging.moment`).

    Raises
    ------
    kbm.errors.NonAutonomousError
        For a driven model.
    kbm.errors.ParameterError
        For a model parameter named ``D`` (the noise's name).

    Examples
    --------
    >>> st = stochastic_average("vdp")
    >>> st.drift_a
    D/(2*a) + mu*(-a**3/8 + a/2)
    >>> st.log_density
    log(a) - a**4*mu/(16*D) + a**2*mu/(2*D)
    >>> round(st.moment(2, {"mu": 0.05, "D": 0.01}), 6)
    4.003403
    """
    m, fixed = noisy_model(model, params, "the stochastic averaging")
    res = derive(m, 1, fixed or None)
    w0 = res.model.omega0
    A1, B1 = sp.expand(res.A[1]), sp.expand(res.B[1])
    drift_a = mu * A1 + NOISE / (2 * w0**2 * a)
    ok, why = _confines(A1)
    log_p = None
    if ok:
        integral = sp.integrate(A1.subs(a, _s), (_s, 0, a))
        if integral.has(sp.Integral):
            why = f"the integral of A_1 = {A1} has no closed form"
        else:
            log_p = sp.expand(sp.log(a) + 2 * w0**2 * mu * integral / NOISE)
    return StochasticAveraging(res.model, drift_a, NOISE / w0**2, mu * B1,
                               NOISE / (w0**2 * a**2), log_p, "" if log_p is not None else why)
