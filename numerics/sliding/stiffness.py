"""The cost of a driven-slider run with an explicit integrator: the stiffness of its damping.

An explicit Runge-Kutta method is stable only for steps ``h <= c/|dD/dx'|``, with ``D`` the
damping force of ``x'' + D(x, x', t) + ... = 0`` and ``c`` the length of the method's
stability interval on the negative real axis (about 6 for DOP853, measured ``|dD/dx'| h =
6.4`` at ``mu = 1e3, 1e4``; E. Hairer, G. Wanner, *Solving ODEs II*, sec. IV.2), so a run to
``T`` needs about ``N = int_0^T |dD/dx'| dt / c`` steps.

``dD/dx' = -mu dF/dx'`` is derived from the model's one symbolic definition (sympy's
derivative of ``F``, :func:`damping_derivative`, memoised per model like the compiled
equations of :mod:`numerics.sliding.driven`): its part attached to the stage
(:attr:`~kbm.model.oscillator.Oscillator.stage_relative`, measured by the spring's extension
``x - v t``) and the rest, measured by the lab-frame ``x``.  Along a run ``|dD/dx'|`` is bounded
by its majorant (every coefficient of the polynomial in ``x, x'`` by its modulus) on the
envelope of the motion, in mean squares (the odd parts of the oscillation average out):

- the lab-frame position: ``x^2 <~ (v t)^2 + A^2``: the spring drags the slider behind the
  stage (``x <= v t`` while the friction force ``Omega^2 (v t - x)`` is positive) and the
  self-excitation alone keeps it within its cycle's amplitude ``A``;
- the spring's extension: ``(x - v t)^2 <~ max(d, A)^2``, ``d`` the largest pinning force
  over the spring's stiffness (``Delta/Omega^2``);
- the velocity: ``x'^2 <~ v^2 + (A omega0)^2``.

``A`` is the first-order KBM amplitude of the cycle: the positive root where the mean power
of the dissipative force ``<mu F_diss x'>`` over ``x = a cos phi, x' = -a omega0 sin phi``
turns from gain to loss (0 for none).  For the SEDF (paper eq. 3) ``|dD/dx'| = mu |beta x^2 -
1| <= mu (beta x^2 + 1)`` and ``A = 2/sqrt(beta)``, so

``N = int_0^T mu (beta (v t)^2 + 5) dt / c = mu (beta v^2 T^3/3 + 5 T) / c``;

for the CDC (eq. 12) ``N = mu T/c``; for ``sedf_comoving`` ``N = mu (max(beta d^2, 4) + 1)
T/c``.  Measured (``kbm slide sedf -p Delta=3 -p beta=1 -p v=0.01``, 0.3 ms a step):
13 442 steps to ``T = 1500``, 51 606 to 3000, 205 818 to 6000, against ``N`` = 1 900,
15 000, 120 000 (the steps are set by the accuracy, ``|dD/dx'| h`` = 1.3-1.8, until the
cubic term dominates); at ``mu = 1e4, v = 0.1, T = 15``: 47 119 against 144 000.
Implicit methods (Radau, BDF, LSODA) have no such bound.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np
import sympy as sp

from kbm.errors import ParameterError
from kbm.model.builtins import Oscillator, get_model
from kbm.parameters.bound import bind
from kbm.symbols import mu as MU, t as T, x as X, xdot as V

from numerics._memo import memo
from numerics.errors import IntegrationError

__all__ = ["STABILITY_INTERVAL", "stiff_steps", "stiff_t_end", "StepGuard", "damping_rate",
           "damping_text", "damping_derivative", "DampingDerivative", "damping_envelope"]

#: length of the real stability interval of the explicit methods (step ``h <= c/|lambda|``)
STABILITY_INTERVAL = {"DOP853": 6.0, "RK45": 3.3, "RK23": 2.5}

#: the spring's extension ``x - v t`` (the variable of a stage-attached damping)
_Z = sp.Symbol("x_rel")
_A, _C, _S = sp.symbols("a c s")
#: Gauss-Legendre nodes of ``int_0^T`` (exact for the polynomial envelopes up to degree 15)
_GL = np.polynomial.legendre.leggauss(8)


@dataclass(frozen=True, eq=False)
class DampingDerivative:
    """``dD/dx' = -mu dF/dx'`` of one slider model, split by frame, with its envelope's pieces.

    Attributes
    ----------
    lab, stage
        The derivative of the lab-frame part of ``mu F`` (in ``x, xdot``) and of its
        stage-attached part (in ``x_rel = x - v t`` and ``xdot``), so ``dD/dx' = lab(x) +
        stage(x - v t)``.
    text
        ``|dD/dx'|`` for the messages, printed from the same expressions.
    rate
        ``rate(values, x, xdot, x - v t)``: ``|dD/dx'|`` at a state (``values`` the scaled
        parameters).
    lab_terms, stage_terms
        The monomials ``(i, j, coefficient)`` of ``lab`` in ``x^i xdot^j`` and of ``stage``
        in ``(x - v t)^i xdot^j``; None if not a polynomial.
    power
        The coefficients (highest power first) of the mean power ``<mu F_diss x'>`` of the
        dissipative force on the cycle ``x = a cos phi``, a polynomial in ``a`` (empty if not).
    pinning, omega
        The largest pinning force (``sin``, ``cos`` at 1) and the spring's ``omega0``.
    """

    lab: sp.Expr
    stage: sp.Expr
    text: str
    rate: Callable
    lab_terms: tuple | None
    stage_terms: tuple | None
    power: tuple
    pinning: Callable
    omega: Callable


def _lambdified(expr: sp.Expr) -> Callable[[Mapping], float]:
    """``expr`` of the parameters as a function of a mapping of their values."""
    free = tuple(sorted(str(s) for s in expr.free_symbols))
    f = sp.lambdify([sp.Symbol(n) for n in free], expr, modules="math")

    def value(vals: Mapping[str, float]) -> float:
        try:
            return float(f(*(vals[n] for n in free)))
        except KeyError as e:
            raise ParameterError(f"the damping's estimate needs the parameter {e.args[0]}; "
                                 f"give it with -p {e.args[0]}=VALUE") from None
    return value


def _terms(expr: sp.Expr, var: sp.Symbol) -> tuple | None:
    """The monomials ``c var^i xdot^j`` of ``expr`` as ``((i, j, c), ...)``; None if not a
    polynomial in ``var, xdot``."""
    try:
        poly = sp.Poly(expr, var, V)
    except sp.PolynomialError:
        return None
    if poly.free_symbols & {X, V, _Z, T} - {var, V}:
        return None
    return tuple((i, j, _lambdified(c)) for (i, j), c in poly.terms())


def _average(expr: sp.Expr) -> sp.Expr:
    """The mean over ``phi`` of a polynomial in ``c = cos phi, s = sin phi`` (``<c^m s^n> =
    (m-1)!! (n-1)!!/(m+n)!!`` for even ``m, n``, else 0)."""
    poly = sp.Poly(sp.expand(expr), _C, _S)
    return sp.Add(*(k * sp.factorial2(m - 1) * sp.factorial2(n - 1) / sp.factorial2(m + n)
                    for (m, n), k in poly.terms() if m % 2 == 0 and n % 2 == 0))


def _text(lab: sp.Expr, stage: sp.Expr) -> str:
    """``|dD/dx'| = mu |...|`` printed from the derivative (sympy's order, ``^`` powers)."""
    inner = sp.expand((lab + stage) / MU)
    lead = "mu"
    if MU in inner.free_symbols:  # mu is not a factor
        inner, lead = sp.expand(lab + stage), ""
    body = sp.sstr(inner).replace("**", "^").replace("*", " ").replace(str(_Z), "(x - v t)")
    if lab + stage == 0:
        text = "0"
    elif inner == 1 and lead:
        text = "mu"
    elif inner.free_symbols & {X, V, _Z}:
        text = f"{lead} |{body}|".strip()
    else:
        text = f"{lead} {body}".strip()
    grows = " (growing with |x| ~ v t)" if X in lab.free_symbols else ""
    return f"|dD/dx'| = {text}{grows}"


@memo(maxsize=16)
def damping_derivative(model: str | Oscillator) -> DampingDerivative:
    """``dD/dx' = -mu dF/dx'`` of a slider model, derived once from its symbolic ``F``.

    Parameters
    ----------
    model
        A built-in slider's name (:data:`kbm.model.builtins.SLIDERS`) or an
        :class:`~kbm.model.oscillator.Oscillator` with ``omega0`` its spring
        (``stage_relative`` the part of ``F`` measured from the stage).

    Returns
    -------
    DampingDerivative
        The derivative by frame, its message text, and the pieces of the envelope of
        :func:`damping_envelope` (module docstring).
    """
    m = get_model(model) if isinstance(model, str) else model
    rel = m.stage_relative
    lab = sp.expand(-MU * sp.diff(m.F - rel, V))
    stage = sp.expand(-MU * sp.diff(rel, V)).subs(X, _Z)
    w = m.omega0
    gain = sp.expand(m.dissipative_force().subs({X: _A * _C, V: -_A * w * _S}) * (-_A * w * _S))
    try:
        mean = sp.Poly(_average(gain), _A)
        power = tuple(_lambdified(k) for k in mean.all_coeffs())
    except sp.PolynomialError:
        power = ()
    cons = m.conservative_force().replace(lambda e: isinstance(e, (sp.sin, sp.cos)),
                                          lambda e: sp.Integer(1))
    pin = sp.Add(*(sp.Abs(term) for term in sp.Add.make_args(sp.expand(cons))
                   if X not in term.free_symbols))
    names = tuple(sorted(str(s) for s in (lab + stage).free_symbols - {X, V, _Z}))
    f = sp.lambdify((X, V, _Z, *map(sp.Symbol, names)), lab + stage, modules="math")

    def rate(vals: Mapping[str, float], x: float, xdot: float, z: float) -> float:
        return abs(float(f(x, xdot, z, *(vals[n] for n in names))))
    return DampingDerivative(lab=lab, stage=stage, text=_text(lab, stage), rate=rate,
                             lab_terms=_terms(lab, X), stage_terms=_terms(stage, _Z),
                             power=power, pinning=_lambdified(pin), omega=_lambdified(w))


def _values(model: str | Oscillator, p: Mapping[str, float]) -> dict[str, float]:
    """The model's scaled parameter values from the physical ones (``v`` aside)."""
    m = get_model(model) if isinstance(model, str) else model
    own = {k: v for k, v in p.items() if k != "v"}
    return dict(bind(m, own).floats)


