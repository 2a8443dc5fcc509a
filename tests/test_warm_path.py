"""The warm path of ``kbm cycle`` (issue 39): the first-order KBM guess from the template
cache's record (:mod:`numerics.cycles.guess`), its roots by a port of Brent's method that
gives scipy's floats to the last bit, and a warm run that imports none of
``scipy.optimize``, ``scipy.special``, ``scipy.integrate``."""

from __future__ import annotations

import json
import math
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from numerics.cycles import guess

ROOT = Path(__file__).resolve().parents[1]

#: scipy's modules the warm path of ``kbm cycle`` must not import (numba itself imports
#: ``scipy`` and ``scipy.linalg``, for its ``np.linalg`` support)
SCIPY_PARTS = ("scipy.optimize", "scipy.special", "scipy.integrate")


@given(st.lists(st.floats(-3, 3), min_size=2, max_size=6),
       st.floats(-2.5, 0.0), st.floats(0.01, 2.5),
       st.sampled_from([(2e-12, 8.881784197001252e-16), (1e-15, 1e-14), (1e-6, 1e-10)]))
def test_brentq_is_scipys_brentq_to_the_last_bit(coefs, a, b, tols):
    """Brent's method (Brent 1973, ch. 4) as :func:`scipy.optimize.brentq` runs it: on a
    polynomial with a sign change in ``[a, b]`` the same root, bit for bit (a second
    implementation of the same steps)."""
    from scipy.optimize import brentq

    def f(x):
        return float(np.polyval(coefs, x))

    if not f(a) * f(b) < 0:
        return
    assert guess.brentq(f, a, b, *tols) == brentq(f, a, b, xtol=tols[0], rtol=tols[1])


def test_brentq_refuses_a_bracket_without_a_sign_change():
    with pytest.raises(ValueError, match="different signs"):
        guess.brentq(lambda x: x * x + 1.0, -1.0, 1.0)


def test_brentq_finds_sqrt2_to_the_tolerance():
    """The positive root of ``x^2 - 2`` (exact: sqrt 2) to ``xtol``."""
    assert abs(guess.brentq(lambda x: x * x - 2.0, 0.0, 2.0, 1e-15, 1e-14) - math.sqrt(2)) \
        < 1e-14


@pytest.mark.parametrize("name, params", [("vdp", {"mu": 1}), ("rayleigh", {"mu": 0.5})])
def test_guess_equals_the_averaged_cycles_of_kbm(name, params, tmp_path, monkeypatch):
    """The guess from the stored rates (cold: built, stored, read back; warm: read) is the
    stable first-order cycle of :meth:`kbm.AveragedRates.cycles` (scipy's brentq) to the
    last bit; van der Pol's first-order amplitude is 2 (the textbook result, Nayfeh and
    Mook, *Nonlinear Oscillations*, sec. 3.3)."""
    from kbm import averaged_rates, derive
    from kbm.bound import bind

    from numerics._memo import clear_caches

    monkeypatch.setenv("KBM_CACHE_DIR", str(tmp_path))
    clear_caches()
    bound = bind(name, params)
    cold = guess.kbm_guess(bound)
    assert len(list(tmp_path.glob("kbm_rates_*.json"))) == 1
    clear_caches()
    warm = guess.kbm_guess(bound)
    rates = averaged_rates(derive(bound.model, 1))
    c = max((c for c in rates.cycles({k: bound.values[k] for k in ("mu", *rates.params)})
             if c.stable), key=lambda c: c.amplitude)
    assert cold == warm == (c.amplitude, c.period)
    if name == "vdp":
        assert abs(cold[0] - 2.0) < 1e-12 and abs(cold[1] - 2 * math.pi) < 1e-12
    clear_caches()


def test_a_damaged_rates_record_is_rebuilt(tmp_path, monkeypatch):
    from kbm.bound import bind

    from numerics._memo import clear_caches

    monkeypatch.setenv("KBM_CACHE_DIR", str(tmp_path))
    clear_caches()
    bound = bind("vdp", {"mu": 1})
    good = guess.kbm_guess(bound)
    path, = tmp_path.glob("kbm_rates_*.json")
    record = json.loads(path.read_text())
    record["functions"]["rate"]["globals"]["sin"] = ["math", "no_such_function"]
    record["functions"]["rate"]["source"] = "def _lambdifygenerated(:\n"
    path.write_text(json.dumps(record))
    clear_caches()
    assert guess.kbm_guess(bound) == good
    assert json.loads(path.read_text())["functions"]["rate"]["source"] != \
        "def _lambdifygenerated(:\n"
    clear_caches()


def _modules_of_cycle(env) -> tuple[bytes, list[str]]:
    code = ("import sys, runpy; sys.argv = ['kbm', 'cycle', 'vdp', '-p', 'mu=1', '--json']\n"
            "try:\n    runpy.run_module('numerics.cli', run_name='__main__')\n"
            "finally:\n    print('MODULES', *sorted(m for m in sys.modules if m.startswith("
            "('scipy.', 'kbm.averag', 'numba'))), file=sys.stderr)")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, cwd=ROOT, env=env,
                          timeout=600, check=True)
    return proc.stdout, proc.stderr.decode().splitlines()[-1].split()[1:]


def test_the_warm_cycle_imports_no_scipy_optimize_special_or_integrate():
    """``kbm cycle vdp -p mu=1`` with the cache in use warm (a first run warms it, building
    the flows ahead of time once per machine): no ``scipy.optimize``, ``scipy.special`` or
    ``scipy.integrate``, no KBM derivation (:mod:`kbm.averaging`, :mod:`kbm.averaged`) and,
    where a C compiler built the flows ahead of time, no numba; the output is the first
    run's, byte for byte (the just-in-time code's where the first run built the flows; the
    two codes' flows are compared bit for bit in ``tests/test_flow_aot.py``)."""
    env = {**os.environ, "PYTHONPATH": str(ROOT), "KBM_COMPILE_NOTICE": "0", "KBM_AOT": "1"}
    first, _ = _modules_of_cycle(env)
    out, modules = _modules_of_cycle(env)
    assert out == first and b'"period"' in out
    assert not [m for m in modules if m.startswith(SCIPY_PARTS)], modules
    assert not [m for m in modules if m.startswith("kbm.averag")], modules
    if shutil.which("cc") or shutil.which("gcc"):
        assert not [m for m in modules if m.startswith("numba")], modules
