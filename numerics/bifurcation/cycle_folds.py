"""Folds of cycles of an autonomous one-degree-of-freedom model in two parameters (the
part of :func:`numerics.bifurcation.oned.autonomous_diagram` that follows cycles).

- :func:`families`: the true families of cycles ``z = (x_max, T, b)`` at fixed ``a`` (on the
  diagram's family lines), started from the energy balance's cycles and from small cycles
  beside each Bautin point (:func:`hopf_seeds`); the zeros of ``int div f dt`` along them
  (the non-trivial multiplier 1) are the starts of the fold curves;
- :func:`fold_curves`: each fold curve continued in ``(x_max, T, a, b)``
  (:meth:`numerics.bifurcation.autonomous.OneDof.cycle_fold`); a curve whose period
  exceeds ``t_max`` ends on a homoclinic curve (codim-2 ``fold-homoclinic``); a curve that
  stops (its system singular) beside a Bautin point is continued into it by the
  amplitude-scaled system (:mod:`numerics.bifurcation.hopf_folds`) and ends on it.
"""

from __future__ import annotations

import math

import numpy as np

from numerics.bifurcation.curve import continue_curve
from numerics.bifurcation.path import CurvePath
from numerics.bifurcation.result import Curve
from numerics.errors import NumericsError

__all__ = ["families", "hopf_seeds", "fold_curves"]


def families(run, seeds) -> list:
    """Fold seeds ``(x0, T, a, b)``: zeros of ``int div f`` along the true families of
    cycles at fixed ``a`` (``z = (x0, T, b)``) started from the energy balance's cycles."""
    kit = run.kit
    out = []
    lines = np.linspace(run.box[0][0], run.box[0][1], run.s.family_lines + 2)
    seeds = [s for s in seeds if np.any(np.isclose(s[0], lines, rtol=0,
                                                   atol=1e-9 * (1 + abs(s[0]))))]
    seeds += hopf_seeds(run)
    for a, b, x0, T, (xlo, xhi) in seeds:
        xlo = xlo + 0.02 * (min(xhi, run.s.L) - xlo)  # not the vanishing cycles at a Hopf point

        def G(z, a=a):
            y = kit.end_state(z[0], z[1], a, z[2])
            return np.array([y[0] - z[0], y[1]])

        def div(z, a=a):
            return kit.end_state(z[0], z[1], a, z[2])[6]

        def stop(pt, path, T0=T):
            return "period" if pt.z[1] > min(run.s.t_max, 40 * T0) else None

        hi = xhi if math.isfinite(xhi) else run.s.L
        key = f"family|{a:.6f},{x0:.6f}"
        bounds = {0: (xlo + 1e-6 * (1 + abs(xlo)), hi - 1e-6 * (1 + abs(hi))),
                  2: run.box[1]}
        try:
            pts = []
            for sign in (1, -1):
                rec = run.store.get(f"{key}|{sign}")
                if rec is not None and rec.get("done"):
                    path = CurvePath.from_records(rec["path"])
                else:
                    path = continue_curve(G, [x0, T, b], tangent=[sign, 0, 0], ds=0.01,
                                          ds_max=0.05, bounds=bounds, max_points=300,
                                          tol=1e-10, tests={"fold": div}, stop=stop,
                                          scale=[abs(hi - xlo), T, run.scale[1]])
                    if path.end == "interrupted":
                        run.interrupted = True
                        return out
                    run.store.put(f"{key}|{sign}", {"path": path.to_records(), "done": True})
                pts.append(path)
                if run.progress is not None:
                    run.progress("family", (a, b))
        except Exception:  # noqa: BLE001 - no true cycle near the prediction: no family
            continue
        for path in pts:
            for ev in path.events:
                out.append((ev.z[0], ev.z[1], a, ev.z[2]))
    return out


def hopf_seeds(run) -> list:
    """Small cycles beside each Bautin point (where a fold of cycles leaves the Hopf
    curve): at ``a`` two hundredths of the range either side, the cycle of amplitude 0.05
    about the equilibrium, corrected in ``(T, b)``; ``(a, b, x0, T, (x_lo, x_hi))``."""
    kit = run.kit
    out = []
    for pt in run.codim2:
        if pt.kind != "bautin":
            continue
        for da in (-0.02, 0.02):
            a = pt.point[0] + da * run.scale[0]
            for hz in run.hopf:
                order = np.argsort(hz[:, 1])
                if not hz[order[0], 1] <= a <= hz[order[-1], 1]:
                    continue
                xe = float(np.interp(a, hz[order, 1], hz[order, 0]))
                bh = float(np.interp(a, hz[order, 1], hz[order, 2]))
                if abs(xe - pt.detail.get("x", xe)) > 0.2:
                    continue
                w = math.sqrt(max(1e-12, -kit.d(1, 0, xe, 0.0, a, bh)))
                r = 0.05 * max(1.0, abs(xe))
                x0 = xe + r

                def G(z, a=a, x0=x0):
                    y = kit.end_state(x0, z[0], a, z[1])
                    return np.array([y[0] - x0, y[1]])
                try:
                    from scipy.optimize import fsolve

                    sol, info, ok, _ = fsolve(G, [2 * math.pi / w, bh], full_output=True,
                                              xtol=1e-12)
                except Exception:  # noqa: BLE001
                    continue
                if ok == 1 and np.max(np.abs(G(sol))) < 1e-9:
                    eq = sorted(x for x, _ in kit.equilibria(a, float(sol[1]), run.s.L))
                    right = [x for x in eq if x > xe + 1e-9]
                    out.append((a, float(sol[1]), x0, float(sol[0]),
                                (xe, right[0] if right else run.s.L)))
    return out