def _amplitude(d: DampingDerivative, vals: Mapping[str, float]) -> float:
    """The first-order KBM amplitude ``A`` of the self-excited cycle (0 for none)."""
    if not d.power:
        return 0.0
    coeffs = np.array([c(vals) for c in d.power])
    if not np.any(coeffs):
        return 0.0
    roots = np.roots(coeffs)
    slope = np.polyder(coeffs)
    stable = [r.real for r in roots if abs(r.imag) <= 1e-12 * abs(r) and r.real > 0
              and np.polyval(slope, r.real) < 0]
    return max(stable, default=0.0)


def damping_envelope(model: str | Oscillator, p: Mapping[str, float]
                     ) -> Callable[[np.ndarray], np.ndarray]:
    """The bound of ``|dD/dx'|`` at times ``t`` on the envelope of the motion (module docstring).

    Parameters
    ----------
    model
        As in :func:`damping_derivative`.
    p
        The physical parameters (``mu, beta, Delta, Omega, v``, ...).

    Returns
    -------
    callable
        ``t -> sum |c_ij| S^(i/2) S_v^(j/2)`` over the monomials ``c_ij x^i x'^j`` of
        ``dD/dx'``, with the mean squares ``S = (v t)^2 + A^2`` (lab frame) or ``max(d,
        A)^2`` (stage frame) and ``S_v = v^2 + (A omega0)^2``; not a polynomial: the
        largest ``|dD/dx'|`` on a grid of that box.
    """
    d = damping_derivative(model)
    vals = _values(model, p)
    v = float(p.get("v", 0.0))
    amp = _amplitude(d, vals)
    w = d.omega(vals)
    s_z = max(d.pinning(vals) / w**2, amp) ** 2
    s_v = v * v + (amp * w) ** 2
    lab = [(i, j, abs(c(vals))) for i, j, c in d.lab_terms or ()]
    stage = [(i, j, abs(c(vals))) for i, j, c in d.stage_terms or ()]

    def bound(t: np.ndarray) -> np.ndarray:
        s_x = (v * np.asarray(t, dtype=float)) ** 2 + amp**2
        if d.lab_terms is None or d.stage_terms is None:
            return _sampled(d, vals, s_x, s_z, s_v)
        out = sum((c * s_x ** (i / 2) * s_v ** (j / 2) for i, j, c in lab), np.zeros_like(s_x))
        return out + sum(c * s_z ** (i / 2) * s_v ** (j / 2) for i, j, c in stage)
    return bound


