"""Each curve of the coupled-vdp locking tongue reported once (issue 38).

``kbm diagram coupled-vdp`` continues the fold curves of the locked cycle over
``(sigma, c)``; a seed (a one-parameter fold at another coupling) already on a found curve
is skipped (:func:`numerics.bifurcation.twoway.on_known`, which compares the whole unknown
``z``: the state on the section ``xdot_1 = 0`` at the maximum of ``x_1``, the period and
the parameters).  A symmetric partner orbit would trace the same curve with another state;
the checks here:

- The symmetries of the field of ``x_i'' + x_i = mu F_i`` with coupled-vdp's ``F``: the
  reflection ``(x1, x2) -> -(x1, x2)`` (``F`` odd) at every ``(sigma, c)``; the exchange
  of the oscillators only at ``sigma = 0``, and no map of the states with
  ``sigma -> -sigma`` (the detuning sits in ``F_2`` alone), checked on the flow.  The locked
  cycle at a point of the tongue's edge is its own reflection half a period on,
  ``y(T/2) = -y(0)`` (scipy, from the hand-written field): the reflected orbit has the same
  section point, so it cannot give a second curve.
- The diagram has each edge once: two true curves (one per side) and two averaged ones per
  order, no two coinciding (a duplicate would agree to ~1e-8: two converged continuations
  of one curve, compared through a cubic spline over ``c``).  With the skip turned off the
  same check finds the two duplicated pairs (the check can fail).
"""

from __future__ import annotations

import argparse
import json

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.interpolate import CubicSpline

from numerics.bifurcation import coupled

MU = 0.1
AXES = ("sigma", "c")
RANGES = {"sigma": (-1.0, 1.0), "c": (0.05, 0.6)}


def deviation(a, b) -> float | None:
    """``max |sigma_a(c) - sigma_b(c)|`` over the points of ``a`` whose ``c`` lies within
    ``b``'s, ``sigma_b`` the cubic spline through ``b``'s points (an edge of the tongue is a
    graph over ``c``); ``None`` where the ranges do not overlap."""
    A, B = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    o = np.argsort(B[:, 1])
    cb, sb = B[o, 1], B[o, 0]
    assert np.all(np.diff(cb) > 0), "the edge is not a graph over c"
    inside = (A[:, 1] >= cb[0]) & (A[:, 1] <= cb[-1])
    if not inside.any():
        return None
    return float(np.max(np.abs(A[inside, 0] - CubicSpline(cb, sb)(A[inside, 1]))))


def duplicated(curves, tol: float = 1e-8) -> list[tuple[int, int]]:
    """The pairs of curves (same kind, method and order) that coincide to ``tol``."""
    out = []
    for i, a in enumerate(curves):
        for j in range(i + 1, len(curves)):
            b = curves[j]
            if (a.kind, a.method, a.order) != (b.kind, b.method, b.order):
                continue
            d = [deviation(a.points, b.points), deviation(b.points, a.points)]
            if all(x is not None and x < tol for x in d):
                out.append((i, j))
    return out


def field(sigma, c, mu=MU):
    """coupled-vdp written out: ``x1'' + x1 = mu ((1 - x1^2) x1' + c (x2' - x1'))``,
    ``x2'' + x2 = mu ((1 - x2^2) x2' + c (x1' - x2') - 2 sigma x2)``; the state is
    ``(x1, x2, x1', x2')``."""
    def f(t, y):
        x1, x2, v1, v2 = y
        return [v1, v2, -x1 + mu * ((1 - x1**2) * v1 + c * (v2 - v1)),
                -x2 + mu * ((1 - x2**2) * v2 + c * (v1 - v2) - 2 * sigma * x2)]
    return f


@pytest.fixture(scope="module")
def tongue():
    """The true edges seeded at c = 0.3 and 0.31 (three points each way), with every seed
    and whether it was skipped as on a found curve."""
    seen = []
    real = coupled.on_known

    def spy(z0, tasks, kind, scale, tol):
        hit = real(z0, tasks, kind, scale, tol)
        seen.append((np.array(z0, dtype=float), hit))
        return hit
    tasks: list = []
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(coupled, "on_known", spy)
        curves, _ = coupled.coupled_true_folds("coupled-vdp", {"mu": MU}, AXES, RANGES,
                                               [0.3, 0.31], max_points=3, tasks_out=tasks)
    return curves, tasks, seen


