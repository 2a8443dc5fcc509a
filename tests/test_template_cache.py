"""The on-disk cache of the model templates' numerical functions (issue 39,
:mod:`numerics.flow.template_cache`): keyed by the model's canonical form and the
compilation's options; a warm run reads the functions back without lambdify; a damaged
record is rebuilt, never trusted; the same bytes of output from a cold and a warm cache."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from kbm.model.builtins import get_model
from kbm.symbols import xdot

from numerics.flow import template_cache as tc
from numerics.flow.template import ModelTemplate, _build_template
from numerics.flow.numba_cache import cache_dir

ROOT = Path(__file__).resolve().parents[1]


def _like(model, **changes):
    """``model`` built anew through the constructor with some arguments changed."""
    from kbm.model.builtins import Oscillator

    args = dict(name=model.name, F=model.F, omega0=model.omega0, description=model.description,
                physical=dict(model.physical), defaults=dict(model.defaults))
    return Oscillator(**{**args, **changes})


def test_the_key_changes_with_the_model_and_the_options():
    """vdp, rayleigh, vdp with another F, another omega0 and the compilation's options give
    five different keys; the same model built twice gives the same key (a pure function of
    the canonical form, no hash seed, no object identity)."""
    vdp = get_model("vdp")
    keys = {tc.template_key(vdp), tc.template_key(get_model("rayleigh")),
            tc.template_key(_like(vdp, F=vdp.F + xdot**3)),
            tc.template_key(_like(vdp, omega0=sp.Integer(2))),
            tc.template_key(vdp, options="another compilation")}
    assert len(keys) == 5
    assert tc.template_key(get_model("vdp")) == tc.template_key(vdp)


def _counting_build():
    built = []

    def build(model):
        built.append(model.name)
        return _build_template(model)
    return build, built


def test_a_warm_template_is_read_without_building(tmp_path, monkeypatch):
    """Cold: built and stored; warm: read back, never built.  Both evaluate to the same
    bytes as the lambdified template, and to the closed forms of van der Pol: the
    acceleration ``mu x'(1 - x^2) - x`` and the energy ``x'^2/2 + x^2/2`` (paper eq. 3 with
    ``F = (1 - x^2) x'``, no conservative part in F)."""
    monkeypatch.setenv("KBM_CACHE_DIR", str(tmp_path))
    vdp = get_model("vdp")
    build, built = _counting_build()
    cold = tc.cached_template(vdp, build, ModelTemplate)
    warm = tc.cached_template(vdp, build, ModelTemplate)
    assert built == ["vdp"]
    direct = _build_template(vdp)
    assert cold.names == warm.names == direct.names == ("mu",)
    rng = np.random.default_rng(39)
    for x, v, mu in rng.uniform(-3, 3, size=(20, 3)):
        exact = mu * v * (1 - x * x) - x
        vals = {f(0.0, x, v, mu) for f in (cold.f_acc, warm.f_acc, direct.f_acc)}
        assert len(vals) == 1 and abs(vals.pop() - exact) <= 1e-14 * (1 + abs(exact))
        y = [x, v, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0]
        assert cold.f_ext(0.0, y, mu) == warm.f_ext(0.0, y, mu) == direct.f_ext(0.0, y, mu)
        assert warm.f_energy(x, v, mu) == pytest.approx((v * v + x * x) / 2, rel=1e-15)
        assert np.array_equal(warm.f_jac(0.0, x, v, mu), direct.f_jac(0.0, x, v, mu))
    assert warm.ext_exprs == direct.ext_exprs
    assert warm.dissipation_expr == direct.dissipation_expr


@pytest.mark.parametrize("damage", ["garbage", "another key", "unknown global",
                                    "bad source"])
def test_a_damaged_record_is_rebuilt(tmp_path, monkeypatch, damage):
    """A record that is not JSON, names another key, names a global that does not resolve,
    or holds source that does not compile is rebuilt and replaced, never used."""
    monkeypatch.setenv("KBM_CACHE_DIR", str(tmp_path))
    vdp = get_model("vdp")
    key = tc.template_key(vdp)
    tc.cached_template(vdp, _build_template, ModelTemplate)
    path = tmp_path / f"kbm_template_{key}.json"
    good = path.read_text()
    record = json.loads(good)
    if damage == "garbage":
        path.write_text("{not json")
    else:
        if damage == "another key":
            record["key"] = "0" * 32
        elif damage == "unknown global":
            record["functions"]["f_acc"]["globals"]["x"] = ["math", "no_such_function"]
        else:
            record["functions"]["f_acc"]["source"] = "def broken(:\n"
        path.write_text(json.dumps(record))
    build, built = _counting_build()
    tpl = tc.cached_template(vdp, build, ModelTemplate)
    assert built == ["vdp"]
    assert tpl.f_acc(0.0, 1.5, 0.5, 1.0) == 1.0 * 0.5 * (1 - 1.5**2) - 1.5
    assert json.loads(path.read_text()) == json.loads(good)


def test_the_coupled_names_are_the_catalogue():
    """:func:`kbm.cli.derive.is_coupled` reads a list of names (no sympy); it is the
    catalogue's."""
    from kbm.cli.derive import COUPLED_NAMES
    from kbm.model.coupled_builtins import COUPLED_MODELS

    assert COUPLED_NAMES == frozenset(COUPLED_MODELS)


def _cycle(env) -> subprocess.CompletedProcess:
    code = ("import sys, runpy; sys.argv = ['kbm', 'cycle', 'vdp', '-p', 'mu=1']\n"
            "try:\n    runpy.run_module('numerics.cli', run_name='__main__')\n"
            "finally:\n    print('MODULES', *sorted(m for m in ('scipy.special', "
            "'scipy.integrate', 'scipy.optimize', 'kbm.model.coupled_builtins') "
            "if m in sys.modules), "
            "file=sys.stderr)")
    return subprocess.run([sys.executable, "-c", code], capture_output=True, cwd=ROOT,
                          env=env, timeout=600, check=True)


def test_cycle_gives_the_same_bytes_with_a_cold_and_a_warm_template_cache(tmp_path):
    """``kbm cycle vdp -p mu=1`` with no template record (built and stored) and again with
    it (read back): the same bytes of output; the warm run imports no ``scipy.integrate``,
    ``scipy.special`` or ``scipy.optimize`` (the KBM guess's rates are a record too,
    :mod:`numerics.cycles.guess`) and not the coupled catalogue.  The compiled flows
    are copied from the cache in use, so that only the template is cold."""
    env = {**os.environ, "PYTHONPATH": str(ROOT), "KBM_COMPILE_NOTICE": "0"}
    _cycle(env)  # the flows compiled in the cache in use (once per machine)
    src = cache_dir()
    for p in src.iterdir():
        if p.name.startswith(("kbm_flow_", "kbm_src_")) or p.name == "__pycache__":
            (shutil.copytree if p.is_dir() else shutil.copy2)(p, tmp_path / p.name)
    env["KBM_CACHE_DIR"] = str(tmp_path)
    cold = _cycle(env)
    assert list(tmp_path.glob("kbm_template_*.json"))
    assert list(tmp_path.glob("kbm_rates_*.json"))
    warm = _cycle(env)
    assert cold.stdout == warm.stdout
    assert b"limit cycle of vdp" in warm.stdout
    modules = warm.stderr.decode().splitlines()[-1].split()
    # the coupled catalogue is not read (kbm.model.coupled is: the one model type lives there)
    assert "scipy.integrate" not in modules and "kbm.model.coupled_builtins" not in modules
    assert "scipy.special" not in modules and "scipy.optimize" not in modules


@pytest.mark.parametrize("name", ["vdp", "duffing", "linear_stiffness", "sedf", "cdc",
                                  "sedf_comoving"])
def test_the_energy_without_mpmath_is_mpmaths_to_the_last_bit(name, monkeypatch):
    """The energy ``v^2/2 + U(x)`` of a built-in model printed with float rationals
    (:func:`numerics.flow.template_cache.lambdify_light`: ``1/2`` where lambdify's mpmath
    printer writes ``mpf(1)/mpf(2)``) needs no mpmath and gives the mpmath-printed
    function's values bit for bit (both round each operation to nearest at 53 bits, IEEE
    754), on random scalars and arrays; SEDF's is paper eq. 3's potential
    ``Omega^2 x^2/2 + delta mu (1 - cos k x)/k``."""
    import inspect

    model = get_model(name)
    light = _build_template(model).f_energy
    monkeypatch.setattr(tc, "lambdify_light",
                        lambda args, expr, modules: sp.lambdify(args, expr, modules=modules))
    printed = _build_template(model).f_energy
    assert "mpf" not in inspect.getsource(light) and "mpf" in inspect.getsource(printed)
    assert "mpmath" not in json.dumps(tc.function_record(light)["globals"])
    rng = np.random.default_rng(7)
    n = len(_build_template(model).names)
    for _ in range(50):
        p = [float(v) for v in rng.uniform(0.05, 3.0, n)]
        xs, vs = rng.uniform(-4, 4, 9), rng.uniform(-4, 4, 9)
        a = np.asarray(light(xs, vs, *p), dtype=float)
        assert a.tobytes() == np.asarray(printed(xs, vs, *p), dtype=float).tobytes()
        x0, v0 = float(xs[0]), float(vs[0])
        assert float(light(x0, v0, *p)) == float(printed(x0, v0, *p))
    if name == "sedf":
        names = _build_template(model).names
        vals = dict(zip(names, p))
        ref = (vals["Omega"] ** 2 * x0 ** 2 / 2 + v0 ** 2 / 2
               + vals["delta"] * vals["mu"] * (1 - np.cos(vals["k"] * x0)) / vals["k"])
        assert float(light(x0, v0, *p)) == pytest.approx(ref, rel=1e-13, abs=1e-13)


def test_an_energy_that_needs_mpmath_keeps_lambdifys_printing():
    """A hypergeometric term (mpmath's ``hyper``) keeps mpmath's numbers throughout, and a
    power with a fractional exponent keeps ``mpf`` in its exponent (mpmath's power)."""
    import inspect

    x, y = sp.symbols("x y")
    hyper = x * sp.hyper((sp.Rational(1, 2),), (1, sp.Rational(3, 2)), -x**2 / 4) / 10
    fn = tc.lambdify_light((x, y), hyper, ["numpy", "scipy", "mpmath"])
    assert inspect.getsource(fn) == inspect.getsource(
        sp.lambdify((x, y), hyper, modules=["numpy", "scipy", "mpmath"]))
    root = tc.lambdify_light((x, y), (1 + x)**sp.Rational(1, 3) + y / 2,
                             ["numpy", "scipy", "mpmath"])
    assert "mpf(1)/mpf(3)" in inspect.getsource(root)
    assert float(root(7.0, 1.0)) == pytest.approx(2.5, rel=1e-15)
