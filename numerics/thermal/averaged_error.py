"""The expected error of each averaged stationary moment of ``kbm noise`` (issue 36: "each
averaged number states its order and its expected error"), from the best reference the run
has, in this order:

1. ``"fokker-planck"``: the stationary Kramers solution (:mod:`numerics.fokker_planck`),
   which owes nothing to averaging: ``|averaged - FP| + e |FP|`` with ``e`` the solve's
   stated relative error (``fokker_planck.hermite_change``).  A measured error, used
   unless the solve's own error ``e |FP|`` exceeds the estimate of the next source that
   applies (a reference less certain than the error it would measure: the SEDF at rest,
   Delta = 3, D = mu/2, at mu = 0.002 states ``e`` = 1e-4 to 1e-3, and before this
   rule a 258 x 1040 solve stated 0.14 and gave <a^2> = 3.669 against 4.006).
2. ``"next order"``: at first order, where the second order of the stochastic averaging
   applies (:mod:`kbm.noise.stochastic_order2`), the size of the next order's correction,
   ``|A_2 - A_1|`` (the error of an asymptotic series is about its first omitted term; van
   der Pol, D/mu = 0.5: 1.00, 1.02 and 1.16 times the true error of ``<a^2>`` at mu = 0.05,
   0.1 and 0.3, tests/test_averaged_error.py).
3. ``"simulation"``: ``|averaged - simulated| + 2 stderr``, a bound at two standard errors
   of the ensemble (a Monte Carlo statement).
4. ``None`` with the source ``"none"``: no reference (no Fokker-Planck solution, no next
   order, no simulation), said so rather than guessed.

The rule itself, :func:`averaged_error`, is shared with ``kbm spectrum``
(:func:`numerics.noise.validity.averaged_error`, imported here so that this path stays).
"""

from __future__ import annotations

from ..noise.validity import averaged_error

__all__ = ["state_averaged_errors"]


def state_averaged_errors(out: dict, next_order: dict | None = None) -> dict:
    """``out`` (a report of :func:`.stationary.noise_report`) with ``averaged_error`` and
    ``averaged_error_source`` in ``moments.a2`` and ``moments.x2``; ``next_order``: the
    moments at the next order (``{"a2": .., "x2": ..}``), where it was computed."""
    fp = out.get("fokker_planck")
    change = None if fp is None else fp.get("hermite_change")
    for key in ("a2", "x2"):
        m = out["moments"][key]
        err, source = averaged_error(m, change, (next_order or {}).get(key))
        m["averaged_error"], m["averaged_error_source"] = err, source
    return out
