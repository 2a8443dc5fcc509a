"""Every cycle an analysis predicts, in one form: ``kbm predict``.

:func:`predict` lists the limit cycles of a model predicted either by

- ``method="energy"``: averaging about the conservative orbit of
  ``x'' + g(x) = 0`` with only the damping as perturbation
  (:func:`numerics.energy.predict_cycles`; order 1 is the energy balance
  ``Gamma(E) = 0``, the paper's eq. (10) as a cycle condition), or
- ``method="kbm"``: classical KBM (generating motion ``a cos psi``), every root of
  the order-``N`` averaged amplitude equation (:func:`kbm.averaged_cycles`) with its
  reconstructed orbit,

as :class:`numerics.energy.PredictedCycle` records (``amplitude_max``,
``amplitude_min``, ``amplitude_first_harmonic``, ``period``, ``frequency``,
``energy``, ``stable``, ``annulus``, ...).  :func:`energy_prediction` turns the
energy method into a row of :func:`numerics.compare`.

References
----------
S. Coppola and R. H. Rand, "Averaging using elliptic functions: approximation of
limit cycles", Acta Mechanica 81 (1990) 125-142.
M. D'Acunto, "Friction force for self-excited systems", eq. (10).
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np

from kbm import averaged_cycles, derive
from kbm.model.conservative import split_conservative
from kbm.errors import KBMError, ParameterError
from kbm.parameters.bound import BoundModel, bind
from kbm.model.builtins import Oscillator

from numerics.comparison.prediction import Prediction, reconstruct
from numerics.energy import EnergyPrediction, PredictedCycle, predict_cycles
from numerics.energy.predict import _readonly

__all__ = ["predict", "kbm_cycles", "energy_prediction", "METHODS", "KBM_TERM_LIMIT"]

#: the analyses :func:`predict` knows
METHODS = ("energy", "kbm")

#: the annulus label of classical KBM cycles (one family, about the origin)
KBM_FAMILY = "classical KBM (x = a cos psi + ...)"

#: largest :attr:`~numerics.energy.PredictedCycle.term_size` of a classical KBM cycle that is
#: presented without a warning: the expansion in mu assumes the frequency shift, the
#: waveform correction and the ratio of successive orders all small.  Measured at order 2:
#: van der Pol 0.058 at mu = 0.1 (the order-2 period is right to 6e-7) and 0.58 at mu = 1
#: (0.6 %); the SEDF at mu = 0.1, Delta = 0.1: 0.105; at Delta = 3: 0.57 to 35 for the 12
#: predicted cycles, of which the true dynamics has one (``kbm cycle --all``)
KBM_TERM_LIMIT = 0.5


def _term_size(fns, a: float, m: float, pars: list[float], order: int, w0: float) -> float:
    """The largest relative size of the expansion's corrections at the root ``a``."""
    psi = np.linspace(0.0, 2 * np.pi, 129)
    B = [float(fns.B[n](a, *pars)) * m**n for n in range(1, order + 1)]
    U = [float(np.max(np.abs(np.broadcast_to(fns.u[n](a, psi, *pars), psi.shape)))) * m**n
         for n in range(1, order + 1)]
    sizes = [abs(sum(B)) / w0, max(abs(sum(U)), max(U)) / a]
    for n in range(1, order):
        for seq in (B, U):
            if abs(seq[n - 1]) > 1e-14 * max(1.0, abs(seq[n])):
                sizes.append(abs(seq[n]) / abs(seq[n - 1]))
    return float(max(sizes))


def kbm_cycles(bound: BoundModel, order: int, *, n_samples: int = 1024,
               a_max: float = 20.0) -> tuple[PredictedCycle, ...]:
    """Every cycle of the order-``order`` KBM averaged equations, reconstructed.

    ``energy`` is the energy ``v^2/2 + G(x)`` of the conservative part at the maximum
    of the reconstructed ``x`` (NaN when the model cannot be split); ``floquet_multiplier``
    is ``exp(T dA/da)``.
    """
    result = derive(bound.model, order)
    vals = bound.values
    try:
        need = {p: vals[p] for p in result.params}
    except KeyError as exc:
        raise ParameterError(f"predict needs a value for {exc.args[0]}") from None
    cycles = averaged_cycles(result, {"mu": vals["mu"], **need}, order=order, a_max=a_max)
    try:
        G = split_conservative(bound.model, dict(vals)).numpy_functions()[2]
    except KBMError:
        G = None
    fns = result.functions("numpy")
    m, pars = float(vals["mu"]), [float(need[p]) for p in result.params]
    w0 = float(bound.model.omega0.subs(bound.subs()))
    out = []
    for c in cycles:
        def x_of_psi(p, a=c.amplitude):
            return fns.displacement(a, p, m, *pars, order=order)

        _, xs, _ = reconstruct(x_of_psi, c.frequency, n_samples=n_samples)
        harm = np.fft.rfft(xs) / xs.size
        xmax, xmin = float(np.max(xs)), float(np.min(xs))
        energy = float(G(np.array([xmax]))[0]) if G is not None else math.nan
        size = _term_size(fns, float(c.amplitude), m, pars, order, w0)
        out.append(PredictedCycle(xmax, xmin, float(c.amplitude), float(c.period),
                                  float(c.frequency), energy, bool(c.stable), KBM_FAMILY,
                                  int(order), float(c.floquet_multiplier),
                                  _readonly(harm[:16]), term_size=size))
    return tuple(out)


