"""The generic two-parameter continuation (:mod:`numerics.bifurcation.curve`) and the
diagram's result types (:mod:`numerics.bifurcation.result`), against closed forms.

- a circle ``x^2 + y^2 = 1``: every point on it to 1e-12, the zeros of the test functions
  ``x`` and ``y`` at ``(0, +-1)``, ``(-1, 0)`` exactly, the path closes on itself;
- the box: the path ends exactly on the edge, at the circle's crossing ``x = -1/2,
  y = sqrt(3)/2``; resuming a stored path reaches the same end; the other ends (at most
  ``max_points``, ``stop``, the step collapsed at the cusp of ``y^2 = x^3``);
- the cusp of the fold curve of ``f = a + b x - x^3``: the defining system
  ``f = f_x = 0`` continued in ``(x, a, b)`` gives ``a = -2 x^3, b = 3 x^2`` (the
  textbook fold curve ``27 a^2 = 4 b^3``, Kuznetsov section 8.2) and the zero of
  ``f_xx = -6 x`` at the cusp ``(0, 0)``.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from hypothesis import given, strategies as st

from numerics.bifurcation.curve import continue_curve
from numerics.bifurcation.path import CurvePath
from numerics.bifurcation.result import Codim2Point, Curve, Diagram


def _circle(z):
    return np.array([z[0] ** 2 + z[1] ** 2 - 1.0])


def test_circle_points_events_and_closing():
    path = continue_curve(_circle, [1.0, 0.01], tangent=[0, 1], ds=0.05, ds_max=0.2,
                          tests={"x": lambda z: z[0], "y": lambda z: z[1]}, max_points=300,
                          tol=1e-12)
    assert path.end == "closed"
    assert max(abs(math.hypot(*p.z) - 1) for p in path.points) < 1e-12
    found = sorted((e.name, round(e.z[0], 9) + 0.0, round(e.z[1], 9) + 0.0)
                   for e in path.events)
    assert found == [("x", 0.0, -1.0), ("x", 0.0, 1.0), ("y", -1.0, 0.0)]
    assert all(abs(e.value) <= 1e-9 for e in path.events)


def test_circle_ends_on_the_box_edge_and_resumes():
    kw = dict(ds=0.05, ds_max=0.2, bounds={0: (-0.5, 2.0)}, scale=[1.0, 3.0])
    path = continue_curve(_circle, [1.0, 0.01], tangent=[0, 1], **kw)
    assert path.end == "bounds"
    assert path.points[-1].z[0] == -0.5
    assert abs(path.points[-1].z[1] - math.sqrt(3) / 2) < 1e-12
    stored = json.loads(json.dumps(path.to_records()))
    part = CurvePath.from_records({"points": stored["points"][:5], "ds": stored["ds"]})
    again = continue_curve(_circle, None, resume=part, **kw)
    assert again.end == "bounds" and again.points[-1].z[0] == -0.5
    assert abs(again.points[-1].z[1] - math.sqrt(3) / 2) < 1e-12


def test_interrupt_keeps_the_points():
    calls = []

    def progress(pt, path):
        calls.append(pt)
        if len(calls) == 4:
            raise KeyboardInterrupt

    path = continue_curve(_circle, [1.0, 0.0], ds=0.1, progress=progress)
    assert path.end == "interrupted" and len(path.points) == 4


def test_the_other_ends_max_points_stopped_and_a_collapsed_step():
    """The ends the driver (:func:`kbm.slowflow.arclength.walk`) reports besides the box and
    the closing: ``max_points`` points on the circle; ``stop`` at the first point above
    ``y = 1/2``; on the semicubical parabola ``y^2 = x^3`` the step falls below ``ds_min``
    at its cusp ``(0, 0)``, where the tangent reverses."""
    path = continue_curve(_circle, [1.0, 0.01], tangent=[0, 1], ds=0.05, max_points=7)
    assert path.end == "max_points" and len(path.points) == 7
    assert max(abs(math.hypot(*p.z) - 1) for p in path.points) < 1e-9
    path = continue_curve(_circle, [1.0, 0.01], tangent=[0, 1], ds=0.05, ds_max=0.2,
                          stop=lambda pt, p: "above" if pt.z[1] > 0.5 else None)
    assert (path.end, path.message) == ("stopped", "above")
    assert path.points[-1].z[1] > 0.5 >= path.points[-2].z[1]
    path = continue_curve(lambda z: np.array([z[1] ** 2 - z[0] ** 3]), [1.0, 1.0],
                          tangent=[-1, -1], ds=0.1, ds_max=0.3, ds_min=0.02)
    assert path.end == "step" and "fell below 0.02" in path.message
    assert np.linalg.norm(path.points[-1].z) < 5 * 0.02


def test_cusp_of_a_fold_curve():
    """``f = a + b x - x^3``: the fold curve ``(a, b) = (-2 x^3, 3 x^2)`` and its cusp."""
    def G(z):
        x, a, b = z
        return np.array([a + b * x - x ** 3, b - 3 * x ** 2])

    path = continue_curve(G, [1.0, -2.0, 3.0], tangent=[-1, 0, 0], ds=0.05, ds_max=0.1,
                          bounds={0: (-1.0, 2.0)}, tests={"f_xx": lambda z: -6 * z[0]})
    assert path.end == "bounds"
    for p in path.points:
        x, a, b = p.z
        assert abs(a + 2 * x ** 3) < 1e-10 and abs(b - 3 * x ** 2) < 1e-10
    (ev,) = path.events
    assert np.max(np.abs(ev.z)) < 1e-9


@given(st.floats(0.2, 3.0), st.floats(-1.0, 1.0))
def test_ellipse_points_converged(a, y0):
    """Every point of an ellipse ``(x/a)^2 + y^2 = 1`` passes the convergence test."""
    def G(z):
        return np.array([(z[0] / a) ** 2 + z[1] ** 2 - 1.0])

    x0 = a * math.sqrt(max(0.0, 1 - y0 ** 2)) + 0.01
    path = continue_curve(G, [x0, y0], ds=0.05, ds_max=0.3, max_points=40, tol=1e-11,
                          scale=[a, 1.0])
    assert all(abs(G(p.z)[0]) <= 1e-11 for p in path.points)


def test_result_json_contract(tmp_path):
    c = Curve("fold", [(0.1, 1.0), (0.2, 1.5)], "averaged", 1, {"label": "x"})
    p = Codim2Point("cusp", (0.0, 0.0), {"on": ["fold"]})
    d = Diagram("m", {"mu": 0.1}, ("a", "b"), {"a": (0, 1), "b": (0, 2)}, (c,), (p,))
    data = json.loads(json.dumps(d.to_json()))
    assert data["curves"] == [{"kind": "fold", "points": [[0.1, 1.0], [0.2, 1.5]],
                               "method": "averaged", "order": 1, "label": "x"}]
    assert data["codim2"] == [{"kind": "cusp", "point": [0.0, 0.0], "on": ["fold"]}]
    assert data["axes"] == ["a", "b"] and data["params"] == {"mu": 0.1}
    with pytest.raises(ValueError, match="true"):
        Curve("fold", [], "exact")
    out = d.plot(tmp_path)
    assert out.name == "diagram-m.png" and out.stat().st_size > 1000


def test_a_step_across_two_edges_ends_on_the_edge_crossed_first():
    """The line ``p2 = 2 p1`` leaves the box ``[0, 0.6] x [0, 1]`` through ``p2 = 1`` at
    ``p1 = 0.5`` (it would reach ``p1 = 0.6`` only at ``p2 = 1.2``): a step large enough to
    cross both edges at once ends exactly at ``(0.5, 1)``, inside the box."""
    path = continue_curve(lambda z: np.array([z[1] - 2.0 * z[0]]), [0.35, 0.7],
                          tangent=[1, 2], ds=1.0, ds_max=1.0, bounds={0: (0, 0.6), 1: (0, 1)})
    end = path.points[-1].z
    assert path.end == "bounds", path.message
    assert abs(end[0] - 0.5) < 1e-12 and end[1] == 1.0
