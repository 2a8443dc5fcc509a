"""What an approximation predicts for a limit cycle, and the true value to compare it with.

:class:`Prediction` holds one approximation's cycle (a KBM order, the paper's
printed formulas, the energy-balance averaging); :func:`kbm_prediction` builds
it from a KBM derivation:

- ``a*``: the root of ``sum_{n<=N} mu**n A_n(a) = 0`` closest to the true
  first-harmonic amplitude (by construction no ``u_n`` holds a first harmonic,
  so ``a`` *is* the first-harmonic amplitude);
- ``omega* = omega0 + sum_{n<=N} mu**n B_n(a*)`` and ``T = 2 pi/omega*``;
- the reconstructed orbit ``x(psi) = a* cos psi + sum_{n<=N} mu**n u_n(a*, psi)``,
  ``x' = omega* dx/dpsi`` (``a`` is constant on the cycle), its maximum and
  harmonics;
- stability: the sign of ``dA/da(a*)`` and the multiplier ``exp(T dA/da(a*))``,
  which for the full series *is* the non-trivial Floquet multiplier (the KBM
  variables are a change of coordinates near the cycle);
- the dissipation ``Gamma = -int_0^T D(x, x') x' dt`` (paper eq. 10, ``D`` the part
  of ``mu F`` that vanishes at ``x' = 0``) over the reconstructed orbit.  Over a
  true cycle ``Gamma = 0`` exactly (energy balance); over the order-``N``
  orbit it equals ``int x' r_N dt`` with the residual ``r_N = O(mu**(N+1))``.

References
----------
N. N. Bogoliubov and Y. A. Mitropolsky, *Asymptotic Methods in the Theory of
Non-Linear Oscillations* (1961), ch. 1.
M. D'Acunto, "Friction force for self-excited systems", eqs. (5)-(10).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
import sympy as sp
from scipy.optimize import minimize_scalar

from kbm import KBMFunctions, KBMResult, averaged_cycles
from kbm.errors import KBMError, ParameterError
from kbm.parameters.bound import BoundModel
from kbm.model.builtins import Oscillator
from kbm.output.strict_json import json_fields
from kbm.symbols import x as X, xdot as V

from numerics.cycles import LimitCycle
from numerics._memo import memo
from numerics._show import num

__all__ = ["Prediction", "ERROR_KEYS", "numeric_value", "kbm_prediction", "derived",
           "reconstruct", "cycle_measures", "dissipation_functions"]

#: the quantities compared, in the order of the tables
ERROR_KEYS = ("amplitude", "amplitude_max", "frequency", "harmonic3", "floquet_multiplier",
              "floquet_exponent", "dissipation")


@dataclass(frozen=True, eq=False)
class Prediction:
    """The cycle one approximation predicts (a KBM order, or the paper's formulas).

    Attributes
    ----------
    label
        ``"KBM order N"``, ``"paper eqs. (5)-(9)"``, ``"energy order N"``.
    order
        The order ``N`` of the approximation (``0`` for the paper's formulas).
    source
        Which approximation: ``"kbm"`` (classical KBM), ``"paper"`` (the paper's
        printed formulas), ``"energy"`` (averaging about the conservative orbit).
    success, message
        Whether the approximation has a cycle near the true one, and why not.
    amplitude
        ``a*``, the predicted first-harmonic amplitude (the root of the amplitude equation).
    amplitude_max
        Maximum of the reconstructed ``x``.
    frequency, period
        ``omega*`` and ``2 pi/omega*``.
    harmonics
        Amplitudes of the harmonics of the reconstructed ``x``: ``|c_0|`` (mean),
        then ``2|c_m|`` for ``m >= 1`` (so ``harmonics[1]`` is the first-harmonic amplitude
        of the reconstruction).
    dA_da, stable, floquet_multiplier
        Slope of the amplitude equation at ``a*``, ``dA_da < 0``, ``exp(T dA_da)``
        (key ``"floquet_exponent"``: ``T dA_da``, compared with ``log|m|`` of the true cycle).
    dissipation, gamma_plus, gamma_minus
        ``Gamma = factor*Gamma_+ - Gamma_-`` (paper eqs. 10-11) over the reconstructed orbit.
    psi, x, xdot
        The reconstructed orbit on a uniform grid of ``psi`` in ``[0, 2 pi)``.
    """

    label: str
    order: int
    success: bool
    message: str
    amplitude: float = math.nan
    amplitude_max: float = math.nan
    frequency: float = math.nan
    period: float = math.nan
    harmonics: np.ndarray = field(default_factory=lambda: np.full(16, np.nan))
    dA_da: float = math.nan
    stable: bool = False
    floquet_multiplier: float = math.nan
    dissipation: float = math.nan
    gamma_plus: float = math.nan
    gamma_minus: float = math.nan
    psi: np.ndarray = field(default_factory=lambda: np.empty(0))
    x: np.ndarray = field(default_factory=lambda: np.empty(0))
    xdot: np.ndarray = field(default_factory=lambda: np.empty(0))
    source: str = "kbm"

    def __post_init__(self) -> None:
        for name in ("harmonics", "psi", "x", "xdot"):
            arr = np.array(getattr(self, name), dtype=float)
            arr.setflags(write=False)
            object.__setattr__(self, name, arr)

    def __repr__(self) -> str:
        if not self.success:
            return f"Prediction({self.label}: failed: {self.message})"
        return (f"Prediction({self.label}: a*={num(self.amplitude)}, x_max="
                f"{num(self.amplitude_max)}, T={num(self.period)}, "
                f"{'stable' if self.stable else 'unstable'})")

    def value(self, key: str) -> float:
        """The predicted value of one of :data:`ERROR_KEYS`."""
        if key == "harmonic3":
            return float(self.harmonics[3])
        if key == "floquet_exponent":
            return float(self.period * self.dA_da)
        return float(getattr(self, key))

    def to_json(self) -> dict:
        return json_fields(self, "order", "label", "success", "message", "amplitude",
                           "amplitude_max", "frequency", "period", "dA_da", "stable",
                           "floquet_multiplier", "dissipation",
                           harmonics=[float(h) for h in self.harmonics[:8]])


def derived(model: Oscillator | str, order: int) -> KBMResult:
    """:func:`kbm.derive` of ``model`` to ``order``, memoised (:func:`numerics._memo.memo`):
    the comparisons, validity maps and convergence studies of one model derive it once per
    process.  A built-in's name and its model are one entry.

    A pure-function memo: the key is immutable values (a frozen, hashable model or a coupled
    built-in's name, and an ``int``), :func:`kbm.derive` is a function of them alone and its
    result is frozen, so a cached result is equal to a fresh one (``tests/test_memo_purity.py``).
    What is computed from the result (its compiled functions, its averaged rates) is kept on
    the result itself (:meth:`kbm.KBMResult.functions`); the built-in ``sedf`` to order 2 is
    :func:`kbm.output.paper.engine_expansion`, the one object the errata evidence compares too."""
    if isinstance(model, str):
        from kbm.model.builtins import get_model

        try:
            model = get_model(model)
        except KBMError:  # a coupled built-in's name: derive reads it
            pass
    return _derived(model, int(order))


@memo(maxsize=16)
def _derived(model, order: int) -> KBMResult:
    from kbm import derive
    from kbm.output import paper
    from kbm.model.builtins import get_model

    if order == 2 and model == get_model("sedf"):  # the paper's derivation: one object, the
        return paper.engine_expansion()  # errata's, so its functions are compiled once
    return derive(model, order)


def numeric_value(cycle: LimitCycle, key: str) -> float:
    """The true value of one of :data:`ERROR_KEYS` from a computed :class:`LimitCycle`."""
    if key == "amplitude":
        return cycle.amplitude_first_harmonic
    if key == "harmonic3":
        return 2 * abs(cycle.harmonics[3])
    if key == "floquet_multiplier":
        return float(cycle.floquet_multipliers[1].real)
    if key == "floquet_exponent":
        return float(np.log(abs(cycle.floquet_multipliers[1])))
    if key == "dissipation":
        return cycle.dissipation.total
    return float(getattr(cycle, key))


def dissipation_functions(model: Oscillator, values: Mapping[str, sp.Expr]):
    """``(plus(x, v), minus(x, v), factor)`` with ``Gamma`` integrand ``factor*plus - minus``
    (:meth:`kbm.model.builtins.Oscillator.dissipation_parts`) at the given values."""
    plus, minus, factor = model.dissipation_parts()
    subs = {sp.Symbol(k): v for k, v in values.items()}
    fp = sp.lambdify((X, V), plus.subs(subs), modules="numpy")
    fm = sp.lambdify((X, V), minus.subs(subs), modules="numpy")
    return fp, fm, float(factor.subs(subs))


def reconstruct(x_of_psi, frequency: float, *, n_samples: int = 1024) -> tuple:
    """Samples ``(psi, x, x')`` of a cycle ``x(psi)`` with ``psi = frequency * t``.

    ``x'`` is ``frequency * dx/dpsi``, the derivative taken spectrally (exact for the
    trigonometric polynomials KBM produces, to rounding).
    """
    psi = np.linspace(0.0, 2 * np.pi, n_samples, endpoint=False)
    xs = np.asarray(x_of_psi(psi), dtype=float) * np.ones_like(psi)
    c = np.fft.rfft(xs)
    m = np.arange(c.size)
    c_d = 1j * m * c
    if n_samples % 2 == 0:
        c_d[-1] = 0.0
    dx = np.fft.irfft(c_d, n_samples)
    return psi, xs, frequency * dx


def cycle_measures(x_of_psi, psi, xs, vs, period, fp, fm, factor, n_harmonics):
    """``(max x, harmonic amplitudes, Gamma_+, Gamma_-, Gamma)`` of a reconstructed cycle.

    The maximum is refined with a bounded scalar search on ``x_of_psi``; the
    harmonics are ``|c_0|`` then ``2|c_m|``; the dissipation integrals are the mean
    of the integrand over the uniform ``psi`` grid times the period (spectrally
    accurate for a smooth periodic orbit).
    """
    i = int(np.argmax(xs))
    h = psi[1] - psi[0]
    r = minimize_scalar(lambda s: -float(x_of_psi(np.array([s]))[0]),
                        bounds=(psi[i] - h, psi[i] + h), method="bounded",
                        options={"xatol": 1e-13})
    xmax = max(float(xs[i]), -float(r.fun))
    coeffs = np.fft.rfft(xs) / xs.size
    harm = 2 * np.abs(coeffs[:n_harmonics])
    harm[0] /= 2
    gp = period * float(np.mean(np.asarray(fp(xs, vs)) * np.ones_like(xs)))
    gm = period * float(np.mean(np.asarray(fm(xs, vs)) * np.ones_like(xs)))
    return xmax, harm, gp, gm, factor * gp - gm


def _pick(cycles, target):
    if not cycles:
        return None
    if target is None:
        stable = [c for c in cycles if c.stable] or list(cycles)
        return max(stable, key=lambda c: c.amplitude)
    return min(cycles, key=lambda c: abs(c.amplitude - target))


def kbm_prediction(result: KBMResult, values: Mapping[str, object] | BoundModel,
                   order: int | None = None, *, target_amplitude: float | None = None,
                   functions: KBMFunctions | None = None, n_samples: int = 1024,
                   n_harmonics: int = 16, a_max: float = 20.0) -> Prediction:
    """The cycle predicted by the order-``order`` KBM expansion.

    Parameters
    ----------
    result
        A :class:`kbm.KBMResult` (its model may keep parameters symbolic).
    values
        ``mu`` and every parameter of the model (scaled or physical names), or a
        :class:`~kbm.parameters.bound.BoundModel` of the same model.
    order
        KBM order ``N <= result.order`` (default ``result.order``).
    target_amplitude
        Of several roots ``a*`` take the one closest to this (e.g. the true
        first-harmonic amplitude); default: the stable root of largest amplitude.
    functions
        Compiled ``result.functions("numpy")`` to reuse.

    Returns
    -------
    Prediction
        ``success = False`` (and a message) when the averaged equation has no cycle.
    """
    N = result.order if order is None else int(order)
    model = result.model
    label = f"KBM order {N}"
    try:
        vals = values.values if isinstance(values, BoundModel) else model.resolve(dict(values))
        need = {p: vals[p] for p in result.params}
        cycles = averaged_cycles(result, {"mu": vals["mu"], **need}, order=N, a_max=a_max)
    except KeyError as exc:
        raise ParameterError(f"kbm_prediction needs a value for {exc.args[0]}") from None
    except KBMError as exc:
        return Prediction(label=label, order=N, success=False, message=str(exc))
    cyc = _pick(cycles, target_amplitude)
    if cyc is None:
        return Prediction(label=label, order=N, success=False,
                          message=f"the order-{N} averaged amplitude equation has no root "
                                  f"0 < a <= {a_max}")
    fns = functions or result.functions("numpy")
    m = float(vals["mu"])
    pars = [float(need[p]) for p in result.params]

    def x_of_psi(p):
        return fns.displacement(cyc.amplitude, p, m, *pars, order=N)

    try:
        psi, xs, vs = reconstruct(x_of_psi, cyc.frequency, n_samples=n_samples)
        fp, fm, factor = dissipation_functions(model, vals)
        xmax, harm, gp, gm, gam = cycle_measures(x_of_psi, psi, xs, vs, cyc.period, fp, fm,
                                                  factor, n_harmonics)
    except KBMError as exc:
        return Prediction(label=label, order=N, success=False, message=str(exc),
                          amplitude=cyc.amplitude, frequency=cyc.frequency)
    others = len(cycles) - 1
    msg = (f"a* = {cyc.amplitude:.10g} ({'stable' if cyc.stable else 'unstable'})"
           + (f"; {others} other root(s) of the averaged equation" if others else ""))
    return Prediction(label=label, order=N, success=True, message=msg,
                      amplitude=cyc.amplitude, amplitude_max=xmax, frequency=cyc.frequency,
                      period=cyc.period, harmonics=harm, dA_da=cyc.dA_da, stable=cyc.stable,
                      floquet_multiplier=cyc.floquet_multiplier, dissipation=gam,
                      gamma_plus=gp, gamma_minus=gm, psi=psi, x=xs, xdot=vs)