def predict(model: Oscillator | str | BoundModel, params: Mapping[str, object] | None = None,
            *, method: str = "energy", order: int = 1, potential=None) -> EnergyPrediction:
    """The cycles predicted by ``method`` to ``order`` (see the module docstring).

    Parameters
    ----------
    model, params
        A model (or built-in name) and its parameter values with ``mu``, or a bound model.
    method
        ``"energy"`` or ``"kbm"``.
    order
        The order of the approximation (``>= 1``).
    potential
        For ``"energy"``: the potential of the conservative part, if not the
        ``x``-only part of the force (:func:`kbm.model.conservative.split_conservative`).

    Returns
    -------
    numerics.energy.EnergyPrediction
        ``to_json()`` has the key ``cycles``; an empty list comes with a ``reason``.

    Raises
    ------
    kbm.errors.ParameterError
        For an unknown method, a missing value or ``mu``.
    kbm.errors.OrderError
        For an order the analysis cannot give.

    Examples
    --------
    >>> p = predict("sedf", {"mu": 0.1, "Delta": 1.5, "beta": 1, "lam": 1})
    >>> [(round(c.amplitude_max, 3), c.stable, c.annulus) for c in p.cycles]
    [(2.051, True, 'outer')]
    """
    if method not in METHODS:
        raise ParameterError(f"unknown method {method!r}; use one of {', '.join(METHODS)}")
    bound = bind(model, params)
    if bound.mu is None:
        raise ParameterError(f"predict needs a value of mu for model {bound.name!r} (e.g. "
                             "params={'mu': 0.1})")
    if method == "energy":
        return predict_cycles(bound.model, dict(bound.values), order=order, potential=potential)
    if potential is not None:
        raise ParameterError("potential= belongs to the energy method, not to classical KBM")
    cycles = kbm_cycles(bound, int(order))
    reason = "" if cycles else (f"the order-{order} averaged amplitude equation has no root "
                                "a > 0")
    bad = [c for c in cycles if not c.term_size <= KBM_TERM_LIMIT]
    warning = ""
    if bad:
        worst = max(c.term_size for c in bad)
        warning = (f"classical KBM is outside its range for {len(bad)} of {len(cycles)} "
                   f"cycles: the corrections reach {worst:.3g} of the leading terms (frequency "
                   f"shift, waveform, ratio of successive orders; the expansion needs them "
                   f"<< 1, here above {KBM_TERM_LIMIT:g}); those cycles are not to be trusted; "
                   "use the energy method (--method energy) or kbm cycle --all")
    return EnergyPrediction(model=bound.name, params=bound.floats, order=int(order),
                            cycles=cycles, reason=reason, method="classical KBM",
                            warning=warning)


def energy_prediction(order: int = 1, **predict_kwargs):
    """A row of :func:`numerics.compare` from the energy method of the given order.

    Returns
    -------
    callable
        ``f(bound, target_amplitude=a)`` giving the :class:`Prediction` of the predicted
        cycle whose first-harmonic amplitude is closest to ``a`` (``source="energy"``,
        label ``"energy order N"``).
    """
    label = f"energy order {order}"

    def row(bound: BoundModel, target_amplitude: float | None = None) -> Prediction:
        try:
            pred = predict_cycles(bound.model, dict(bound.values), order=order,
                                  **predict_kwargs)
        except KBMError as exc:
            return Prediction(label=label, order=order, success=False, message=str(exc),
                              source="energy")
        if not pred.cycles:
            return Prediction(label=label, order=order, success=False, message=pred.reason,
                              source="energy")
        cyc = (min(pred.cycles, key=lambda c: abs(c.amplitude_first_harmonic
                                                  - target_amplitude))
               if target_amplitude is not None else
               max((c for c in pred.cycles if c.stable), default=pred.cycles[-1],
                   key=lambda c: c.amplitude_max))
        harm = 2 * np.abs(np.asarray(cyc.harmonics))
        harm[0] /= 2
        mult = cyc.floquet_multiplier
        slope = math.log(abs(mult)) / cyc.period if mult else math.nan
        msg = (f"E* = {cyc.energy:.10g} on the {cyc.annulus} annulus "
               f"({'stable' if cyc.stable else 'unstable'}); {len(pred.cycles) - 1} other "
               "predicted cycle(s)")
        if cyc.period_sensitivity > 1:
            msg += (f"; period sensitivity {cyc.period_sensitivity:.2g} > 1: the cycle's "
                    "energy swing reaches the separatrix, orders beyond 1 are not reliable")
        return Prediction(label=label, order=order, success=True, message=msg,
                          amplitude=cyc.amplitude_first_harmonic,
                          amplitude_max=cyc.amplitude_max, frequency=cyc.frequency,
                          period=cyc.period, harmonics=harm, dA_da=slope, stable=cyc.stable,
                          floquet_multiplier=mult, source="energy")

    row.__name__ = f"energy_order_{order}"
    return row
