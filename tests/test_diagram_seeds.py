"""The seeds of the forced and coupled diagrams' curves (issue 38), the physical-name axes
and the Bessel functions of the coupled slow flows (issue 35: one binding, one lambdify).

- A seed is looked for on lines strictly inside the box (:func:`seed_levels`); a seed that
  corrects to just outside the box starts on its edge (checked on a straight line, whose
  points are known exactly).
- The right Neimark–Sacker curve of ``vdp-forced`` at mu = 0.1, lost when its seed sat on
  the top edge h = 1.5, is found from that seed; a point of it is shot again with scipy
  (``solve_ivp`` on the forced van der Pol and its variational equation, Newton on the
  periodicity): the two Floquet multipliers are a complex pair on the unit circle.  The
  averaged ones at orders 1-3 are found from the same line: order 1 against the closed
  form of its Hopf curve ``h^2 = 1/2 + 8 sigma^2`` (trace ``1 - rho/2 = 0`` on the response
  ``rho/4 - rho^2/8 + rho^3/64 + sigma^2 rho = h^2/4``, Guckenheimer & Holmes 1983,
  sec. 2.1), orders 2 and 3 against the true curve.
- ``sedf-dimer``: ``--vary Delta`` computed as ``delta = Delta/mu`` (:class:`Plane`), the
  order-1 slow flow with its Bessel functions against mpmath, and the empty diagram at
  Delta = 0 explained (the in-phase cycle's transverse multipliers, shot with scipy, stay
  away from 1 on the box: no fold).
"""

from __future__ import annotations

import argparse
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from _references import forced_floquet, section_cycle
from numerics.bifurcation.twoway import both_ways, joined, seed_levels

MU = 0.1
VDP_RANGES = {"sigma": (-1.5, 1.5), "h": (0.05, 1.5)}


@settings(max_examples=50, deadline=None)
@given(lo=st.floats(-1e3, 1e3), span=st.floats(1e-6, 1e3), n=st.integers(1, 12))
def test_seed_levels_lie_strictly_inside(lo, span, n):
    """Property: the seed lines are n equally spaced values strictly inside (lo, hi)."""
    hi = lo + span
    v = seed_levels(lo, hi, n)
    assert len(v) == n and all(lo < x < hi for x in v)
    assert np.allclose(np.diff([lo, *v, hi]), span / (n + 1), rtol=1e-9,
                       atol=1e-12 * (abs(lo) + span))


def test_seed_corrected_outside_starts_on_the_edge():
    """The line z1 = z0 + 0.001 from the seed (0.5, 0.5) on the edge z1 = 0.5: the
    correction (normal to the tangent) lands at z1 = 0.5005, outside; the curve starts on
    the edge instead, at (0.499, 0.5) exactly, and runs to the other edge z1 = 0."""
    G = lambda z: np.array([z[1] - z[0] - 1e-3])  # noqa: E731
    paths = both_ways(G, np.array([0.5, 0.5]), bounds={1: (0.0, 0.5)}, ds=0.05, ds_max=0.1)
    pts = joined(paths)
    assert len(pts) > 3
    assert np.allclose(pts[:, 1] - pts[:, 0], 1e-3, atol=1e-12)
    assert sorted([pts[0, 1], pts[-1, 1]]) == [0.0, 0.5]
    assert any(np.allclose(p, [0.499, 0.5], atol=1e-12) for p in (pts[0], pts[-1]))


def _vdp_floquet(sigma: float, h: float, y0) -> np.ndarray:
    """The Floquet multipliers of the periodic response of x'' + x = mu ((1 - x^2) x' +
    h cos(nu t)), nu = 1 + mu sigma, near ``y0``: Newton on y(T) = y0 (scipy's DOP853 with
    the variational equation), then the monodromy's eigenvalues."""
    nu = 1 + MU * sigma
    return forced_floquet(
        lambda t, x, v: -x + MU * ((1 - x * x) * v + h * math.cos(nu * t)),
        lambda x, v: np.array([[0.0, 1.0], [-1 - 2 * MU * x * v, MU * (1 - x * x)]]),
        2 * math.pi / nu, y0, rtol=1e-11, tol=1e-11, steps=20)[1]


