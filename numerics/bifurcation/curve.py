"""Pseudo-arclength continuation of a curve of zeros of ``G: R^(n+1) -> R^n``.

``z`` holds the ``n - 1`` unknowns of a defining system and the two parameters (or any
``n + 1`` numbers whose zero set is a curve).  :func:`continue_curve` follows the curve
point by point (Keller's pseudo-arclength method, e.g. Kuznetsov, *Elements of Applied
Bifurcation Theory*, 3rd ed., section 10.2; Allgower & Georg, *Numerical Continuation
Methods*):

- the tangent ``t`` is the null vector of ``G'(z)`` (the last right singular vector),
  oriented along the previous one;
- the predictor ``z + ds t`` is corrected by Newton's method on the bordered system
  ``G(z) = 0, t . (z - z_pred) = 0``;
- **convergence test**: a point is accepted when ``max|G(z)| <= tol`` *and* the last
  Newton correction satisfies ``max|dz| <= xtol (1 + max|z|)``; every point of a path passed
  it (points are converged, never extrapolated);
- step control: ``ds`` grows by 1.3 after an easy correction (at most 3 Newton steps), up
  to ``ds_max``, and halves after a failed one or a turn of the tangent by more than
  ``max_turn`` radians; the path ends when ``ds`` falls below ``ds_min``;
- bounds: when a point leaves the box, the path ends on the box's edge exactly (the
  arclength condition is replaced by ``z_i = edge``); a seed that corrects to just outside
  the box (a seed on its edge) starts on the edge the same way, and the path that would
  leave the box there at once ends at its first point;
- test functions ``psi(z)`` are evaluated at each point; a sign change between two points
  is located by the Illinois variant of regula falsi on the curve (each trial point
  corrected onto the curve on the hyperplane orthogonal to the chord) until
  ``|psi| <= test_tol`` or the bracket is below ``1e-12`` of the chord; these are the
  codim-2 points of a codim-1 curve;
- ``progress(point, path)`` after each accepted point; ``on_point(point)`` to store it;
  a :class:`KeyboardInterrupt` ends the path with what was found (``end == "interrupted"``);
- resume: :meth:`CurvePath.to_records` / :meth:`CurvePath.from_records` and
  ``continue_curve(..., resume=path)`` continue from the last point and its tangent.

The records (:class:`~numerics.bifurcation.path.PathPoint`, :class:`~numerics.bifurcation.path.TestEvent`,
:class:`~numerics.bifurcation.path.CurvePath`) live in :mod:`numerics.bifurcation.path`, the
corrector (:func:`~numerics.bifurcation.corrector.correct`) in :mod:`numerics.bifurcation.corrector`,
the tangent (:func:`~numerics.shooting.arclength.null_vector`) in :mod:`numerics.shooting.arclength`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence

import numpy as np

from kbm.slowflow.arclength import walk

from numerics.bifurcation.corrector import FAILURES, _jac, correct
from numerics.bifurcation.path import CurvePath, PathPoint, TestEvent
from numerics.errors import ConvergenceError, NumericsError
from numerics.shooting.arclength import null_vector

__all__ = ["continue_curve"]


def _evaluate_tests(tests, pt: PathPoint) -> dict:
    out = {}
    for name, fn in tests.items():
        try:
            out[name] = float(fn(pt.z) if _arity(fn) == 1 else fn(pt.z, pt.tangent))
        except FAILURES:
            out[name] = float("nan")
    return out


def _arity(fn) -> int:
    try:
        import inspect

        params = [p for p in inspect.signature(fn).parameters.values()
                  if p.default is p.empty and p.kind in (p.POSITIONAL_ONLY,
                                                         p.POSITIONAL_OR_KEYWORD)]
        return len(params)
    except (TypeError, ValueError):
        return 1


def _locate(G, jac, name, fn, a: PathPoint, b: PathPoint, fa, fb, kw, test_tol) -> TestEvent:
    """The zero of the test ``fn`` between the path points ``a`` and ``b`` (Illinois)."""
    chord = b.z - a.z
    length = float(np.linalg.norm(chord))
    row = chord / length
    s0, s1, f0, f1 = 0.0, 1.0, fa, fb
    side = 0
    best = None
    for _ in range(60):
        s = s0 - f0 * (s1 - s0) / (f1 - f0) if f1 != f0 else 0.5 * (s0 + s1)
        if not (s0 < s < s1):
            s = 0.5 * (s0 + s1)
        zp = a.z + s * chord
        z, res, _, J = correct(G, zp, row, float(row @ zp), jac=jac, **kw)
        t = null_vector(J, a.tangent)
        f = float(fn(z) if _arity(fn) == 1 else fn(z, t))
        best = (z, f, res)
        if abs(f) <= test_tol or (s1 - s0) <= 1e-12:
            break
        if (f > 0) == (f0 > 0):
            s0, f0 = s, f
            if side == -1:
                f1 *= 0.5
            side = -1
        else:
            s1, f1 = s, f
            if side == 1:
                f0 *= 0.5
            side = 1
    z, f, res = best
    return TestEvent(name, z, f, -1, float(s1 - s0), res)


def continue_curve(G: Callable, z0, *, jac: Callable | None = None, tangent=None,
                   ds: float = 0.01, ds_max: float = 0.1, ds_min: float | None = None,
                   bounds: Mapping[int, tuple[float, float]] | None = None,
                   max_points: int = 500, tol: float = 1e-10, xtol: float = 1e-9,
                   tests: Mapping[str, Callable] | None = None, test_tol: float = 1e-9,
                   stop: Callable | None = None, progress: Callable | None = None,
                   on_point: Callable | None = None, resume: CurvePath | None = None,
                   max_turn: float = 0.35, newton_steps: int = 12, fd_step: float = 1e-7,
                   scale: Sequence[float] | None = None, closed_check: bool = True
                   ) -> CurvePath:
    """Follow the curve ``G(z) = 0`` from ``z0`` (module docstring for the method).

    Parameters
    ----------
    G : callable
        ``z -> G(z)``, ``R^(n+1) -> R^n``.
    z0 : array_like
        A point near the curve (corrected onto it first, on the hyperplane through ``z0``
        normal to ``tangent`` or, without it, to the first null direction).
    jac : callable, optional
        ``z -> G'(z)`` (``n x (n+1)``); central differences with step ``fd_step`` if
        ``None``.
    tangent : array_like, optional
        Picks the direction: the path goes along the null vector with ``t . tangent > 0``.
    ds, ds_max, ds_min : float
        First, largest and smallest step in the (scaled) arclength.
    bounds : mapping ``index -> (lo, hi)``
        The box; the path ends exactly on its edge.
    max_points : int
        Points of the path at most (the start included).
    tol, xtol : float
        The convergence test of :func:`correct`.
    tests : mapping ``name -> psi(z)`` or ``psi(z, t)``
        Test functions whose sign changes are located (:class:`TestEvent`).
    stop : callable ``(point, path) -> str or None``
        Ends the path with ``end = "stopped"`` and the message returned.
    progress, on_point : callable
        ``progress(point, path)`` and ``on_point(point)`` after each accepted point.
    resume : CurvePath
        A stored path: continued from its last point and tangent (``z0`` ignored).
    scale : sequence of float
        The components' scales in the arclength norm (``z / scale``).

    Returns
    -------
    CurvePath
    """
    tests = dict(tests or {})
    if resume is not None and resume.points:
        z0 = resume.points[-1].z
    z0 = np.atleast_1d(np.asarray(z0, dtype=float))
    sc = np.ones(z0.size) if scale is None else np.asarray(scale, dtype=float)
    # internally w = z / scale: unit tangents and steps in the scaled norm
    Gw = (lambda w: G(w * sc))
    jw = None if jac is None else (lambda w: np.atleast_2d(np.asarray(jac(w * sc))) * sc)
    wtests = {k: _scaled_test(fn, sc) for k, fn in tests.items()}
    wbounds = {i: tuple(sorted((lo / sc[i], hi / sc[i]))) for i, (lo, hi)
               in dict(bounds or {}).items()}
    ds_min = ds_min if ds_min is not None else ds * 1e-4
    kw = dict(tol=tol, xtol=xtol, max_steps=newton_steps, h=fd_step)
    path = resume if resume is not None else CurvePath()
    path.end, path.message = "", ""
    wpath = CurvePath([_to_w(p, sc) for p in path.points], [], "", path.ds)

    def emit(wpt):
        pt = _to_z(wpt, sc)
        path.points.append(pt)
        path.ds = wpath.ds
        if on_point is not None:
            on_point(pt)
        if progress is not None:
            progress(pt, path)
        return pt

    try:
        if not wpath.points:
            w = z0 / sc
            J0 = _jac(Gw, jw, w, fd_step)
            t0 = null_vector(J0, None if tangent is None else np.asarray(tangent) / sc)
            w, res, k, J = correct(Gw, w, t0, float(t0 @ w), jac=jw, **kw)
            if _outside(w, wbounds) is not None:  # a seed on the box's edge corrected to
                w, res, k, J = _onto_edge(Gw, jw, w, wbounds, kw, (w, res, k, J))  # outside
            wpt = PathPoint(w, null_vector(J, t0), res, k)
            wpt.tests = _evaluate_tests(wtests, wpt)
            wpath.points.append(wpt)
            wpath.ds = ds
            emit(wpt)
            if _outside(w, wbounds) is not None:
                path.end, path.message = "outside", (
                    f"the seed corrected to z = {_fmt(w * sc)}, outside the box, and no point "
                    "of the curve on the edge it crossed was found")
                return path
        step = ds if not math.isfinite(wpath.ds) else wpath.ds
        if resume is not None and len(wpath.points) > 1:  # the step the run would take next
            step = _next_step(step, wpath.points[-1].steps, ds_max)

        def collapsed(last, exc=None):
            return "step", f"the step fell below {ds_min:g} at z = {last.z * sc}"

        def advance(last, h):  # predictor and corrector; a failure halves the step
            wp = last.z + h * last.tangent
            w, res, k, J = correct(Gw, wp, last.tangent, float(last.tangent @ wp), jac=jw, **kw)
            t = null_vector(J, last.tangent)
            turn = math.acos(max(-1.0, min(1.0, float(t @ last.tangent))))
            if turn > max_turn or float((w - last.z) @ last.tangent) <= 0:
                raise ConvergenceError(f"the tangent turned by {turn:.3f} rad")
            return PathPoint(w, t, res, k)

        def visit(last, wpt, h):
            edge = _outside(wpt.z, wbounds, last.z)
            if edge is not None:
                i, value = edge
                if last.z[i] == value:  # started on this edge
                    return last, h, ("bounds", f"on the edge z[{i}] = {value * sc[i]:g}")
                row = np.zeros_like(wpt.z)
                row[i] = 1.0
                # from the secant's crossing of the edge: Newton with w_i fixed
                w, span = wpt.z, wpt.z[i] - last.z[i]
                start = w if abs(span) < 1e-300 else \
                    last.z + (value - last.z[i]) / span * (w - last.z)
                try:
                    w, res, k, J = correct(Gw, start, row, value, jac=jw, **kw)
                    w[i] = value
                except FAILURES:
                    if h * 0.5 >= ds_min:
                        return last, h * 0.5, ""
                    return last, h, ("step", "the box's edge could not be reached by Newton")
                wpt = PathPoint(w, null_vector(J, last.tangent), res, k)
            wpt.tests = _evaluate_tests(wtests, wpt)
            wpath.points.append(wpt)
            wpath.ds = h
            for ev in _find_events(Gw, jw, wtests, wpath, kw, test_tol):
                ev.z = ev.z * sc
                path.events.append(ev)
            pt = emit(wpt)
            if edge is not None:
                return wpt, h, ("bounds", f"on the edge z[{i}] = {value * sc[i]:g}")
            why = stop(pt, path) if stop is not None else None
            if why:
                return wpt, h, ("stopped", str(why))
            if closed_check and _closed(wpath, h):
                return wpt, h, ("closed", "the curve closed on its first point")
            h = _next_step(h, wpt.steps, ds_max)
            return wpt, h, (collapsed(wpt) if h < ds_min and not full() else "")

        def full():
            return ("max_points", "") if len(wpath.points) >= max_points else None

        # the one pseudo-arclength driver (kbm.slowflow.arclength.walk): the turn of the
        # tangent is tested in radians by advance, the box's edges by visit
        path.end, path.message = full() or (
            collapsed(wpath.points[-1]) if step < ds_min else
            walk(wpath.points[-1], step, step=advance, visit=visit, collapsed=collapsed,
                 ds_min=ds_min, max_turn=-2.0, full=full, failures=FAILURES))
    except KeyboardInterrupt:
        path.end = "interrupted"
        path.message = "stopped by Ctrl-C; the points found are kept"
    except NumericsError as exc:
        if not path.points:
            raise
        path.end, path.message = "step", str(exc)
    return path


def _to_w(p: PathPoint, sc) -> PathPoint:
    t = p.tangent / sc
    return PathPoint(p.z / sc, t / np.linalg.norm(t), p.residual, p.steps, dict(p.tests))


def _to_z(p: PathPoint, sc) -> PathPoint:
    return PathPoint(p.z * sc, p.tangent * sc, p.residual, p.steps, dict(p.tests))


def _scaled_test(fn, sc):
    if _arity(fn) == 1:
        return lambda w: fn(w * sc)
    return lambda w, t: fn(w * sc, t * sc)


def _outside(z, bounds, prev=None):
    """The box edge ``(index, value)`` that ``z`` lies beyond, or ``None``; with the last
    point ``prev``, of the edges crossed the one the secant ``prev -> z`` crosses first (a
    step across two edges ends on the nearer, not on the lower-numbered)."""
    crossed = []
    for i, (lo, hi) in sorted(bounds.items()):
        value = lo if z[i] < lo else hi if z[i] > hi else None
        if value is None:
            continue
        span = z[i] - prev[i] if prev is not None else 0.0
        frac = (value - prev[i]) / span if prev is not None and span != 0 else 0.0
        crossed.append((frac, i, float(value)))
    if not crossed:
        return None
    _, i, value = min(crossed)
    return i, value


def _onto_edge(G, jac, w, bounds, kw, fallback):
    """The point of the curve on the box's edge that ``w`` (a corrected seed, just outside)
    lies beyond: Newton with that component fixed at the edge (``fallback`` when it fails
    or the point found lies outside another edge)."""
    i, value = _outside(w, bounds)
    row = np.zeros_like(w)
    row[i] = 1.0
    try:
        z, res, k, J = correct(G, w, row, value, jac=jac, **kw)
    except FAILURES:
        return fallback
    z[i] = value
    return (z, res, k, J) if _outside(z, bounds) is None else fallback


def _fmt(z) -> str:
    return "(" + ", ".join(f"{float(x):.6g}" for x in z) + ")"


def _next_step(step: float, k: int, ds_max: float) -> float:
    """The step after a point corrected in ``k`` Newton steps (module docstring)."""
    return min(ds_max, step * 1.3) if k <= 3 else (step * 0.7 if k > 6 else step)


def _closed(path, step) -> bool:
    if len(path.points) < 6:
        return False
    first, prev, last = path.points[0].z, path.points[-2].z, path.points[-1].z
    d = np.linalg.norm(last - first)
    return bool(d < 1.5 * step and np.linalg.norm(prev - first) > d
                and float((last - prev) @ path.points[0].tangent) > 0)


def _find_events(G, jac, tests, path, kw, test_tol) -> list[TestEvent]:
    """The located zeros of the tests between the path's last two points."""
    out = []
    a, b = path.points[-2], path.points[-1]
    for name, fn in tests.items():
        fa, fb = a.tests.get(name, math.nan), b.tests.get(name, math.nan)
        if not (math.isfinite(fa) and math.isfinite(fb)) or (fa > 0) == (fb > 0) \
                or fa == 0:
            continue
        try:
            ev = _locate(G, jac, name, fn, a, b, fa, fb, kw, test_tol)
        except FAILURES:
            continue
        ev.after = len(path.points) - 2
        out.append(ev)
    return out