def fold_curves(run, seeds) -> None:
    kit = run.kit
    G = kit.cycle_fold()
    for z0 in seeds:
        if run.covered("fold", z0[2:]):
            continue
        key = f"fold|{z0[0]:.6f},{z0[1]:.6f},{z0[2]:.6f},{z0[3]:.6f}"

        def stop(pt, path):
            return "period" if pt.z[1] > run.s.t_max else None

        found = run.attempt("fold", z0, key, G, [0, 0, 1.0, 1.0],
                            scale=np.concatenate([[1.0, max(1.0, z0[1])], run.scale]),
                            stop=stop, tol=1e-10, fd_step=1e-7)
        if found is None:
            if run.interrupted:
                return
            continue
        pts, _, ends = found
        ab = [tuple(float(v) for v in p.z[2:]) for p in pts]
        detail = {"x_max": [float(pts[0].z[0]), float(pts[-1].z[0])],
                  "period": [float(pts[0].z[1]), float(pts[-1].z[1])],
                  "residual_max": max(p.residual for p in pts)}
        for side, (end, p) in enumerate(((ends[0], pts[0]), (ends[1], pts[-1]))):
            tail = _into_bautin(run, key, side, p.z) if end == "step" else None
            if tail is not None:
                ab = (list(reversed(tail["ab"])) + ab) if side == 0 else ab + tail["ab"]
                detail.setdefault("bautin_ends", []).append(tail["detail"])
        run.curves.append(Curve("fold", ab, "true", None, detail))
        for end, p in ((ends[0], pts[0]), (ends[1], pts[-1])):
            if end == "stopped":
                ab = np.asarray(p.z[2:], dtype=float)
                near = [q for q in run.codim2 if q.kind == "neutral-saddle-loop" and np.linalg.norm(
                    (np.asarray(q.point) - ab) / run.scale) < 0.05]
                if near:  # the end located on the homoclinic curve (saddle quantity zero)
                    q = min(near, key=lambda q: np.linalg.norm((np.asarray(q.point) - ab)
                                                                / run.scale))
                    run.add_codim2("fold-homoclinic", q.point, {
                        "on": "fold", "period": float(p.z[1]), "last_fold_point":
                        [float(v) for v in ab], "note": "the neutral saddle loop located on "
                        "the homoclinic curve (the saddle quantity's zero), where the fold "
                        "curve ends; last_fold_point: its last converged point"})
                    continue
                run.add_codim2("fold-homoclinic", tuple(p.z[2:]), {
                    "on": "fold", "period": float(p.z[1]),
                    "note": "the last converged point of the fold curve, period above t_max"})
        if run.interrupted:  # the points so far are kept above
            return


def _into_bautin(run, key, side, z):
    """The fold curve's end at ``z = (x0, T, a, b)`` continued into the Bautin point near it
    (:func:`numerics.bifurcation.hopf_folds.into_bautin`): ``{"ab": [...], "detail": {...}}``
    (the points from ``z`` outwards, the Bautin point last), or ``None`` when no Bautin
    point lies within 5 % of the box or the scaled system fails (the failure kept)."""
    from numerics.bifurcation.hopf_folds import into_bautin

    ab = np.asarray(z[2:], dtype=float)
    near = [q for q in run.codim2 if q.kind == "bautin" and "x" in q.detail
            and np.linalg.norm((np.asarray(q.point) - ab) / run.scale) < 0.05]
    if not near:
        return None
    q = min(near, key=lambda q: np.linalg.norm((np.asarray(q.point) - ab) / run.scale))
    xb = float(q.detail["x"])
    if run.kit.odd and abs(z[0] + xb) < abs(z[0] - xb):  # the mirror well's Bautin point
        xb = -xb
    rec = run.store.get(f"{key}|bautin|{side}")
    if rec is None:
        try:
            out = into_bautin(run.kit, z, (xb, *q.point), progress=lambda zz: (
                run.progress is not None and run.progress("fold", zz[3:])))
        except (NumericsError, np.linalg.LinAlgError) as exc:
            run.failures.append(f"fold into the Bautin point {q.point}: {exc}")
            return None
        end = out["end"]
        last = out["points"][-1]
        rec = {"ab": [[float(p[3]), float(p[4])] for p in out["points"]]
               + [[float(end[1]), float(end[2])]],
               "detail": {"end": "bautin", "bautin": [float(end[1]), float(end[2])],
                          "scaled_points": len(out["points"]),
                          "eps_min": float(abs(last[1])),
                          "last_scaled_point": [float(last[3]), float(last[4])],
                          "scaled_residual_max": float(max(out["residuals"])),
                          "note": "amplitude-scaled fold system down to eps_min, then the "
                          "Bautin point (its eps = 0 member: Hopf conditions and l1 = 0)"}}
        run.store.put(f"{key}|bautin|{side}", rec)
    return {"ab": [tuple(p) for p in rec["ab"]], "detail": rec["detail"]}
