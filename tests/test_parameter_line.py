"""A model bound along one parameter (kbm.parameters.bound.ParameterLine,
numerics.flow.CompiledLine) against binding from scratch (kbm.parameters.bound.bind,
numerics.flow.compile_model), and the keyed source of a compiled flow against the source printed
from its expressions.

The continuation of cycles binds its model thousands of times along the varied parameter;
the line is a faster route to the same object, so the reference is the slow route itself:
the same exact values, in the same order, and the same floats.
"""

from __future__ import annotations

import pytest
import sympy as sp
from hypothesis import given, settings, strategies as st

from kbm.parameters.bound import ParameterLine, bind
from kbm.errors import ParameterError
from numerics.flow import CompiledLine, compile_model, model_template

SEDF = {"mu": 0.1, "beta": 1, "lam": 1, "Delta": 2}

CASES = [
    ("sedf", {"mu": 0.1, "beta": 1, "lam": 1}, "Delta"),   # physical name -> delta
    ("sedf", SEDF, "mu"),                                  # mu, with delta = Delta/mu
    ("sedf", SEDF, "beta"),                                # a scaled parameter
    ("sedf", SEDF, "lam"),                                 # k = 2 pi/lam, exact
    ("sedf", {"mu": 0.1, "beta": 1, "lam": 1, "delta": 2}, "mu"),  # scaled delta stays
    ("sedf", SEDF, "v"),                                   # the model itself changes
    ("vdp", {"mu": 0.1}, "mu"),
    ("cdc", {"mu": 0.1, "lam": 1, "Delta": 2}, "Delta"),
]


@settings(max_examples=40, deadline=None)
@given(case=st.sampled_from(CASES), value=st.floats(0.05, 4.0))
def test_line_equals_bind(case, value):
    model, params, vary = case
    line = ParameterLine(model, params, vary, 1.0)
    a, b = line(value), bind(model, {**params, vary: value})
    assert a == b
    assert list(a.values.items()) == list(b.values.items())  # the same order: same bytes
    assert hash(a) == hash(b)


@pytest.mark.parametrize("case", CASES)
def test_compiled_line_equals_compile_model(case):
    model, params, vary = case
    line = CompiledLine(model, params, vary, 1.0)
    for value in (0.3, 1.7, 3.1):
        a, b = line(value), compile_model(model, {**params, vary: value})
        assert a.pvec == b.pvec and a.values == b.values and a.omega0 == b.omega0
        assert a.bound == b.bound and a.autonomous == b.autonomous
        assert a.acc(0.0, 0.3, -0.2) == b.acc(0.0, 0.3, -0.2)


def test_line_refuses_what_bind_refuses():
    line = ParameterLine("sedf", {"beta": 1, "lam": 1, "Delta": 2}, "mu", 0.1)
    with pytest.raises(ParameterError, match="undefined"):
        line(0.0)  # delta = Delta/mu
    with pytest.raises(ParameterError):
        bind("sedf", {"beta": 1, "lam": 1, "Delta": 2, "mu": 0.0})
    with pytest.raises(ParameterError, match="finite"):
        ParameterLine("vdp", {"mu": 0.1}, "mu", 0.1)(float("nan"))


def test_keyed_source_is_the_printed_source(tmp_path, monkeypatch):
    """The source kept under a key is byte-equal to the one printed from the expressions,
    and a second process-like call reads it back without printing (exprs not called)."""
    pytest.importorskip("numba")
    from numerics.flow import jit as jit_mod

    monkeypatch.setenv("KBM_CACHE_DIR", str(tmp_path))
    tpl = model_template("vdp")
    names = [sp.Symbol(n) for n in tpl.names]
    printed = jit_mod._source_by_key(None, tpl.ext_exprs, sp.Symbol("t"), tpl.ext_symbols,
                                     names, 2)
    key = "test|" + sp.srepr(tuple(tpl.ext_exprs))
    first = jit_mod._source_by_key(key, lambda: tpl.ext_exprs, sp.Symbol("t"),
                                   tpl.ext_symbols, names, 2)

    def fail():
        raise AssertionError("the keyed source was printed again")

    again = jit_mod._source_by_key(key, fail, sp.Symbol("t"), tpl.ext_symbols, names, 2)
    assert printed == first == again
    assert len(list(tmp_path.glob("kbm_src_*.txt"))) == 1


@pytest.mark.parametrize("name, params, vary", [
    ("coupled-vdp", {"mu": 0.1, "c": 0.3, "sigma": 0.2}, "c"),
    ("duffing-1-3", {"mu": 0.02, "h": 2, "sigma": 0.5}, "sigma"),
    ("duffing-forced", {"mu": 1, "zeta": 0.05, "alpha": 1, "h": 20, "sigma": 1}, "mu")])