def test_each_edge_once_and_the_skipped_seeds_lie_on_them(tongue):
    """Two true curves, one per edge, not coinciding and not mirror images (the true
    tongue is not symmetric in sigma: -0.2955 and 0.3045 at c = 0.3, kbm lock); the two
    seeds at c = 0.31 were skipped, and each lies on the reported edge of its side to 1e-8
    (the spline through the curve's converged points), at the same section point and period
    (1e-7; the other edge's state is 0.1 away)."""
    curves, tasks, seen = tongue
    assert len(curves) == 2 and duplicated(curves) == []
    sides = sorted(np.sign(np.mean(np.asarray(c.points)[:, 0])) for c in curves)
    assert sides == [-1, 1]
    a, b = (np.asarray(c.points) for c in curves)
    assert deviation(a * [-1, 1], b) > 1e-3
    skipped = [z for z, hit in seen if hit]
    assert len(seen) == 4 and len(skipped) == 2
    assert sorted(round(z[-1], 12) for z in skipped) == [0.31, 0.31]
    n2 = 4
    for z in skipped:
        i = next(k for k, c in enumerate(curves)
                 if np.sign(np.mean(np.asarray(c.points)[:, 0])) == np.sign(z[n2]))
        assert deviation([z[n2:]], curves[i].points) < 1e-8
        pts = coupled.joined(tasks[i].paths)
        pts = pts[np.argsort(pts[:, -1])]
        on = CubicSpline(pts[:, -1], pts[:, :n2])(z[-1])  # state and period at its c
        assert np.max(np.abs(on - z[:n2])) < 1e-7
        other = [t for k, t in enumerate(tasks) if k != i][0].z0
        assert np.linalg.norm(other[:n2 - 1] - z[:n2 - 1]) > 0.1


def test_the_reflection_maps_the_locked_cycle_to_itself(tongue):
    """At each seed of the edges: the field is odd, ``f(-y) = -f(y)``, on the package's
    flow (random states, 1e-12), and the cycle integrated by scipy (DOP853, 1e-12) from the
    seed's state closes after ``T`` and is ``-y0`` after ``T/2`` (1e-8): the reflected
    orbit is the cycle itself.  The exchange of the oscillators (with or without
    ``sigma -> -sigma``, with or without the reflection) is not a symmetry there."""
    _, tasks, _ = tongue
    rng = np.random.default_rng(1)
    S = np.array([[0, 1, 0, 0], [1, 0, 0, 0], [0, 0, 0, 1], [0, 0, 1, 0]], dtype=float)
    for task in tasks:
        z = task.z0
        y0, T, sigma, c = task.problem.state(z), z[3], z[4], z[5]
        fl = task.problem.flow.at(sigma=sigma, c=c)
        for y in rng.normal(size=(4, 4)):
            assert np.allclose(fl.rhs(-y), -fl.rhs(y), rtol=1e-12, atol=1e-12)
        flip = task.problem.flow.at(sigma=-sigma, c=c)
        y = rng.normal(size=4)
        for R in (S, -S):
            for g in (fl, flip):
                assert np.max(np.abs(g.rhs(R @ y) - R @ fl.rhs(y))) > 1e-3
        assert np.max(np.abs(flip.rhs(-y) + fl.rhs(y))) > 1e-3
        sol = solve_ivp(field(sigma, c), (0, T), y0, method="DOP853", rtol=1e-12,
                        atol=1e-12, dense_output=True)
        assert np.linalg.norm(sol.y[:, -1] - y0) < 1e-8
        assert np.linalg.norm(sol.sol(T / 2) + y0) < 1e-8
        assert abs(y0[2]) < 1e-14 and y0[0] > 0.5  # on the section, x1 at its maximum


@pytest.mark.slow
def test_cli_diagram_has_each_curve_once(capsys, monkeypatch):
    """``kbm diagram coupled-vdp -p mu=0.1 --vary sigma=-1:1 --vary c=0.05:0.6 --json``:
    two true edges and two averaged ones at orders 1 and 2, no pair coinciding (the first
    order's are mirror images, |sigma| = c, two edges); with the skip of seeds on found
    curves turned off, the same seeds give four true curves and the check finds the two
    duplicated pairs (agreeing to 1e-8).  Sibling in the default run:
    test_each_edge_once_and_the_skipped_seeds_lie_on_them."""
    from numerics.bifurcation.result import Curve
    from numerics.cli._diagram_driven import run_driven

    ns = argparse.Namespace(model="coupled-vdp", param=["mu=0.1"],
                            vary=["sigma=-1:1", "c=0.05:0.6"], json=True, out=None,
                            store=None, resume=False, order=None)
    assert run_driven(ns) == 0
    data = json.loads(capsys.readouterr().out)
    curves = [Curve(c["kind"], [tuple(p) for p in c["points"]], c["method"], c["order"], {})
              for c in data["curves"]]
    groups: dict = {}
    for c in curves:
        groups.setdefault((c.kind, c.method, c.order), []).append(c)
    assert set(groups) == {("fold", "true", None), ("fold", "averaged", 1),
                           ("fold", "averaged", 2)}
    for group in groups.values():
        assert len(group) == 2
        assert sorted(np.sign(np.mean(np.asarray(c.points)[:, 0])) for c in group) == [-1, 1]
    assert duplicated(curves, tol=1e-3) == []
    assert data["codim2"] == []
    others = list(np.linspace(0.05, 0.6, 4)[1:-1])  # the command's seeds
    monkeypatch.setattr(coupled, "on_known", lambda *a, **k: False)
    every, _ = coupled.coupled_true_folds("coupled-vdp", {"mu": MU}, AXES, RANGES, others,
                                          max_points=400)
    assert len(every) == 4
    pairs = duplicated(every)
    assert len(pairs) == 2 and sorted(i for p in pairs for i in p) == [0, 1, 2, 3]
