"""The cache of compiled flows (issue 39): keyed by the model's canonical form and the
compilation's options; a warm run reads the printed source back (no sympy printing) and
integrates to the same numbers as the cold run; the first-run notice follows numba's own
compile events."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from kbm.symbols import t as T

from numerics.flow.jit import _source_by_key, flow_cache_key, jit_available, jit_flow
from numerics.flow.numba_cache import compile_notice
from numerics.flow.template import model_template

ROOT = Path(__file__).resolve().parents[1]
X, V = sp.symbols("y0 y1")
OMEGA = sp.Symbol("omega")


def _key(name: str) -> str:
    tpl = model_template(name)
    return f"extended|{sp.srepr(tuple(tpl.ext_exprs))}|{tpl.names}"


def test_the_key_changes_with_the_model_and_the_options():
    """Two models, the same model with the other states integrated alone (``n_state``) or
    another source compiled with it (``extra``): four different names; the same inputs
    give the same name (a pure function of its inputs, no hash seed)."""
    vdp, rayleigh = _key("vdp"), _key("rayleigh")
    names = {flow_cache_key(vdp), flow_cache_key(rayleigh), flow_cache_key(vdp, n_state=9),
             flow_cache_key(vdp, extra="def f():\n    pass\n")}
    assert len(names) == 4
    assert flow_cache_key(vdp) == flow_cache_key(_key("vdp"))


def test_a_warm_run_reads_the_source_without_printing(tmp_path, monkeypatch):
    """Cold: the expressions are built and printed; warm (a fresh cache of the process,
    the same folder): the source is read back, the expressions are never built, and the
    text is the same."""
    monkeypatch.setenv("KBM_CACHE_DIR", str(tmp_path))
    built = []

    def exprs():
        built.append(1)
        return [V, -OMEGA**2 * X]

    key = "harmonic oscillator x'' = -omega^2 x"
    cold = _source_by_key(key, exprs, T, [X, V], [OMEGA], 2)
    warm = _source_by_key(key, exprs, T, [X, V], [OMEGA], 2)
    assert built == [1]
    assert warm == cold
    assert (tmp_path / f"kbm_src_{flow_cache_key(key)}.txt").read_text() == cold


@pytest.mark.slow  # a compilation in a fresh cache: ~10-25 s
@pytest.mark.skipif(not jit_available(), reason="numba not installed")
def test_warm_and_cold_flows_give_the_same_numbers_as_the_closed_form(tmp_path, monkeypatch):
    """The harmonic oscillator ``x'' = -omega^2 x`` from ``(1, 0)``: ``x = cos(omega t)``
    (the closed form), the same bytes from the flow built from the expressions and from the
    source read back under its key."""
    monkeypatch.setenv("KBM_CACHE_DIR", str(tmp_path))
    key = "harmonic oscillator x'' = -omega^2 x (warm and cold)"
    cold = jit_flow([V, -OMEGA**2 * X], T, [X, V], [OMEGA], key=key)
    warm = jit_flow(lambda: pytest.fail("the warm run built the expressions"), T, [X, V],
                    [OMEGA], key=key)
    args = ([1.0, 0.0], 3.0, [1.7], 1e-12, 1e-12, 6)
    a, b = cold(*args).y, warm(*args).y
    assert np.array_equal(a, b)
    t = np.linspace(0, 3.0, 7)
    np.testing.assert_allclose(a[:, 0], np.cos(1.7 * t), atol=1e-10)


def test_the_notice_shows_when_numba_compiles_and_not_when_it_has_the_code(capsys,
                                                                           monkeypatch):
    """A function of a module with a notice: the first compilation prints the notice once
    (on standard error, here not a terminal: ``KBM_COMPILE_NOTICE=1``); another
    compilation of the same module and a call of compiled code print nothing; with
    ``KBM_COMPILE_NOTICE=0``, a new module's compilation prints nothing either."""
    numba = pytest.importorskip("numba")
    monkeypatch.setenv("KBM_COMPILE_NOTICE", "1")
    name = "kbm_flow_test_notice"
    namespace = {"__name__": name}
    exec("def f(x):\n    return 2 * x\n\ndef g(x):\n    return 3 * x\n", namespace)
    compile_notice(name, "the test's functions", 7)
    f, g = numba.njit(namespace["f"]), numba.njit(namespace["g"])
    assert f(2.0) == 4.0
    first = capsys.readouterr()
    assert first.out == ""
    assert first.err == ("kbm: compiling the test's functions with numba (first run; about "
                         f"7 s on two cores, then cached in {_cache()})\n")
    assert f(3.0) == 6.0 and g(1.0) == 3.0
    assert capsys.readouterr().err == ""
    monkeypatch.setenv("KBM_COMPILE_NOTICE", "0")
    other = {"__name__": "kbm_flow_test_notice_off"}
    exec("def h(x):\n    return 4 * x\n", other)
    compile_notice(other["__name__"], "nothing", 1)
    assert numba.njit(other["h"])(1.0) == 4.0
    assert capsys.readouterr().err == ""