def test_vdp_forced_right_neimark_sacker_from_a_seed_on_the_top_edge():
    """The seed of the right Neimark-Sacker curve on the old top line h = 1.5 (it corrects
    to h = 1.5001) gives the curve, from the edge down to its Bogdanov-Takens end; a point
    of it re-shot with scipy has a complex pair of multipliers of modulus 1 (to 1e-7)."""
    from numerics.bifurcation.forced import DrivenProblem, forced_seeds, forced_true_curves

    prob = DrivenProblem("vdp-forced", {"mu": MU}, ("sigma", "h"))
    seeds = [s for s in forced_seeds(prob, (0.3, 0.6), [1.5], n_points=30)
             if s[0] == "neimark-sacker"]
    assert len(seeds) == 1
    dropped: list = []
    tasks, curves, _ = forced_true_curves(prob, VDP_RANGES, seeds, dropped=dropped)
    assert not dropped and len(curves) == 1
    pts = np.array(curves[0].points)
    assert pts[:, 1].max() == 1.5 and pts[:, 1].min() < 1.02  # the BT end near h = 1.0186
    assert np.all(pts[:, 0] > 0.2)
    z = joined(tasks[0].paths)[len(pts) // 2]  # (x0, x0', sigma, h)
    m = _vdp_floquet(z[2], z[3], z[:2])
    assert abs(m[0].imag) > 1e-3 and np.allclose(np.abs(m), 1.0, atol=1e-7)
    # off the curve (h 1 % larger) the pair leaves the circle: the check can fail
    assert not np.allclose(np.abs(_vdp_floquet(z[2], 1.01 * z[3], z[:2])), 1.0, atol=1e-4)


def test_vdp_forced_averaged_right_neimark_sacker_orders_1_to_3():
    """From the line h = 1.5 the slow flow's right Hopf curves at orders 1-3 are found
    (orders 2, 3 were lost at the edge): order 1 on h^2 = 1/2 + 8 sigma^2, ending at its
    Bogdanov-Takens point (1/4, 1); orders 2 and 3 each end within 1e-3 of the true BT point
    (0.248476, 1.018636, the true curve's end)."""
    from numerics.bifurcation.forced_averaged import averaged_fold_curves

    dropped: list = []
    curves, pts = averaged_fold_curves("vdp-forced", {"mu": MU}, ("sigma", "h"), VDP_RANGES,
                                       (1, 2, 3), [1.5], dropped=dropped)
    right = {c.order: np.array(c.points) for c in curves
             if c.kind == "neimark-sacker" and np.array(c.points)[:, 0].mean() > 0}
    assert sorted(right) == [1, 2, 3]
    s, h = right[1].T
    assert np.allclose(h * h, 0.5 + 8 * s * s, atol=1e-9)
    bt = {p.detail["order"]: p.point for p in pts
          if p.kind == "bogdanov-takens" and p.point[0] > 0}
    assert bt[1] == pytest.approx((0.25, 1.0), abs=1e-8)
    for n in (2, 3):
        assert math.dist(bt[n], (0.248476, 1.018636)) < 1e-3
        assert right[n][:, 1].max() == pytest.approx(1.5, abs=1e-12)


def test_dropped_seed_is_reported():
    """A seed whose correction fails is not silently lost: it is recorded with why."""
    from numerics.bifurcation.forced import DrivenProblem, forced_true_curves

    prob = DrivenProblem("vdp-forced", {"mu": MU}, ("sigma", "h"))
    dropped: list = []
    _, curves, _ = forced_true_curves(prob, VDP_RANGES, [("period-doubling",
                                                          np.array([0.3, 0.0, 0.0, 0.5]))],
                                      dropped=dropped, max_points=5)
    assert not curves and len(dropped) == 1
    assert dropped[0]["kind"] == "period-doubling" and dropped[0]["seed"] == [0.0, 0.5]
    assert dropped[0]["reason"]


# -- sedf-dimer: the physical axes, the Bessel functions, the empty diagram -----------------

def test_plane_maps_physical_axes_to_scaled_ones():
    """--vary Delta=0:1 at mu = 0.1 is delta = Delta/mu in [0, 10]; lam=0.5:2 is k = 2 pi/lam
    in [pi, 4 pi] (increasing); the points go back to Delta and lam.  Delta fixed with mu
    varied, or a range where the scaled value is not finite, is refused in -p/--vary terms."""
    from kbm.model.coupled_builtins import get_coupled_model
    from kbm.errors import ParameterError
    from numerics.cli.params.plane import Plane

    model = get_coupled_model("sedf-dimer")
    p = Plane.of(model, {"mu": "0.1"}, ("Delta", "kappa"), {"Delta": (0, 1), "kappa": (0.1, 1)})
    assert p.axes == ("delta", "kappa") and p.ranges["delta"] == pytest.approx((0, 10))
    assert p.point((7.5, 0.3)) == pytest.approx((0.75, 0.3))
    q = Plane.of(model, {"mu": "0.1", "Delta": "0.5"}, ("lam", "beta"),
                 {"lam": (0.5, 2), "beta": (0.5, 1.5)})
    assert q.ranges["k"] == pytest.approx((math.pi, 4 * math.pi))
    assert q.point((math.pi, 1.0)) == pytest.approx((2.0, 1.0))
    with pytest.raises(ParameterError, match=r"-p delta=VALUE"):
        Plane.of(model, {"Delta": "0.5"}, ("mu", "kappa"), {"mu": (0.05, 0.2),
                                                           "kappa": (0.1, 1)})
    with pytest.raises(ParameterError, match=r"--vary lam=0:2"):
        Plane.of(model, {"mu": "0.1"}, ("lam", "beta"), {"lam": (0, 2), "beta": (0.5, 1.5)})


def test_diagram_setup_takes_a_physical_axis_like_p():
    """``kbm diagram sedf-dimer -p mu=0.1 --vary Delta=0:1 --vary kappa=0.1:1`` was refused
    ("give either delta or Delta, not both"); its setup now computes over delta in [0, 10]
    with no delta among the fixed values."""
    from numerics.cli._diagram_driven import _setup

    args = argparse.Namespace(model="sedf-dimer", rhs=None, param=["mu=0.1"],
                              vary=["Delta=0:1", "kappa=0.1:1"], order=None)
    model, params, values, plane, order = _setup(args, "coupled")
    assert plane.user == ("Delta", "kappa") and plane.axes == ("delta", "kappa")
    assert "delta" not in values and "Delta" not in values and values["mu"] == MU
    assert plane.ranges["delta"] == pytest.approx((0.0, 10.0))


@pytest.mark.parametrize("argv, says", [
    (["-p", "Delta=0.5", "--vary", "mu=0.05:0.2", "--vary", "kappa=0.1:1"],
     "give the scaled -p delta=VALUE instead of -p Delta"),
    (["-p", "mu=0.1", "--vary", "delta=0:10", "--vary", "Delta=0:1"],
     "give either delta or Delta"),
])
def test_diagram_refuses_a_scaled_value_bound_to_two_names_in_command_line_terms(
        argv, says, capsys):
    """A refused axis is one line on stderr and exit 2 (no traceback), in -p/--vary terms."""
    from numerics.cli import main

    assert main(["diagram", "sedf-dimer", *argv]) == 2
    err = capsys.readouterr().err
    assert says in err and "Traceback" not in err and len(err.strip().splitlines()) == 1


def test_sedf_dimer_slow_flow_bessel_against_mpmath():
    """The order-1 slow flow of sedf-dimer at Delta = 0.5 (besselj of the potential's
    sin k x) was lambdified without scipy's Bessel function (NameError); it now agrees with
    sympy's own evaluation (mpmath) to 1e-13, and the averaged edges are computed."""
    import sympy as sp

    from kbm.model.coupled import amplitudes
    from kbm.expansion.coupled import derive_coupled
    from numerics.locking.mutual import averaged_edges
    from numerics.locking.slow_flow import _slow_flow, _split
    from numerics.flow.coupled_flow import bind_coupled
    from numerics.errors import NumericsError

    model, values = bind_coupled("sedf-dimer", {"mu": 0.1, "Delta": 0.5, "kappa": 0.3,
                                                "beta": 1.0})
    fixed = _split(model, values, "kappa")
    f, jac, m = _slow_flow(model, 1, fixed, "kappa")
    y = np.array([1.7, 1.9, 0.4])
    got = np.asarray(f(y, 0.3, 0.1), dtype=float)
    res = derive_coupled(model, 1, dict(fixed))
    state = [*amplitudes(2), *[g for g, _ in res.gammas]]
    sub = {**dict(zip(state, y)), sp.Symbol("kappa"): 0.3, sp.Symbol("mu"): 0.1}
    want = [float(sp.N(r.subs(sub), 20)) for r in res.slow_flow()]
    assert any(r.atoms(sp.besselj) for r in res.slow_flow())
    assert np.allclose(got, want, rtol=1e-13, atol=1e-15)
    try:  # the locked state followed in kappa from 0 (degenerate there): an answer or a
        averaged_edges(model, values, 1, "kappa", 1.0)  # package error, not a NameError
    except NumericsError as exc:
        assert "no locked state" in str(exc) and "np.float64" not in str(exc)


def _inphase_transverse_multipliers(kappas, beta: float) -> list[np.ndarray]:
    """The multipliers of the difference mode u = x1 - x2 on the in-phase cycle x1 = x2 =
    x(t) of the dimer at Delta = 0 (x'' + x = mu (1 - beta x^2) x', the van der Pol cycle,
    the same at every kappa): u'' + u = mu ((1 - beta x^2) u' - 2 beta x x' u - 2 kappa u),
    shot with scipy, at each value of ``kappas``."""
    from scipy.integrate import solve_ivp

    def vdp(t, w):
        return [w[1], -w[0] + MU * (1 - beta * w[0] ** 2) * w[1]]

    # Newton on (x0, T), x'(0) = 0 (the section)
    x0, T = section_cycle(vdp, 2 / math.sqrt(beta), 2 * math.pi)
    out = []
    for kappa in kappas:
        def ext(t, w, kappa=kappa):
            x, v, P = w[0], w[1], w[2:].reshape(2, 2)
            A = np.array([[0.0, 1.0], [-1 - MU * (2 * beta * x * v + 2 * kappa),
                                       MU * (1 - beta * x * x)]])
            return np.concatenate([vdp(t, w[:2]), (A @ P).ravel()])

        s = solve_ivp(ext, (0, T), [x0, 0.0, 1, 0, 0, 1], method="DOP853", rtol=1e-11,
                      atol=1e-12)
        out.append(np.linalg.eigvals(s.y[2:, -1].reshape(2, 2)))
    return out


def test_dimer_at_delta_zero_has_no_fold_in_the_box():
    """At Delta = 0 the in-phase cycle (the van der Pol cycle in both) exists at every
    (kappa, beta): the coupling vanishes on it.  Its transverse multipliers (the
    difference mode, shot with scipy) lie inside the unit circle on kappa = 0.1..1 (the one
    nearest 1, 0.9953 at kappa = 0.1, falls with kappa: it is 1 only at kappa = 0, the
    uncoupled pair), and they do not depend on beta (x -> x/sqrt(beta) scales it out): no
    multiplier +1 joins the trivial one in the box, no fold of the locked cycle, so the
    empty diagram is right."""
    kappas = np.linspace(0.1, 1.0, 7)
    top = [np.max(np.abs(m)) for m in _inphase_transverse_multipliers(kappas, 1.0)]
    assert top[0] == pytest.approx(0.9953, abs=1e-4)
    assert max(top) < 0.999 and np.all(np.diff(top) <= 1e-9)
    low, high = (_inphase_transverse_multipliers([0.1, 1.0], b) for b in (0.5, 1.5))
    for m1, m2 in zip(low, high):
        assert np.allclose(np.sort_complex(m1), np.sort_complex(m2), atol=1e-7)


def test_empty_coupled_diagram_says_why(capsys):
    """``kbm diagram sedf-dimer -p mu=0.1 -p Delta=0 --vary kappa=0.1:1 --vary beta=0.5:1.5``
    found no curve and printed nothing about it; it now names the seed lines searched,
    from where, to where, and that no fold of the locked cycle was met."""
    import json

    from numerics.cli._diagram_driven import run_driven

    base = dict(model="sedf-dimer", rhs=None, param=["mu=0.1", "Delta=0"],
                vary=["kappa=0.1:1", "beta=0.5:1.5"], order=1, out=None, store=None,
                resume=False, no_averaged=True)
    assert run_driven(argparse.Namespace(**base, json=False)) == 0
    out = capsys.readouterr().out
    assert "no true curve in the box: the folds were looked for on 2 lines" in out
    assert "at beta = 0.833333, along kappa from 0.55 to 0.1 and to 1: no fold" in out
    assert run_driven(argparse.Namespace(**base, json=True)) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["curves"] == [] and len(data["seed_lines"]) == 2
    assert all(r["folds"] == [] and r["period"] == pytest.approx(
        2 * math.pi * (1 + MU**2 / 16), rel=1e-5) for r in data["seed_lines"])


# -- the command line (slow: whole diagrams; their cheaper siblings above) -------------------

def _cli_json(capsys, *argv) -> dict:
    import json

    from numerics.cli import main

    assert main(list(argv) + ["--json"]) == 0
    return json.loads(capsys.readouterr().out)


@pytest.mark.slow
def test_cli_vdp_forced_diagram_has_both_neimark_sacker_curves(capsys):
    """``kbm diagram vdp-forced -p mu=0.1 --vary sigma=-1.5:1.5 --vary h=0.05:1.5`` (25 s;
    siblings in the default run: test_vdp_forced_right_neimark_sacker_from_a_seed_on_the_top_
    edge, test_vdp_forced_averaged_right_neimark_sacker_orders_1_to_3): the true
    Neimark-Sacker curves on both sides (the right one was lost) and the averaged ones at
    orders 1-3 on both sides (orders 2, 3 on the right were lost), each averaged curve
    within 2e-2 (order 1), 1e-3 (orders 2, 3) of the true one of its side; nothing dropped."""
    from numerics.bifurcation.twoway import curve_distance

    d = _cli_json(capsys, "diagram", "vdp-forced", "-p", "mu=0.1", "--vary", "sigma=-1.5:1.5",
                  "--vary", "h=0.05:1.5")
    ns = [c for c in d["curves"] if c["kind"] == "neimark-sacker"]
    side = {(c["method"], c["order"], int(np.sign(np.mean(np.array(c["points"])[:, 0])))): c
            for c in ns}
    assert len(side) == len(ns) == 8
    for s in (-1, 1):
        true = side[("true", None, s)]["points"]
        for n, tol in ((1, 2e-2), (2, 1e-3), (3, 1e-3)):
            assert curve_distance(true, side[("averaged", n, s)]["points"]) < tol
    assert d["dropped"] == []


@pytest.mark.slow
def test_cli_sedf_dimer_physical_axis_equals_scaled_axis(capsys):
    """``--vary Delta=0:1`` at mu = 0.1 (refused before: "give either delta or Delta, not
    both") is the diagram of ``--vary delta=0:10`` with the values divided by mu (40 s;
    sibling in the default run: test_diagram_setup_takes_a_physical_axis_like_p)."""
    common = ["-p", "mu=0.1", "--vary", "kappa=0.1:1", "--order", "1", "--no-averaged"]
    a = _cli_json(capsys, "diagram", "sedf-dimer", "--vary", "Delta=0:1", *common)
    b = _cli_json(capsys, "diagram", "sedf-dimer", "--vary", "delta=0:10", *common)
    assert a["axes"] == ["Delta", "kappa"] and a["ranges"]["Delta"] == [0.0, 1.0]
    assert len(a["seed_lines"]) == len(b["seed_lines"]) == 2
    for la, lb in zip(a["seed_lines"], b["seed_lines"]):
        assert la["along"] == "Delta" and lb["along"] == "delta"
        assert la["from"] == pytest.approx(lb["from"] * 0.1)
        assert la["folds"] == pytest.approx([f * 0.1 for f in lb["folds"]])
        assert la["period"] == pytest.approx(lb["period"], rel=1e-12)
    assert len(a["curves"]) == len(b["curves"])


def test_dimer_locking_edge_in_delta_is_no_fold_and_is_said_so():
    """The dimer's averaged locking edge in delta (``kbm lock sedf-dimer --vary delta=-1:1``:
    -0.3496 at kappa = 0.4, order 1) sits on the symmetric state a1 = a2, gamma = 0: the
    in-phase state loses stability there by a symmetry-breaking pitchfork, where the fold's
    defining system is singular.  The seed is not dropped silently: the record says so."""
    from numerics.bifurcation.coupled import coupled_averaged_folds

    vals = {"mu": MU, "beta": 1.0, "lam": 1.0}
    edge = -0.87398916 * 0.4  # kbm lock's order-1 edges: -0.87398916 kappa (kappa = 0.1..1)
    dropped: list = []
    curves = coupled_averaged_folds("sedf-dimer", vals, ("delta", "kappa"),
                                    {"delta": (-1.0, 1.0), "kappa": (0.1, 1.0)}, (1,), [0.4],
                                    dropped=dropped)
    assert curves == [] and len(dropped) == 1
    assert dropped[0]["seed"] == pytest.approx([edge, 0.4], abs=1e-7)
    assert "singular" in dropped[0]["reason"] and "pitchfork" in dropped[0]["reason"]
