"""The compiled flows built ahead of time (issue 39, :mod:`numerics.flow.aot`): the same
numbers as numba's just-in-time code to the last bit, a module that does not load is not
used, and ``KBM_AOT=0`` turns them off."""

from __future__ import annotations

import numpy as np
import pytest

from numerics._memo import clear_caches
from numerics.flow import aot, compile_model, jit_available
from numerics.flow.template import template_flow
from numerics.flow.numba_cache import _load, cache_dir

pytestmark = pytest.mark.skipif(not jit_available(), reason="numba not installed")


def _flows(monkeypatch, model, params, make=template_flow, exports=None):
    """The just-in-time flow and the ahead-of-time one of ``model`` made by ``make`` (built
    in the cache in use if it is not there yet, once per machine); with ``exports``, the
    functions the module must export."""
    cm = compile_model(model, params)
    monkeypatch.setenv("KBM_AOT", "0")
    clear_caches()
    jit = make(cm.template)
    monkeypatch.setenv("KBM_AOT", "1")
    text = open(jit.module.__file__).read()
    if exports is not None:
        assert set(aot.exports(text)) == exports
    if aot.load(cache_dir(), text) is None:
        assert aot.build(cache_dir(), text, _load(text))
    clear_caches()
    built = make(cm.template)
    clear_caches()
    return cm, jit, built


@pytest.mark.parametrize("model, params", [("vdp", {"mu": 1}),
                                           ("sedf", {"mu": 0.1, "Delta": 1.5, "beta": 1,
                                                     "lam": 1})])
def test_ahead_of_time_equals_just_in_time_to_the_last_bit(monkeypatch, model, params):
    """The extended flow (state, variational equations, Liouville and dissipation
    integrals), the turn of ``x'`` and the crossing of a section ``x = xsec`` from the
    extension and from numba's code: equal arrays, statuses and step counts (the same
    source, the same LLVM, no fast-math)."""
    cm, jit, built = _flows(monkeypatch, model, params)
    assert built.module.__name__.startswith("kbm_aot_")
    assert not jit.module.__name__.startswith("kbm_aot_")
    for x0, t_end, rtol, n_out in [(2.0, 6.7, 1e-12, 1), (0.5, 30.0, 1e-8, 7),
                                   (1.2, 3.0, 1e-10, 64)]:
        y0 = [x0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0]
        a = jit(y0, t_end, cm.pvec, rtol, rtol, n_out)
        b = built(y0, t_end, cm.pvec, rtol, rtol, n_out)
        assert a.status == b.status and a.steps == b.steps
        np.testing.assert_array_equal(a.y, b.y)
        assert a.y.tobytes() == b.y.tobytes()
        assert jit.to_turn(y0, 1.0, 50.0, cm.pvec, rtol, rtol) == \
            built.to_turn(y0, 1.0, 50.0, cm.pvec, rtol, rtol)
        for sign in (1.0, -1.0):
            assert jit.to_section(y0, sign, 0.3 * x0, 50.0, cm.pvec, rtol, rtol) == \
                built.to_section(y0, sign, 0.3 * x0, 50.0, cm.pvec, rtol, rtol)
    # the transient integrates the state alone: two of the nine states
    a, b = jit([1.0, 0.0], 20.0, cm.pvec, 1e-10, 1e-10, 5), built([1.0, 0.0], 20.0, cm.pvec,
                                                                  1e-10, 1e-10, 5)
    assert a.y.tobytes() == b.y.tobytes() and a.steps == b.steps


def test_a_module_that_does_not_load_is_not_used(tmp_path, monkeypatch):
    monkeypatch.setenv("KBM_AOT", "1")
    source = "# a source\n"
    name = aot.module_name(source)
    aot._path(tmp_path, name).write_bytes(b"not an extension module")
    assert aot.load(tmp_path, source) is None


def test_kbm_aot_0_turns_them_off(tmp_path, monkeypatch):
    monkeypatch.setenv("KBM_AOT", "0")
    assert not aot.enabled()
    assert aot.load(tmp_path, "# a source\n") is None
    assert aot.build(tmp_path, "# a source\n", None) is False


def test_the_name_changes_with_the_source():
    assert aot.module_name("a\n") != aot.module_name("b\n")
    assert aot.module_name("a\n") == aot.module_name("a\n")