def _cache():
    from numerics.flow.numba_cache import cache_dir

    return cache_dir()


def test_the_stepper_reads_scipys_dop853_tableau_without_scipy_integrate():
    """The compiled stepper's Butcher tableau is scipy's ``dop853_coefficients`` value for
    value (Hairer, Norsett and Wanner, sec. II.10: the method of ``solve_ivp(method=
    "DOP853")``), read without importing :mod:`scipy.integrate` (half a second, issue 39)."""
    code = ("import sys; from numerics.flow._dop853_tableau import dop853_coefficients as f; "
            "m = f(); print('scipy.integrate' in sys.modules, m.N_STAGES, m.A.shape)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, cwd=ROOT).stdout.split(maxsplit=1)
    assert out[0] == "False"
    from scipy.integrate._ivp import dop853_coefficients as scipy_dc

    from numerics.flow._dop853_tableau import dop853_coefficients

    ours = dop853_coefficients()
    assert out[1].strip() == f"{scipy_dc.N_STAGES} {scipy_dc.A.shape}"
    for name in ("N_STAGES", "A", "B", "C", "E3", "E5", "D"):
        assert np.array_equal(getattr(ours, name), getattr(scipy_dc, name)), name


def test_a_cached_source_with_another_stepper_is_printed_anew(tmp_path, monkeypatch):
    """A source cached under the key by an older stepper (the key names the model and the
    options, not the stepper's text) is not reused: the expressions are printed again and
    the stepper of this version is compiled."""
    monkeypatch.setenv("KBM_CACHE_DIR", str(tmp_path))
    key = "harmonic oscillator x'' = -omega^2 x (old stepper)"
    path = tmp_path / f"kbm_src_{flow_cache_key(key)}.txt"
    cold = _source_by_key(key, [V, -OMEGA**2 * X], T, [X, V], [OMEGA], 2)
    path.write_text(cold.replace("dop853_coefficients()", "old_tableau()"))
    again = _source_by_key(key, [V, -OMEGA**2 * X], T, [X, V], [OMEGA], 2)
    assert again == cold
    assert path.read_text() == cold


def _cycle_json(cache: Path) -> tuple[str, str]:
    """``kbm cycle vdp -p mu=1 --json`` in a new process with the cache folder ``cache``:
    its standard output and the heavy modules it imported."""
    code = ("import sys, runpy; sys.argv = ['kbm', 'cycle', 'vdp', '-p', 'mu=1', '--json']\n"
            "try:\n    runpy.run_module('numerics.cli', run_name='__main__')\n"
            "except SystemExit:\n    pass\n"
            "print('MODULES', ' '.join(m for m in ('scipy.integrate', 'numerics.energy', "
            "'numerics.cycles.continuation', 'numerics.cycles.sweep') if m in sys.modules))")
    env = {**os.environ, "KBM_CACHE_DIR": str(cache), "KBM_COMPILE_NOTICE": "0",
           "PYTHONPATH": str(ROOT)}
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, cwd=ROOT, env=env, timeout=900).stdout
    body, _, modules = out.rpartition("MODULES")
    return body, modules.strip()


@pytest.mark.slow  # two compilations in a fresh cache: ~20-60 s
@pytest.mark.skipif(not jit_available(), reason="numba not installed")
def test_warm_cycle_command_gives_the_cold_runs_bytes(tmp_path):
    """``kbm cycle vdp -p mu=1 --json`` cold (a new cache folder: printed and compiled) and
    warm (read back): the same bytes; the van der Pol period at ``mu = 1`` is 6.6632868593
    (Urabe's value, Mathematical Methods of Nonlinear Oscillations); the compiled path
    imports neither scipy's integrators nor the energy balance, the continuation or the
    sweeps (issue 39)."""
    cold, cold_modules = _cycle_json(tmp_path)
    warm, warm_modules = _cycle_json(tmp_path)
    assert warm == cold
    assert abs(json.loads(cold)["period"] - 6.6632868593) < 1e-9
    assert cold_modules == warm_modules == ""