def _sampled(d: DampingDerivative, vals, s_x: np.ndarray, s_z: float, s_v: float):
    """``max |dD/dx'|`` over a 9-point grid of each of ``x, x - v t, x'`` in the envelope."""
    u = np.linspace(-1.0, 1.0, 9)
    out = []
    for sx in np.atleast_1d(s_x):
        out.append(max(d.rate(vals, a * math.sqrt(sx), b * math.sqrt(s_v), c * math.sqrt(s_z))
                       for a in u for b in u for c in u))
    return np.asarray(out)


def _lambda_integral(model: str | Oscillator, p: Mapping[str, float], t_end: float,
                     envelope: Callable | None = None) -> float:
    """``int_0^T |dD/dx'| dt`` on the envelope of the module docstring (Gauss-Legendre)."""
    nodes, weights = _GL
    bound = envelope or damping_envelope(model, p)
    half = t_end / 2
    return float(half * np.dot(weights, np.asarray(bound(half * (nodes + 1)), dtype=float)))


def stiff_steps(model: str | Oscillator, p: Mapping[str, float], t_end: float,
                method: str) -> float:
    """Steps an explicit ``method`` needs for stability alone up to ``t_end`` (0 if implicit).

    Parameters
    ----------
    model
        A slider's name (``"sedf"``, ``"cdc"``, ``"sedf_comoving"``) or an
        :class:`~kbm.model.oscillator.Oscillator` (:func:`damping_derivative`).
    p
        The physical parameters (``mu, beta, Delta, Omega, v``).
    t_end
        Final time.
    method
        The :func:`scipy.integrate.solve_ivp` method.

    Returns
    -------
    float
        ``int_0^T |dD/dx'| dt / c`` (module docstring).
    """
    c = STABILITY_INTERVAL.get(method)
    return 0.0 if c is None else _lambda_integral(model, p, t_end) / c