def test_a_failed_build_is_noted_and_not_tried_again(tmp_path, monkeypatch):
    """A build that fails (here: no module to compile) leaves ``NAME.failed`` in the folder,
    and the next process does not try again (a build takes seconds)."""
    monkeypatch.setenv("KBM_AOT", "1")
    source = "# a source that was never compiled\n"
    assert aot.build(tmp_path, source, None) is False
    failed = tmp_path / f"{aot.module_name(source)}.failed"
    assert failed.exists() and "Error" in failed.read_text()
    assert aot.build(tmp_path, source, None) is False
    assert not list(tmp_path.glob("kbm_aot_*.so")) and not list(tmp_path.glob(".kbm_aot_*"))


def _correctors(monkeypatch, model, params):
    """The nine-state flow with its Newton corrector (``extra`` source) of ``model``, from
    numba's just-in-time code and from the module built ahead of time (built in the cache
    in use if it is not there yet, once per machine)."""
    from numerics.flow.sensitivity import sensitivity_flow

    return _flows(monkeypatch, model, params, sensitivity_flow,
                  {"flow", "to_turn", "to_section", "shoot_correct", "accelerations"})


@pytest.mark.parametrize("model, params, vary, rates", [
    ("vdp", {"mu": 1}, "mu", [1.0]),
    # Delta moves delta = Delta/mu at the rate 1/mu (the template's order: Omega, beta,
    # delta, k, mu)
    ("sedf", {"mu": 0.1, "Delta": 1.5, "beta": 1, "lam": 1}, "Delta",
     [0.0, 0.0, 10.0, 0.0, 0.0])])
def test_ahead_of_time_corrector_equals_just_in_time_to_the_last_bit(monkeypatch, model,
                                                                     params, vary, rates):
    """The continuation's compiled Newton corrector (``shoot_correct`` of
    ``numerics/flow/_shooting_corrector.py``, Newton's method on the shooting problem of a
    cycle with the parameter, Seydel, *Practical Bifurcation and Stability Analysis*,
    sec. 7.3) from the extension and from numba's code: the same status, iterations,
    corrected unknowns, residual, Jacobian and samples, byte for byte, converging (whole
    and half period) and refusing a start too far off; and the same ``accelerations``."""
    from numerics.cycles import limit_cycle
    from numerics.shooting import acceptance

    cm, jit, built = _correctors(monkeypatch, model, params)
    assert built.module.__name__.startswith("kbm_aot_")
    assert not jit.module.__name__.startswith("kbm_aot_")
    cyc = limit_cycle(model, params)
    p = float(params[vary])
    pbase, rates = np.asarray(cm.pvec, dtype=float), np.asarray(rates)
    starts = [((1.01, 0.99, 1.0), False, 1e-10), ((0.999, 1.002, 1.0), True, 1e-9),
              ((1.01, 0.99, 1.0), False, 1e-12), ((3.0, 0.3, 1.0), False, 1e-10)]
    statuses = set()
    for (fx, ft, fp), half, rtol in starts:
        u0 = np.array([fx * cyc.amplitude_max, ft * cyc.period, fp * p])
        row, target = np.array([0.0, 0.0, 1.0]), p  # the parameter fixed: a cycle at p
        scale = max(1.0, u0[0])  # the standard's numbers at the start's scale
        args = (row, target, pbase, rates, p, half, rtol, 32, 10**6, 8,
                acceptance.residual_tolerance(rtol, scale),
                acceptance.correction_tolerance(rtol, scale),
                rtol * max(scale, u0[1], abs(u0[2])), acceptance.TRIVIAL_TOL,
                acceptance.NOISE_RTOL)
        a = jit.module.shoot_correct(u0.copy(), *args)
        b = built.module.shoot_correct(u0.copy(), *args)
        assert a[:2] == b[:2] and a[7] == b[7]
        for x, y in zip(a[2:7], b[2:7]):
            assert x.shape == y.shape and x.tobytes() == y.tobytes()
        statuses.add(int(a[0]))
    assert 0 in statuses and len(statuses) > 1  # converged, and refused the far start
    xs = np.linspace(-2.0, 2.0, 41)
    assert jit.module.accelerations(xs, pbase).tobytes() == \
        built.module.accelerations(xs, pbase).tobytes()
    # the flow of the nine states itself
    y0 = [cyc.amplitude_max, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0]
    pv = np.concatenate([pbase, rates])
    ra, rb = jit(y0, cyc.period, pv, 1e-10, 1e-10, 16), built(y0, cyc.period, pv, 1e-10, 1e-10, 16)
    assert ra.y.tobytes() == rb.y.tobytes() and ra.steps == rb.steps
