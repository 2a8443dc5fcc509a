"""Every limit cycle the averaging predicts, each confirmed by shooting (:func:`limit_cycles`).

Each predicted cycle (:func:`numerics.energy.predict_cycles`, stable and unstable, on every
period annulus) starts :func:`numerics.cycles.shooting.limit_cycle`; a prediction Newton
misses near a separatrix is sought by homotopy in the size of the dissipative part
(continued by :func:`numerics.cycles.continuation.continue_cycles`); for a model mapped to
itself by ``x -> -x`` the list is closed under the symmetry.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING

import numpy as np

from kbm.errors import KBMError

from numerics.cycles.result import LimitCycle
from numerics.cycles.seeds import seeds as _seeds
from numerics.cycles.shooting import limit_cycle
from numerics.errors import ConvergenceError, IntegrationError, NoCycleError

if TYPE_CHECKING:  # the symbolic model is bound on use (a model card: issue 39)
    from kbm.parameters.bound import BoundModel
    from kbm.model.builtins import Oscillator

__all__ = ["limit_cycles", "CycleList"]


def limit_cycles(model: Oscillator | str | BoundModel, params: Mapping[str, object] | None = None,
                 *, order: int = 1, potential=None, **cycle_kwargs) -> list[LimitCycle]:
    """Every limit cycle the energy-balance averaging predicts, each confirmed by shooting.

    Each predicted cycle (stable and unstable, on every period annulus;
    :func:`numerics.energy.predict_cycles`) starts :func:`limit_cycle`; cycles that
    shoot to the same orbit are reported once.  A prediction that does not lead to a
    cycle is left out (its failure is in the ``failures`` attribute of the list).

    Parameters
    ----------
    order, potential
        Passed to :func:`numerics.energy.predict_cycles`.
    cycle_kwargs
        Passed to :func:`limit_cycle` (``rtol``, ``method``, ...).

    Returns
    -------
    CycleList
        A list of :class:`LimitCycle` sorted by ``amplitude_max``, with the attributes
        ``predictions`` (the :class:`numerics.energy.EnergyPrediction`) and
        ``failures`` (``(predicted cycle, error message)`` pairs).  For a model mapped
        to itself by ``x -> -x`` the list is closed under the symmetry: the mirror of
        every side-well cycle is shot from the mirrored orbit (``predicted`` is ``None``
        for it), and a prediction that failed but whose mirror image was found is no
        longer a failure.

    Examples
    --------
    >>> cs = limit_cycles("vdp", {"mu": 0.5})
    >>> [round(c.amplitude_max, 6) for c in cs], cs[0].stable
    ([2.002488], True)
    """
    bound, shoot = _bound_and_shooting(model, params, cycle_kwargs)
    seeds = _seeds(bound, order, potential)
    found = CycleList(predictions=seeds.prediction)
    for p in seeds.cycles:
        try:
            c = shoot((p.amplitude_max, p.period))
        except (ConvergenceError, IntegrationError, NoCycleError) as exc:
            c = _from_smaller_mu(_full(bound), p, cycle_kwargs)
            if c is None:
                found._failures.append((p, str(exc)))
                continue
        if not any(_same_orbit(c, d) for d in found):
            found.append(c)
            found._predicted.append(p)
    if seeds.odd:
        _add_mirrors(shoot, found)
    order_ = sorted(range(len(found)), key=lambda i: found[i].amplitude_max)
    return CycleList([found[i] for i in order_], predictions=seeds.prediction,
                     predicted=[found._predicted[i] for i in order_], failures=found._failures)


def _bound_and_shooting(model, params, cycle_kwargs):
    """``(bound, shoot)``: the bound model (a model card's where one is stored and the
    cards are in use, :mod:`numerics.flow.card`: no sympy) and ``shoot(guess)``, the
    :func:`limit_cycle` from ``(x_max, period)`` at these values (by the name and the values
    as given where the cards are in use, so that the first run stores the card)."""
    from numerics.flow.card import card_key, card_model

    carded = card_model(model, params)
    if carded is None and card_key(model, params) is not None:
        from numerics.cycles.shooting import _bound_and_compiled

        _bound_and_compiled(model, params, None)  # bound, compiled and the card stored
        carded = card_model(model, params)  # the first run as the later ones
    if carded is None:
        from kbm.parameters.bound import bind

        bound = bind(model, params)
    else:
        bound = carded[0]
    if carded is not None or card_key(model, params) is not None:
        def shoot(guess):
            return limit_cycle(model, params, guess=guess, **cycle_kwargs)
    else:
        def shoot(guess):
            return limit_cycle(bound, guess=guess, **cycle_kwargs)
    return bound, shoot


def _full(bound):
    """The :class:`kbm.parameters.bound.BoundModel` of a model card's bound model (its exact
    values)."""
    return bound.full() if hasattr(bound, "full") else bound


class CycleList(list):
    """A list of :class:`LimitCycle` with the predictions that led to them.

    Attributes
    ----------
    predictions
        The :class:`numerics.energy.EnergyPrediction` the search started from.
    predicted
        For each cycle, the :class:`numerics.energy.PredictedCycle` that led to it.
    failures
        ``(predicted cycle, error message)`` for each prediction that led to no cycle.
    """

    def __init__(self, items=(), *, predictions=None, predicted=None, failures=None):
        super().__init__(items)
        self._predictions = predictions
        self._predicted: list = list(predicted or [])
        self._failures: list = list(failures or [])

    @property
    def predictions(self):
        """The energy-balance prediction (computed here on first use where the cycles were
        started from a stored record of it, :class:`numerics.cycles.seeds.Seeds`)."""
        p = self._predictions
        return p() if callable(p) else p

    @predictions.setter
    def predictions(self, value) -> None:
        self._predictions = value

    @property
    def predicted(self) -> list:
        """For each cycle, its :class:`numerics.energy.PredictedCycle` (``None``: a mirror)."""
        return [p.resolve() if hasattr(p, "resolve") else p for p in self._predicted]

    @predicted.setter
    def predicted(self, value) -> None:
        self._predicted = list(value)

    @property
    def failures(self) -> list:
        """``(predicted cycle, error message)`` for each prediction that led to no cycle."""
        return [(p.resolve() if hasattr(p, "resolve") else p, e) for p, e in self._failures]

    @failures.setter
    def failures(self, value) -> None:
        self._failures = list(value)


def _from_smaller_mu(bound: BoundModel, p, cycle_kwargs) -> LimitCycle | None:
    """A predicted cycle that Newton missed (near a separatrix its basin is narrower than
    the prediction's error), sought by homotopy in the size of the dissipative part.

    The model ``x'' = -g(x) + mu h(x, x')`` is embedded in ``-g + s mu h``: the conservative
    part, hence the phase portrait and the separatrices, stays; the first-order energy
    balance root does not move with ``s``, and the true cycle tends to it as ``s -> 0``.
    At ``s = 1/2, 1/4, 1/8`` Newton starts from the prediction; from the first ``s`` where
    it converges, the cycle is continued in ``s`` to 1 (pseudo-arclength,
    :func:`numerics.cycles.continuation.continue_cycles`) and polished on the model.  The
    result is kept only if it is the predicted cycle (same side, ``x_max`` within 5 %,
    period within 25 %); else ``None``, and the caller reports the first failure.
    """
    import sympy as sp

    from kbm.model.builtins import Oscillator
    from kbm.symbols import xdot as V
    from numerics.cycles.continuation import continue_cycles

    model = bound.model
    S = sp.Symbol("homotopy_s")
    Fc = model.F.subs(V, 0)
    emb = Oscillator(f"{model.name} (homotopy)", sp.expand(Fc + S * (model.F - Fc)),
                     model.omega0, model.description, physical=dict(model.physical),
                     defaults=dict(model.defaults), drive=model.drive,
                     gain_factor=model.gain_factor, stage_relative=model.stage_relative)
    vals = {k: v for k, v in dict(bound.values).items()}
    for s0 in (0.5, 0.25, 0.125):
        try:
            c0 = limit_cycle(emb, {**vals, S.name: s0}, guess=(p.amplitude_max, p.period),
                             **cycle_kwargs)
            br = continue_cycles(emb, {**vals, S.name: s0}, S.name, (s0, 1.0), start=c0,
                                 directions=(1,))
        except (ConvergenceError, IntegrationError, NoCycleError, KBMError):
            continue
        end = br.points[-1] if br.points else None
        if end is None or abs(end.parameter - 1.0) > 1e-12:
            continue
        try:
            c = limit_cycle(bound, guess=(end.amplitude_max, end.period), **cycle_kwargs)
        except (ConvergenceError, IntegrationError, NoCycleError):
            continue
        # the same cycle as predicted, not another one the homotopy slid onto
        if (np.sign(c.amplitude_max) == np.sign(p.amplitude_max)
                and abs(c.amplitude_max - p.amplitude_max) <= 0.05 * abs(p.amplitude_max)
                and abs(c.period - p.period) <= 0.25 * p.period):
            return c
    return None


def _add_mirrors(shoot, found: "CycleList") -> None:
    """For each cycle whose mirror image ``-x(t)`` is a different orbit (a side-well cycle),
    shoot from the mirrored orbit (its maximum ``-min x`` and its period) unless it is
    listed already; the symmetry makes it a cycle with the same period and multipliers,
    so a failure here is reported, never silent."""
    for c in list(found):
        x_lo = _minimum(c)
        if abs(x_lo + c.amplitude_max) <= 1e-6 * max(1.0, abs(c.amplitude_max)):
            continue  # symmetric orbit: its own mirror
        if any(abs(d.period - c.period) <= 1e-6 * c.period
               and abs(d.amplitude_max + x_lo) <= 1e-6 * max(1.0, abs(x_lo)) for d in found):
            continue
        try:
            m = shoot((-x_lo, c.period))
        except (ConvergenceError, IntegrationError, NoCycleError) as exc:
            found._failures.append((f"mirror of the cycle with x in [{x_lo:.6g}, "
                                   f"{c.amplitude_max:.6g}]", str(exc)))
            continue
        if not any(_same_orbit(m, d) for d in found):
            found.append(m)
            found._predicted.append(None)
        # a prediction of this orbit that failed to shoot is answered by the mirror
        found._failures[:] = [
            (p, e) for p, e in found._failures
            if isinstance(p, str) or not (
                np.sign(p.amplitude_max) == np.sign(m.amplitude_max)
                and abs(p.amplitude_max - m.amplitude_max) <= 0.05 * abs(m.amplitude_max))]


def _minimum(c: LimitCycle) -> float:
    """The orbit's minimum of ``x``: where the sampled ``x'`` crosses 0 upwards, by cubic
    Hermite interpolation of ``x`` with ``x'`` (error ~ ``(T/n)^4``; the sample minimum alone
    is off by ~``(T/n)^2``, too far for Newton near a separatrix: at mu = 0.1, Delta = 1.5,
    beta = 1.3345 the mirrored SEDF side-well cycle was missed from the sample minimum and
    found in one Newton step from this one)."""
    i = int(np.argmin(c.x))
    n = len(c.x)
    for k in (i - 1, i):
        k0, k1 = k % n, (k + 1) % n
        v0, v1 = c.xdot[k0], c.xdot[k1]
        if v0 <= 0 <= v1 and v1 > v0:
            h = c.period / n
            s = v0 / (v0 - v1)
            return float((2 * s**3 - 3 * s**2 + 1) * c.x[k0] + (s**3 - 2 * s**2 + s) * h * v0
                         + (-2 * s**3 + 3 * s**2) * c.x[k1] + (s**3 - s**2) * h * v1)
    return float(c.x[i])


def _same_orbit(a: LimitCycle, b: LimitCycle) -> bool:
    return (abs(a.period - b.period) <= 1e-6 * b.period
            and abs(a.amplitude_max - b.amplitude_max) <= 1e-6 * max(1.0, abs(b.amplitude_max)))
