"""Two-parameter curves of forced and coupled oscillators (issue 38), each checked by an
independent computation.

- The averaged cusp of the forced Duffing oscillator (order 1) against the closed form of
  the first-order frequency response ``h^2/4 = a^2 (zeta^2 + (sigma - 3 alpha a^2/8)^2)``
  (Nayfeh & Mook 1979, eq. 4.1.17): the folds ``zeta^2 + 3u^2 - 2 sigma u = 0`` with
  ``u = sigma - 3 alpha a^2/8`` have a double root at ``sigma_c = sqrt(3) zeta``,
  ``h_c^2 = 256 zeta^3/(9 sqrt(3) alpha)``; and its scaling ``a -> a/sqrt(alpha)``,
  ``h -> h/sqrt(alpha)`` (the slow flow's symmetry, linear in ``h``).
- A point of the true fold curve against the one-parameter fold of ``kbm response``'s
  continuation in ``sigma`` at that ``h``
  (:func:`numerics.shooting.forced_branch.numeric_response`), and
  the multiplier +1 of its monodromy.
- The true cusp against the averaged cusps at orders 1-3 (the distance decreasing with
  the order).
- The coupled-vdp tongue against ``kbm lock``'s true edges (bisection on shooting and the
  one-parameter fold) and the first-order averaged edges ``sigma = +-c``.
"""

from __future__ import annotations

import argparse
import json
import math

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from numerics.bifurcation.corrector import correct
from numerics.bifurcation.forced import DrivenProblem, forced_seeds, forced_true_curves
from numerics.bifurcation.forced_averaged import averaged_fold_curves
from numerics.bifurcation.twoway import joined

DUFFING = {"mu": 0.1, "zeta": 0.1, "alpha": 1.0}
AXES = ("sigma", "h")
RANGES = {"sigma": (-1.0, 3.0), "h": (0.02, 0.4)}


def _cusp_closed_form(zeta, alpha):
    return math.sqrt(3) * zeta, math.sqrt(256 * zeta**3 / (9 * math.sqrt(3) * alpha))


@pytest.mark.parametrize("zeta, alpha", [(0.1, 1.0), (0.05, 4.0)])
def test_averaged_cusp_order1_closed_form(zeta, alpha):
    """Nayfeh & Mook eq. 4.1.17: the averaged fold curves meet at the closed-form cusp."""
    values = {"mu": 0.1, "zeta": zeta, "alpha": alpha}
    sc, hc = _cusp_closed_form(zeta, alpha)
    curves, points = averaged_fold_curves("duffing-forced", values, AXES,
                                          {"sigma": (-1.0, 3.0), "h": (0.3 * hc, 3 * hc)},
                                          (1,), [2.5 * hc])
    cusps = [p for p in points if p.kind == "cusp"]
    assert len(cusps) == 1 and [c.kind for c in curves] == ["fold"]
    assert cusps[0].point == pytest.approx((sc, hc), abs=1e-9)
    # every point of the averaged fold curve solves the first-order fold conditions
    k = 3 * alpha / 8
    for s, h in curves[0].points:
        roots = np.roots([3.0, -2 * s, zeta**2])  # 3u^2 - 2 sigma u + zeta^2 = 0
        vals = [(s - u) / k * (zeta**2 + u**2) * 4 for u in roots.real
                if abs(roots.imag).max() < 1e-9 and s - u > 0]
        assert min(abs(v - h * h) for v in vals) < 1e-8 * (1 + h * h)


def test_averaged_cusp_scaling_in_alpha():
    """The symmetry a -> a/sqrt(alpha), h -> h/sqrt(alpha) of the first-order slow flow:
    the cusp at alpha = 4 has the sigma of alpha = 1 and half its h."""
    out = []
    for alpha in (1.0, 4.0):
        _, pts = averaged_fold_curves("duffing-forced", {**DUFFING, "alpha": alpha}, AXES,
                                      {"sigma": (-1.0, 3.0), "h": (0.02, 0.4)}, (1,), [0.3])
        out.append([p.point for p in pts if p.kind == "cusp"][0])
    assert out[1][0] == pytest.approx(out[0][0], abs=1e-10)
    assert out[1][1] == pytest.approx(out[0][1] / 2, abs=1e-10)