def stiff_t_end(model: str | Oscillator, p: Mapping[str, float], method: str, steps: float,
                t_end: float) -> float:
    """The largest final time (below ``t_end``) whose stability steps stay within ``steps``."""
    c = STABILITY_INTERVAL.get(method)
    if c is None:
        return t_end
    envelope = damping_envelope(model, p)
    lo, hi = 0.0, t_end
    for _ in range(60):
        mid = (lo + hi) / 2
        fits = _lambda_integral(model, p, mid, envelope) / c <= steps
        lo, hi = (mid, hi) if fits else (lo, mid)
    return lo


class _Exhausted(Exception):
    """Raised inside the right-hand side when the evaluation budget is spent."""

    def __init__(self, t: float, y):
        super().__init__()
        self.t, self.y = t, y


class StepGuard:
    """A right-hand side that stops the integration after ``steps`` steps' worth of calls.

    ``solve_ivp`` has no bound on its steps; this wrapper counts the evaluations of ``rhs``
    (``evals_per_step`` a step: 12 for DOP853 and 3 more for its dense output) and raises
    :class:`numerics.errors.IntegrationError` from :meth:`run` with the time reached, the
    steps taken and the damping's ``|dD/dx'|`` there, so a run never hangs.
    """

    def __init__(self, rhs: Callable, steps: int, method: str, evals_per_step: int = 16):
        self.rhs, self.steps, self.method = rhs, int(steps), method
        self.limit, self.calls = self.steps * evals_per_step, 0

    def __call__(self, t, y):
        self.calls += 1
        if self.calls > self.limit:
            raise _Exhausted(float(t), y)
        return self.rhs(t, y)

    def run(self, solve: Callable, t_end: float, stiffness: Callable[[float, object], float]):
        """``solve(self)``; on an exhausted budget an :class:`IntegrationError` with numbers
        (``stiffness(t, y)`` the damping's ``|dD/dx'|`` at the state ``y`` reached)."""
        try:
            return solve(self)
        except _Exhausted as e:
            x = float(e.y[0])
            lam = stiffness(e.t, e.y)
            raise IntegrationError(
                f"the integration stopped at t = {e.t:.6g} of t_end = {t_end:g} after about "
                f"{self.steps:.3g} steps (the limit of this run): at x = {x:.4g} the damping "
                f"has |dD/dx'| = {lam:.3g}, so an explicit step is at most about "
                f"{STABILITY_INTERVAL.get(self.method, 6.0) / max(lam, 1e-300):.3g}; lower mu "
                "or t_end") from None


def damping_text(model: str | Oscillator) -> str:
    """``|dD/dx'|`` of ``model`` for the messages, printed from its derivative
    (:func:`damping_derivative`: ``mu`` for the CDC, ``mu |beta x^2 - 1|`` for the SEDF)."""
    return damping_derivative(model).text


def damping_rate(model: str | Oscillator, p: Mapping[str, float]
                 ) -> Callable[[float, object], float]:
    """``|dD/dx'|`` at time ``t`` and state ``y = (x, x', ...)`` (:func:`damping_derivative`)."""
    d, vals, v = damping_derivative(model), _values(model, p), float(p.get("v", 0.0))
    return lambda t, y: d.rate(vals, float(y[0]), float(y[1]), float(y[0]) - v * float(t))
