"""The averaged counterparts of the codim-1 curves of an autonomous one-degree-of-freedom
model, on the same axes ``(a, b)``.

- **Energy balance** (first-order strongly nonlinear averaging, :mod:`numerics.energy.balance`):
  on the conservative orbit of energy ``E`` of ``x'' + g(x) = 0`` the cycle condition is
  ``Gamma(E; a, b) = oint h x' dt = 0``.  Where ``g`` does not depend on ``b`` and ``h`` is
  affine in ``b`` (the SEDF's ``beta``, a gain), each annulus gives ``b(E) =`` the root of
  ``Gamma``; its interior extrema in ``E`` are the **folds of cycles**, its value at the
  annulus's top, the separatrix energy, is the **Melnikov estimate of the homoclinic loop**
  (``Gamma`` at the saddle's energy is the Melnikov integral, Guckenheimer & Holmes sec.
  4.5), and at a well's bottom the **Hopf point** of its center.  Computed on a grid of ``a``
  and chained into curves per annulus.
- **KBM** (classical averaging at orders 1..3, :func:`numerics.comparison.branches.kbm_branch`)
  when the second axis is ``mu``: the folds of the order-``n`` amplitude equation in ``a``
  at each ``mu`` of a grid (for ``F = (-nu + x^2 - x^4) x'``: ``nu = 1/8`` at orders 1-2,
  the ``O(mu^2)`` shift at order 3).
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np
from scipy.optimize import minimize_scalar

from numerics.bifurcation.result import Curve
from numerics.bifurcation.run import runs

__all__ = ["energy_balance_curves", "kbm_fold_curves", "ENERGY_ORDER"]

#: the order of the energy balance (first-order averaging)
ENERGY_ORDER = 1


def _split(model, params, a_name, b_name, a, b):
    from kbm.model.conservative import split_conservative

    return split_conservative(model, {**params, a_name: a, b_name: b})


def _well_key(annulus, centers) -> tuple:
    """The annulus's wells as ranks from the center nearest 0 (stable as new wells appear
    outside)."""
    c0 = int(np.argmin(np.abs(centers)))
    return tuple(int(np.argmin(np.abs(centers - w))) - c0 for w in annulus.wells)


def energy_balance_curves(model, params: Mapping, axes, ranges, *, n: int = 41,
                          samples: int = 120, progress=None, seeds: list | None = None
                          ) -> tuple[list[Curve], str]:
    """``(curves, note)``: the averaged fold, homoclinic and Hopf curves of the energy
    balance (module docstring), clipped to ``ranges``; ``note`` says why there are none
    where they cannot be made.  ``seeds``, a list, receives for each grid value of ``a``
    and each annulus a predicted cycle ``(a, b, x_max, period, (x_lo, x_hi))`` with ``b``
    in its range, the range ``x_lo < x_max < x_hi`` of the annulus's right turning points
    (starts of the true families of cycles)."""
    from numerics.energy.portrait import phase_portrait

    a_name, b_name = axes
    (a0, a1), (b0, b1) = ranges[a_name], ranges[b_name]
    if b_name == "mu" or a_name == "mu":
        return [], "the energy balance is first order in mu: no curve in a plane with mu"
    rows: dict = {}
    note = ""
    for a in np.linspace(a0, a1, n):
        if progress is not None:
            progress()
        try:
            s0 = _split(model, params, a_name, b_name, a, b0)
            s1 = _split(model, params, a_name, b_name, a, b1)
        except Exception as exc:  # noqa: BLE001 - no split here: no averaged curve at a
            note = note or f"no conservative split at {a_name} = {a:g}: {exc}"
            continue
        if (s0.g - s1.g).simplify() != 0:
            return [], f"the conservative force depends on {b_name}: no energy-balance curve"
        try:
            portrait = phase_portrait(s0)
        except Exception:  # noqa: BLE001
            continue
        p1 = phase_portrait(s1)
        centers = np.array([e.x for e in portrait.equilibria if e.kind == "center"])
        for ann, ann1 in zip(portrait.annuli, p1.annuli):
            key = _well_key(ann, centers)
            found = _annulus_points(ann, ann1, b0, b1, samples)
            if seeds is not None:
                seed = _seed(ann, ann1, a, b0, b1)
                if seed is not None:
                    seeds.append(seed)
            for kind, pts in found.items():
                rows.setdefault((kind, key), []).append((float(a), pts, ann))
    curves, seen = [], set()
    for (kind, key), row in sorted(rows.items(), key=lambda kv: (kv[0][0], kv[0][1])):
        for seg in _clip(_chain(row), b0, b1):
            sig = (kind, tuple((round(a, 9), round(b, 9)) for a, b, _ in seg))
            if len(seg) < 2 or sig in seen:  # the mirror image of a symmetric annulus
                continue
            seen.add(sig)
            detail = {"annulus": [int(k) for k in key], "source": "energy balance"}
            if kind.startswith("homoclinic"):
                detail["estimate"] = ("Melnikov integral on the annulus's " +
                                      ("inner" if kind.endswith("inner") else "outer") +
                                      " separatrix")
                kind = "homoclinic"
            if kind == "fold":
                detail["energies"] = [e for _, _, e in seg]
            curves.append(Curve(kind, [(a, b) for a, b, _ in seg], "averaged", ENERGY_ORDER,
                                detail))
    return curves, "" if curves else note


def _clip(segs, b0, b1):
    """The parts of the segments inside ``b0 <= b <= b1``."""
    return [r for seg in segs for r in runs(seg, lambda p: b0 <= p[1] <= b1)]


def _seed(ann, ann1, a, b0, b1):
    """A predicted cycle of the annulus with ``b`` in range (module docstring)."""
    lo, hi = ann.energy_min, ann.energy_max
    lo_out, lo_in, hi_in, hi_out = ann.bounds
    if not math.isfinite(hi):
        hi = lo + 4.0 * (1.0 + abs(lo))
    for frac in (0.5, 0.25, 0.75, 0.1, 0.9):
        E = lo + frac * (hi - lo)
        try:
            g0, g1 = float(_gamma(ann, E)[0]), float(_gamma(ann1, E)[0])
            b = b0 - g0 * (b1 - b0) / (g1 - g0)
            if not b0 <= b <= b1:
                continue
            x_max = float(ann.turning_points(np.array([E]))[1][0])
            T = float(ann.period(np.array([E]))[0])
        except Exception:  # noqa: BLE001 - no prediction here
            continue
        return (float(a), float(b), x_max, T, (float(hi_in), float(hi_out)))
    return None


def _gamma(ann, E):
    h = ann._fun[3]
    vals, err, _, _ = ann.orbit_integrals(np.atleast_1d(E), [
        lambda x, v, sq: (h(x, v) - h(x, -v)) * v / sq], tol=1e-11)
    return vals[0]


def _annulus_points(ann, ann1, b0, b1, samples) -> dict:
    """``{kind: [(b, E), ...]}`` on one annulus: folds (interior extrema of ``b(E)``),
    homoclinic (``b`` at the top) and Hopf (at a well's bottom)."""
    lo, hi = ann.energy_min, ann.energy_max
    if not math.isfinite(hi):
        hi = lo + 50.0 * (1.0 + abs(lo))
    u = (np.arange(samples) + 0.5) / samples
    E = lo + (hi - lo) * (1 - np.cos(np.pi * u)) / 2

    def bE(e):
        g0, g1 = _gamma(ann, e), _gamma(ann1, e)
        with np.errstate(divide="ignore", invalid="ignore"):
            return b0 - g0 * (b1 - b0) / (g1 - g0)

    try:
        b = bE(E)
    except Exception:  # noqa: BLE001 - the quadrature failed: nothing from this annulus
        return {}
    out: dict = {}
    for k in range(1, samples - 1):
        if not all(np.isfinite(b[k - 1:k + 2])):
            continue
        if (b[k] - b[k - 1]) * (b[k + 1] - b[k]) < 0:
            sign = 1.0 if b[k] < b[k - 1] else -1.0
            r = minimize_scalar(lambda e: sign * float(bE(e)[0]), bounds=(E[k - 1], E[k + 1]),
                                method="bounded", options={"xatol": 1e-12 * (1 + abs(E[k]))})
            out.setdefault("fold", []).append((float(bE(r.x)[0]), float(r.x)))
    if ann.bounded:
        top = ann.energy_max - 1e-10 * (1 + abs(ann.energy_max))
        try:
            out["homoclinic"] = [(float(bE(top)[0]), float(ann.energy_max))]
        except Exception:  # noqa: BLE001
            pass
    if len(ann.wells) > 1:  # a band's inner boundary: the loops seen from outside
        bottom = ann.energy_min + 1e-10 * (1 + abs(ann.energy_min))
        try:
            out["homoclinic-inner"] = [(float(bE(bottom)[0]), float(ann.energy_min))]
        except Exception:  # noqa: BLE001
            pass
    if len(ann.wells) == 1:
        bottom = ann.energy_min + 1e-7 * (hi - lo)
        try:
            out["hopf"] = [(float(bE(bottom)[0]), float(ann.energy_min))]
        except Exception:  # noqa: BLE001
            pass
    return out


def _chain(row):
    """Segments ``[(a, b, E), ...]``: the i-th point (by ``E``) of consecutive grid values
    joined while the count stays."""
    segs, open_ = [], []
    prev_a = None
    for a, pts, _ in row:
        pts = sorted(pts, key=lambda p: p[1])
        pts = [p for p in pts if math.isfinite(p[0])]
        if len(pts) != len(open_) or prev_a is None:
            segs += open_
            open_ = [[(a, b, e)] for b, e in pts]
        else:
            for seg, (b, e) in zip(open_, pts):
                seg.append((a, b, e))
        prev_a = a
    return segs + open_


def kbm_fold_curves(model, params: Mapping, axes, ranges, *, orders=(1, 2, 3), n: int = 11,
                    progress=None) -> list[Curve]:
    """The folds of the KBM amplitude equation at ``orders`` in ``a`` at ``n`` values of
    ``mu`` (the second axis), chained by their order in ``a``."""
    from numerics.comparison.branches import kbm_branch

    a_name, b_name = axes
    (a0, a1), (m0, m1) = ranges[a_name], ranges[b_name]
    curves = []
    for order in orders:
        rows = []
        for m in np.linspace(m0, m1, n):
            if progress is not None:
                progress()
            if m <= 0:
                continue
            try:
                c = kbm_branch(model, {**params, b_name: float(m)}, a_name, (a0, a1),
                               order=order, n=81)
            except Exception:  # noqa: BLE001 - no averaged equation here
                continue
            rows.append((float(m), sorted((f.parameter, f.amplitude) for f in c.folds)))
        width = max((len(r[1]) for r in rows), default=0)
        for i in range(width):
            pts = [(f[i][0], m) for m, f in rows if len(f) > i]
            amp = [f[i][1] for m, f in rows if len(f) > i]
            if len(pts) >= 2:
                curves.append(Curve("fold", pts, "averaged", order,
                                     {"source": f"KBM order {order}",
                                      "amplitude": float(np.median(amp))}))
    return curves