@pytest.fixture(scope="module")
def true_fold():
    prob = DrivenProblem("duffing-forced", DUFFING, AXES)
    seeds = forced_seeds(prob, RANGES["sigma"], [0.3])
    tasks, curves, points = forced_true_curves(prob, RANGES, seeds)
    return prob, tasks, curves, points


def test_true_fold_points_against_one_parameter_folds(true_fold):
    """A point of the fold curve is a fold of the one-parameter response curve at its h
    (kbm response's continuation), and its monodromy has a multiplier +1."""
    from kbm.expansion.forced import derive_forced
    from numerics.flow.forced_system import ForcedSystem
    from numerics.shooting.forced_branch import numeric_response

    prob, tasks, curves, _ = true_fold
    assert [c.kind for c in curves] == ["fold"]
    pts = joined(tasks[0].paths)
    assert len(pts) > 20 and curves[0].detail["residual_max"] < 1e-10
    for z in (pts[len(pts) // 4], pts[3 * len(pts) // 4]):
        vals = {**DUFFING, "h": z[3]}
        nr = numeric_response(ForcedSystem("duffing-forced", vals),
                              derive_forced("duffing-forced", 1).slow_flow(vals),
                              RANGES["sigma"])
        assert min(abs(f.sigma - z[2]) for f in nr.folds) < 1e-6
        mult = np.linalg.eigvals(prob.monodromy(z)[1])
        assert min(abs(mult - 1)) < 1e-7


def test_true_cusp_against_averaged_orders(true_fold):
    """One cusp on the true fold curve; the averaged cusps approach it with the order
    (orders 1-3, mu = 0.1)."""
    _, _, _, points = true_fold
    cusps = [p.point for p in points if p.kind == "cusp"]
    assert len(cusps) == 1
    _, av = averaged_fold_curves("duffing-forced", DUFFING, AXES, RANGES, (1, 2, 3), [0.3])
    d = [math.dist(cusps[0], [p.point for p in av if p.detail["order"] == n][0])
         for n in (1, 2, 3)]
    assert d[0] > d[1] > d[2]
    assert d[0] < 0.1 * 0.1 and d[2] < 1e-4


def test_coupled_vdp_averaged_tongue_order1():
    """The first-order averaged tongue of coupled-vdp is |sigma| = c (kbm lock order 1)."""
    from numerics.bifurcation.coupled import coupled_averaged_folds

    curves = coupled_averaged_folds("coupled-vdp", {"mu": 0.1}, ("sigma", "c"),
                                    {"sigma": (-1.0, 1.0), "c": (0.05, 0.6)}, (1,), [0.3])
    assert len(curves) == 2
    for c in curves:
        for s, cv in c.points:
            assert abs(abs(s) - cv) < 1e-10


def test_coupled_vdp_tongue_from_a_range_without_zero():
    """Over ``sigma`` in [0.1, 1] the seed lines started at the middle 0.55, outside the
    order-1 tongue ``|sigma| < c`` (closed form of ``gamma' = mu (sigma - c sin gamma)``):
    no curve.  They now start where ``kbm lock`` does (``line_start``): at c = 0.3 the first
    value from the middle out inside the tongue, 0.2125; the right edge ``sigma = c`` is
    found from it."""
    from numerics.bifurcation.coupled import coupled_averaged_folds, line_start
    from numerics.locking.start import start_values

    inside = [s for s in start_values(0.1, 1.0) if abs(s) < 0.3]
    assert line_start("coupled-vdp", {"mu": 0.1}, "sigma", "c", 0.3, (0.1, 1.0)) \
        == inside[0] == pytest.approx(0.2125)
    curves = coupled_averaged_folds("coupled-vdp", {"mu": 0.1}, ("sigma", "c"),
                                    {"sigma": (0.1, 1.0), "c": (0.05, 0.6)}, (1,), [0.3])
    assert len(curves) == 1
    assert all(abs(s - cv) < 1e-10 for s, cv in curves[0].points)


@pytest.mark.slow
def test_coupled_vdp_tongue_against_kbm_lock():
    """The fold curve of the locked cycle, corrected onto c = 0.3 (not a seed), gives
    kbm lock's true edges (bisection on shooting, then the one-parameter fold)."""
    from numerics.bifurcation.coupled import coupled_true_folds
    from numerics.locking.fold import true_edges

    tasks = []
    curves, _ = coupled_true_folds("coupled-vdp", {"mu": 0.1}, ("sigma", "c"),
                                   {"sigma": (-1.0, 1.0), "c": (0.05, 0.6)}, [0.45],
                                   tasks_out=tasks)
    assert len(curves) == 2
    edges = {e.side: e.sigma for e in true_edges("coupled-vdp", {"mu": 0.1, "c": 0.3},
                                                  tol=1e-7)}  # kbm lock's default
    for task in tasks:
        pts = joined(task.paths)
        z = pts[np.argmin(abs(pts[:, -1] - 0.3))]
        row = np.zeros(len(z))
        row[-1] = 1.0
        zc, res, _, _ = correct(task.problem.G, z, row, 0.3, jac=task.problem.J)
        side = 1 if zc[-2] > 0 else -1
        assert res < 1e-10 and zc[-2] == pytest.approx(edges[side], abs=1e-7)


def test_run_driven_json_and_errors(tmp_path, capsys):
    """kbm diagram's forced entry point: the JSON contract (curves, codim2) and one-line
    refusals."""
    from kbm.errors import ParameterError
    from numerics.cli._diagram_driven import run_driven

    ns = argparse.Namespace(model="duffing-forced", param=["mu=0.1", "zeta=0.1", "alpha=1"],
                            vary=["sigma=-1:3", "h=0.05:0.4"], json=True, out=None,
                            store=str(tmp_path / "d"), resume=False, order=1)
    assert run_driven(ns) == 0
    data = json.loads(capsys.readouterr().out)
    kinds = {(c["kind"], c["method"], c["order"]) for c in data["curves"]}
    assert kinds == {("fold", "true", None), ("fold", "averaged", 1)}
    assert {p["kind"] for p in data["codim2"]} == {"cusp"}
    assert all(len(p) == 2 for c in data["curves"] for p in c["points"])
    from numerics.store import StoreError

    with pytest.raises(StoreError, match="--resume"):  # the run is in the folder already
        run_driven(ns)
    ns.resume = True  # everything stored: the same diagram again, nothing recomputed
    assert run_driven(ns) == 0
    assert json.loads(capsys.readouterr().out) == data
    for bad in (dict(param=["mu=0.1", "zeta=0.1", "alpha=1", "gamma=2"]),
                dict(vary=["h=0.05:0.4"]), dict(vary=["zeta=0:1", "h=0.05:0.4"])):
        with pytest.raises(ParameterError):
            run_driven(argparse.Namespace(**{**vars(ns), "resume": False, "store": None,
                                             **bad}))


def test_forced_vdp_averaged_cusp_and_bogdanov_takens_closed_form():
    """Forced van der Pol at order 1: with rho = a^2 the response is
    f(rho) = rho/4 - rho^2/8 + rho^3/64 + sigma^2 rho = h^2/4; the folds f' = 0 meet at the
    cusp f'' = 0 (rho = 8/3: sigma = +-1/sqrt(12), h = sqrt(32/27)), and the slow flow's
    trace 1 - rho/2 vanishes on a fold at the Bogdanov-Takens points (rho = 2: sigma = +-1/4,
    h = 1), where the Hopf (averaged Neimark-Sacker) curves end (Guckenheimer & Holmes
    1983, sec. 2.1)."""
    curves, pts = averaged_fold_curves("vdp-forced", {"mu": 0.1}, AXES,
                                       {"sigma": (-1.5, 1.5), "h": (0.05, 1.5)}, (1,), [1.2, 0.6])
    found = {(p.kind, round(p.point[0], 6), round(p.point[1], 6)) for p in pts}
    c, h = round(1 / math.sqrt(12), 6), round(math.sqrt(32 / 27), 6)
    assert {("cusp", -c, h), ("cusp", c, h), ("bogdanov-takens", -0.25, 1.0),
            ("bogdanov-takens", 0.25, 1.0)} <= found
    hopf = [q for cv in curves if cv.kind == "neimark-sacker" for q in cv.points]
    assert hopf and min(q[1] for q in hopf) == pytest.approx(1.0, abs=1e-7)


def test_run_driven_ctrl_c_keeps_the_paths_and_resume_finishes(tmp_path, capsys, monkeypatch):
    """Ctrl-C during a true curve: exit 130 with what was found, the path kept in --store;
    --resume continues it from its last point to the diagram of an uninterrupted run."""
    import numerics.cli._diagram_driven as dd

    base = dict(model="duffing-forced", param=["mu=0.1", "zeta=0.1", "alpha=1"],
                vary=["sigma=-1:3", "h=0.05:0.4"], json=True, out=None, order=1)
    assert dd.run_driven(argparse.Namespace(**base, store=None, resume=False)) == 0
    full = json.loads(capsys.readouterr().out)
    calls = {"n": 0}

    def interrupt(self, point, path):
        calls["n"] += 1
        if calls["n"] == 12:
            raise KeyboardInterrupt

    monkeypatch.setattr(dd._Progress, "__call__", interrupt)
    store = str(tmp_path / "d")
    assert dd.run_driven(argparse.Namespace(**base, store=store, resume=False)) == 130
    part = json.loads(capsys.readouterr().out)
    assert part["complete"] is False
    assert 0 < sum(len(c["points"]) for c in part["curves"]) < \
        sum(len(c["points"]) for c in full["curves"] if c["method"] == "true")
    monkeypatch.undo()
    assert dd.run_driven(argparse.Namespace(**base, store=store, resume=True)) == 0
    done = json.loads(capsys.readouterr().out)
    assert done["complete"] is True
    for a, b in zip(done["codim2"], full["codim2"]):
        assert a["kind"] == b["kind"] and np.allclose(a["point"], b["point"], atol=1e-8)
    ta = [c for c in done["curves"] if c["method"] == "true"]
    tb = [c for c in full["curves"] if c["method"] == "true"]
    assert len(ta) == len(tb) == 1
    assert all(min(math.dist(p, q) for q in tb[0]["points"]) < 2e-2 for p in ta[0]["points"])


@pytest.mark.slow
def test_forced_vdp_neimark_sacker_against_one_parameter_bisection():
    """A point of the true Neimark-Sacker curve of vdp-forced is where kbm response's
    one-parameter branch at that h has its Neimark-Sacker point (located there by bisection
    on shooting, numerics.shooting.special); the true Bogdanov-Takens points lie within
    1e-3 of the order-2 averaged ones."""
    from kbm.expansion.forced import derive_forced
    from numerics.flow.forced_system import ForcedSystem
    from numerics.shooting.forced_branch import numeric_response

    ranges = {"sigma": (-1.5, 1.5), "h": (0.05, 1.5)}
    prob = DrivenProblem("vdp-forced", {"mu": 0.1}, AXES)
    seeds = forced_seeds(prob, ranges["sigma"], [1.2, 0.6])
    tasks, curves, points = forced_true_curves(prob, ranges, seeds)
    ns = [t for t in tasks if t.kind == "neimark-sacker"]
    assert len(ns) == 2
    z = joined(ns[0].paths)[len(joined(ns[0].paths)) // 2]
    vals = {"mu": 0.1, "h": z[3]}
    nr = numeric_response(ForcedSystem("vdp-forced", vals),
                          derive_forced("vdp-forced", 1).slow_flow(vals), ranges["sigma"])
    located = [sp.orbit.sigma for sp in nr.special if sp.kind == "neimark-sacker"]
    assert min(abs(s - z[2]) for s in located) < 1e-5
    _, av = averaged_fold_curves("vdp-forced", {"mu": 0.1}, AXES, ranges, (2,), [1.2, 0.6])
    bt_true = [p.point for p in points if p.kind == "bogdanov-takens"]
    bt_av = [p.point for p in av if p.kind == "bogdanov-takens"]
    assert len(bt_true) >= 2
    for p in bt_true:
        assert min(math.dist(p, q) for q in bt_av) < 1e-3


@pytest.mark.slow
def test_duffing_cusp_error_falls_as_mu_to_the_order():
    """The true cusp's distance to the order-N averaged cusp falls as mu^N: halving mu
    divides it by about 2^N (orders 1-3)."""
    err = {}
    for mu in (0.1, 0.05):
        vals = {**DUFFING, "mu": mu}
        prob = DrivenProblem("duffing-forced", vals, AXES)
        _, _, pts = forced_true_curves(prob, RANGES, forced_seeds(prob, RANGES["sigma"], [0.3]))
        true = [p.point for p in pts if p.kind == "cusp"][0]
        _, av = averaged_fold_curves("duffing-forced", vals, AXES, RANGES, (1, 2, 3), [0.3])
        err[mu] = [math.dist(true, [p.point for p in av if p.kind == "cusp"
                                    and p.detail["order"] == n][0]) for n in (1, 2, 3)]
    for n in (1, 2, 3):
        ratio = err[0.1][n - 1] / err[0.05][n - 1]
        assert 0.6 * 2**n < ratio < 1.6 * 2**n


@settings(max_examples=5, deadline=None)
@given(zeta=st.floats(0.02, 0.3), alpha=st.floats(0.2, 5.0))
@example(zeta=0.020000000000000004, alpha=5.0)
def test_averaged_cusp_closed_form_property(zeta, alpha):
    """Property (Nayfeh & Mook eq. 4.1.17): for every damping and hardening, the order-1
    averaged cusp is (sqrt(3) zeta, sqrt(256 zeta^3/(9 sqrt(3) alpha))).  The example: the
    smallest damping with the hardest spring, whose seeds' responses (a = 0.002..0.006) lay
    in the first cell of the fixed points' linear amplitude grid and were not found."""
    sc, hc = _cusp_closed_form(zeta, alpha)
    _, points = averaged_fold_curves("duffing-forced", {"mu": 0.1, "zeta": zeta, "alpha": alpha},
                                     AXES, {"sigma": (-1.0, 3.0), "h": (0.3 * hc, 3 * hc)},
                                     (1,), [2.5 * hc])
    cusps = [p.point for p in points if p.kind == "cusp"]
    assert len(cusps) == 1
    assert cusps[0] == pytest.approx((sc, hc), rel=1e-8)


def test_interruptible_turns_a_numba_ctrl_c_into_keyboard_interrupt():
    """Ctrl-C inside compiled code surfaces as a SystemError over the KeyboardInterrupt:
    the defining systems raise the interrupt itself (continue_curve keeps the path); any
    other SystemError is left as it is."""
    from numerics.bifurcation.twoway import interruptible

    def numba_like(kind):
        try:
            raise KeyboardInterrupt if kind == "ctrl-c" else ValueError("x")
        except BaseException:
            raise SystemError("returned a result with an exception set")

    with pytest.raises(KeyboardInterrupt):
        interruptible(numba_like)("ctrl-c")
    with pytest.raises(SystemError):
        interruptible(numba_like)("other")
    assert interruptible(lambda x: 2 * x)(3) == 6
