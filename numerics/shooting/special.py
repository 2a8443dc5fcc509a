"""Period doublings and Neimark-Sacker points on a branch of periodic responses.

As AUTO does (Doedel et al., AUTO-07p manual, sec. 10; Kuznetsov, *Elements of Applied
Bifurcation Theory*, sec. 10.2), the points are detected by test functions of the Floquet
multipliers ``lambda_1, lambda_2`` between consecutive responses of the continuation and
located by bisection on the segment between them (each trial corrected by shooting at its
detuning; the one locator, :func:`numerics.shooting.locate.locate_zero`):

- **period doubling**: ``tau_PD = (1 + lambda_1)(1 + lambda_2) = det(Phi + I)`` changes
  sign (a real multiplier passes through -1: a response of twice the period is born);
- **Neimark-Sacker**: with a complex pair on both sides, ``tau_NS = lambda_1 lambda_2 - 1 =
  det Phi - 1`` changes sign (the pair crosses the unit circle: a torus is born).  For a
  damping that does not depend on the state, ``det Phi = exp(int div f) < 1`` everywhere
  (Liouville), so such points need a self-excited or state-dependent damping.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from kbm.output.strict_json import complex_pairs, json_fields
from numerics.shooting.forced_orbit import ForcedOrbit, periodic_response
from numerics.flow.forced_system import ForcedSystem
from numerics.shooting.locate import locate_zero

__all__ = ["SpecialOrbit", "detect_special", "tau_pd", "tau_ns"]


@dataclass(frozen=True)
class SpecialOrbit:
    """A located special point: ``kind`` is ``"period-doubling"`` or ``"neimark-sacker"``,
    ``orbit`` the response there, ``bracket`` the final bisection bracket in the detuning."""

    kind: str
    orbit: ForcedOrbit
    bracket: tuple[float, float]

    def to_json(self) -> dict:
        return {"kind": self.kind, **json_fields(self.orbit, "sigma", "amplitude", "amplitude_max"),
                "multipliers": complex_pairs(self.orbit.multipliers),
                "sigma_bracket": list(self.bracket)}


def tau_pd(orbit: ForcedOrbit) -> float:
    """``(1 + lambda_1)(1 + lambda_2)``."""
    l1, l2 = orbit.multipliers
    return float(((1 + l1) * (1 + l2)).real)


def tau_ns(orbit: ForcedOrbit) -> float | None:
    """``lambda_1 lambda_2 - 1`` for a complex pair, else ``None``."""
    l1, l2 = orbit.multipliers
    if abs(l1.imag) < 1e-12:
        return None
    return float((l1 * l2).real - 1)


def _locate(system: ForcedSystem, a: ForcedOrbit, b: ForcedOrbit, test, tol: float
            ) -> tuple[ForcedOrbit, tuple[float, float]] | None:
    """The sign change of ``test`` on the segment ``a -> b`` (detuning and start state
    interpolated, each trial corrected at its detuning) by the one locator
    (:func:`numerics.shooting.locate.locate_zero`, bisection)."""
    ta, tb = test(a), test(b)
    if ta is None or tb is None or ta * tb > 0:
        return None
    span = b.sigma - a.sigma
    ya, yb = np.array(a.y0), np.array(b.y0)
    found = locate_zero(lambda w: periodic_response(system, a.sigma + w * span,
                                                    ya + w * (yb - ya)),
                        test, 0.0, 1.0, ta, tb, tol=tol / max(abs(span), 1e-300))
    if found.failure is not None:
        return None
    s_lo, s_hi = a.sigma + found.lo * span, a.sigma + found.hi * span
    return found.point, (min(s_lo, s_hi), max(s_lo, s_hi))


def detect_special(system: ForcedSystem, branch, tol: float = 1e-10) -> list[SpecialOrbit]:
    """Every period doubling and Neimark-Sacker point between consecutive responses of
    ``branch`` (a sequence of :class:`ForcedOrbit` along the continuation), located."""
    out: list[SpecialOrbit] = []

    def add(kind, found):
        if found is None:
            return
        o = found[0]
        for old in out:  # a branch traced both ways meets a point twice
            if old.kind == kind and abs(old.orbit.sigma - o.sigma) < 1e-7 and \
                    abs(old.orbit.amplitude - o.amplitude) < 1e-6:
                return
        out.append(SpecialOrbit(kind, *found))

    for a, b in zip(branch, branch[1:]):
        add("period-doubling", _locate(system, a, b, tau_pd, tol))
        na, nb = tau_ns(a), tau_ns(b)
        if na is not None and nb is not None and na * nb <= 0:
            add("neimark-sacker", _locate(system, a, b, tau_ns, tol))
    return sorted(out, key=lambda sp: (sp.orbit.sigma, sp.kind))