def test_coupled_flow_at_equals_a_new_binding(name, params, vary):
    """CoupledFlow.at (the continuation of coupled orbits moves one value of one
    compilation) against coupled_flow from scratch: the same values, parameter vector and
    field."""
    import numpy as np

    from numerics.flow.coupled_flow import coupled_flow

    base = coupled_flow(name, params)
    for value in (0.07, 0.9):
        a, b = base.at(**{vary: value}), coupled_flow(name, {**params, vary: value})
        assert dict(a.values) == dict(b.values) and np.array_equal(a._p, b._p)
        y = np.linspace(0.3, 1.2, 2 * a.dof)
        assert np.array_equal(a.rhs(y, 0.4), b.rhs(y, 0.4))
    with pytest.raises(ParameterError, match="not among the values"):
        base.at(Delta=1.0)


SPLIT_CASES = [
    ("sedf", {"mu": 0.1, "beta": 1, "lam": 1}, "Delta"),   # delta = Delta/mu symbolic
    ("sedf", {"mu": 0.1, "lam": 1, "Delta": 2}, "beta"),   # in h only
    ("sedf", {"mu": 0.1, "beta": 1, "Delta": 2}, "lam"),   # inside sin(k x): piecewise G?
    ("sedf", {"beta": 1, "lam": 1, "Delta": 2}, "mu"),     # mu: split from scratch
    ("cdc", {"mu": 0.1, "lam": 1}, "Delta"),
]


@pytest.mark.parametrize("case", SPLIT_CASES)
def test_split_line_equals_split_conservative(case):
    """kbm.model.conservative.SplitLine (the energy branch splits once along the parameter)
    against split_conservative at each value: the same g, h, G, values and functions."""
    import numpy as np

    from kbm.model.conservative import SplitLine, split_conservative

    model, params, vary = case
    line = SplitLine(model, params, vary, 0.5)
    z = np.linspace(-3.0, 3.0, 13)
    for value in (0.3, 1.7, 3.1):
        a, b = line(value), split_conservative(model, {**params, vary: value})
        assert (a.g, a.h, a.G, a.mu, dict(a.params)) == (b.g, b.h, b.G, b.mu, dict(b.params))
        for fa, fb in zip(a.numpy_functions()[:3], b.numpy_functions()[:3]):
            assert np.allclose(fa(z), fb(z), rtol=1e-13, atol=1e-13)
        assert np.allclose(a.numpy_functions()[3](z, 0.7), b.numpy_functions()[3](z, 0.7),
                           rtol=1e-13, atol=1e-13)
        assert np.allclose(a.h_velocity_function()(z, 0.7), b.h_velocity_function()(z, 0.7),
                           rtol=1e-13, atol=1e-13)
        ga, Ga = a.scalar_functions()
        gb, Gb = b.scalar_functions()
        assert all(abs(ga(v) - gb(v)) < 1e-12 and abs(Ga(v) - Gb(v)) < 1e-12 for v in z)


def test_split_line_refuses_what_split_conservative_refuses():
    """A potential that stops confining along the line is refused at that value, as from
    scratch (NotConfiningError)."""
    from kbm import custom_model
    from kbm.model.conservative import NotConfiningError, SplitLine, split_conservative

    model = custom_model("-c*x + (1 - x**2)*xdot", name="softening-c")
    line = SplitLine(model, {"mu": 0.1}, "c", 0.5)
    line(5.0)  # g = (1 + mu c) x: confining for c > -10
    for bad in (-20.0, -30.0):
        with pytest.raises(NotConfiningError):
            split_conservative(model, {"mu": 0.1, "c": bad})
        with pytest.raises(NotConfiningError):
            line(bad)


@pytest.mark.slow  # 3-4 s; kept out of the default run (five-minute rule)
def test_energy_branch_with_the_split_line_equals_splitting_each_value(monkeypatch):
    """numerics.comparison.energy_branch splits the model once along the parameter
    (SplitLine); against splitting at every value (split_conservative, the line disabled)
    the predicted cycles of the SEDF's energy balance (paper eq. 3) agree to rounding."""
    import numpy as np

    import kbm.model.conservative as cons
    from kbm.errors import KBMError
    from numerics.comparison.branches import energy_branch

    params = {"mu": 0.1, "beta": 1, "lam": 1}
    fast = energy_branch("sedf", params, "Delta", (0.5, 3.5), n=12)

    class Refused(cons.SplitLine):
        def __init__(self, *args, **kwargs):
            raise KBMError("no line")

    monkeypatch.setattr(cons, "SplitLine", Refused)
    slow = energy_branch("sedf", params, "Delta", (0.5, 3.5), n=12)
    assert len(fast.points) == len(slow.points) > 0
    assert np.allclose(np.array(fast.points, float), np.array(slow.points, float),
                       rtol=1e-11, atol=1e-12)
