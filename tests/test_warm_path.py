"""The warm path of ``kbm cycle`` (issue 39): the first-order KBM guess from the template
cache's record (:mod:`numerics.cycles.guess`), its roots by a port of Brent's method that
gives scipy's floats to the last bit, the model card (:mod:`numerics.flow.card`) that
spares the symbolic model, and a warm run that imports none of ``scipy.optimize``,
``scipy.special``, ``scipy.integrate`` and no sympy; refused input gives the same message
with a card stored."""

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

from kbm.slowflow import roots
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
    try:
        expected = brentq(f, a, b, xtol=tols[0], rtol=tols[1])
    except RuntimeError:  # scipy's 100 steps not enough (e.g. x**3 at xtol 2e-12): so too here
        with pytest.raises(RuntimeError, match="did not converge"):
            roots.brentq(f, a, b, *tols)
        return
    assert roots.brentq(f, a, b, *tols) == expected


def test_brentq_refuses_a_bracket_without_a_sign_change():
    with pytest.raises(ValueError, match="different signs"):
        roots.brentq(lambda x: x * x + 1.0, -1.0, 1.0)


def test_brentq_finds_sqrt2_to_the_tolerance():
    """The positive root of ``x^2 - 2`` (exact: sqrt 2) to ``xtol``."""
    assert abs(roots.brentq(lambda x: x * x - 2.0, 0.0, 2.0, 1e-15, 1e-14) - math.sqrt(2)) \
        < 1e-14


@pytest.mark.parametrize("name, params", [("vdp", {"mu": 1}), ("rayleigh", {"mu": 0.5})])
def test_guess_equals_the_averaged_cycles_of_kbm(name, params, tmp_path, monkeypatch):
    """The guess from the stored rates (cold: built, stored, read back; warm: read) is the
    stable first-order cycle of :meth:`kbm.AveragedRates.cycles` (rates lambdified anew from
    the symbolic derivation; both search with :func:`kbm.slowflow.roots.amplitude_roots`, whose
    Brent steps equal scipy's brentq, tested above) to the last bit; van der Pol's first-order
    amplitude is 2 (the textbook result, Nayfeh and Mook, *Nonlinear Oscillations*,
    sec. 3.3)."""
    from kbm import averaged_rates, derive
    from kbm.parameters.bound import bind

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
    from kbm.parameters.bound import bind

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


def _modules_of(env, argv, prefixes) -> tuple[bytes, list[str]]:
    """The standard output of ``kbm argv`` and the modules it imported whose names start
    with one of ``prefixes``."""
    code = (f"import sys, runpy; sys.argv = ['kbm', *{list(argv)!r}]\n"
            "try:\n    runpy.run_module('numerics.cli', run_name='__main__')\n"
            "finally:\n    print('MODULES', *sorted(m for m in sys.modules if m.startswith("
            f"{tuple(prefixes)!r})), file=sys.stderr)")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, cwd=ROOT, env=env,
                          timeout=600, check=True)
    return proc.stdout, proc.stderr.decode().splitlines()[-1].split()[1:]


def _modules_of_cycle(env, args=("vdp", "-p", "mu=1")) -> tuple[bytes, list[str]]:
    return _modules_of(env, ["cycle", *args, "--json"],
                       ("scipy.", "kbm.averag", "numba", "sympy"))


def test_the_warm_cycle_imports_no_scipy_optimize_special_or_integrate():
    """``kbm cycle vdp -p mu=1`` with the cache in use warm (a first run warms it, building
    the flows ahead of time once per machine): no ``scipy.optimize``, ``scipy.special`` or
    ``scipy.integrate``, no KBM derivation (:mod:`kbm.expansion.one_dof`,
    :mod:`kbm.slowflow.averaged`) and, where a C compiler built the flows ahead of time, no numba;
    the output is the first run's, byte for byte (the just-in-time code's where the first run built
    the flows; the two codes' flows are compared bit for bit in ``tests/test_flow_aot.py``)."""
    env = {**os.environ, "PYTHONPATH": str(ROOT), "KBM_COMPILE_NOTICE": "0", "KBM_AOT": "1"}
    first, _ = _modules_of_cycle(env)
    out, modules = _modules_of_cycle(env)
    assert out == first and b'"period"' in out
    assert not [m for m in modules if m.startswith(SCIPY_PARTS)], modules
    assert not [m for m in modules if m.startswith("kbm.averag")], modules
    if shutil.which("cc") or shutil.which("gcc"):
        assert not [m for m in modules if m.startswith("numba")], modules
        # the model card and the flows built ahead of time: no symbolic model at all
        assert not [m for m in modules if m.startswith("sympy")], modules


#: the whole continuation command of issue 39
BRANCH = ["branch", "sedf", "-p", "mu=0.1", "-p", "beta=1", "-p", "lam=1", "--vary",
          "Delta=0:4", "--orders", "none", "--no-energy", "--json"]


def _modules_of_branch(env) -> tuple[bytes, list[str]]:
    return _modules_of(env, BRANCH, ("numba", "numerics.comparison.", "numerics.energy.", "sympy",
                                       "scipy", "mpmath"))


def test_the_warm_branch_imports_no_numba_and_gives_the_same_bytes():
    """The whole ``kbm branch sedf ... --vary Delta=0:4`` of issue 39 with the cache warm:
    the continuation's Newton corrector and nine-state flow built ahead of time
    (:mod:`numerics.flow.aot`), so no numba where a C compiler built them; none of
    :mod:`numerics.comparison`'s comparison, convergence and fixed-``Delta`` studies nor
    the energy method's maps (lazy exports); the JSON is the first run's, byte for byte."""
    env = {**os.environ, "PYTHONPATH": str(ROOT), "KBM_COMPILE_NOTICE": "0", "KBM_AOT": "1"}
    first, _ = _modules_of_branch(env)
    out, modules = _modules_of_branch(env)
    assert out == first and b'"branches"' in out
    assert not [m for m in modules if m.startswith(("numerics.comparison.comparison",
                                                    "numerics.comparison.convergence",
                                                    "numerics.comparison.fixed_delta",
                                                    "numerics.energy.maps"))], modules
    if shutil.which("cc") or shutil.which("gcc"):
        assert not [m for m in modules if m.startswith("numba")], modules


def test_the_warm_branch_imports_no_sympy_scipy_or_numba():
    """The whole ``kbm branch sedf ... --vary Delta=0:4 --orders none --no-energy`` of issue
    39 with every cache warm (a first run stores the model and line cards, the checks, the
    seeds' record, :mod:`numerics.flow.line_card`, :mod:`numerics.cycles.seeds`): no sympy
    (no symbolic model is built), no ``scipy`` at all (the homoclinic end's minimiser and
    energies by :mod:`numerics.cycles.localmin`, tested against scipy in
    ``tests/test_localmin.py``; the roots by :func:`kbm.slowflow.roots.brentq`), no mpmath (the
    stored energy's rationals are floats, :func:`numerics.flow.template_cache.lambdify_light`)
    and, where a C compiler built the flows ahead of time, no numba; the JSON is the first
    run's."""
    env = {**os.environ, "PYTHONPATH": str(ROOT), "KBM_COMPILE_NOTICE": "0", "KBM_AOT": "1"}
    first, _ = _modules_of_branch(env)
    out, modules = _modules_of_branch(env)
    assert out == first and b'"branches"' in out
    assert not [m for m in modules if m.startswith(("sympy", "scipy"))], modules
    # the stored energy prints its rationals as floats (no mpf: no mpmath, 0.1 s)
    assert not [m for m in modules if m.startswith("mpmath")], modules
    assert not [m for m in modules if m.startswith("numerics.energy.")
                and m != "numerics.energy._zeros"], modules
    if shutil.which("cc") or shutil.which("gcc"):
        assert not [m for m in modules if m.startswith("numba")], modules


def test_the_warm_sedf_cycle_imports_no_scipy_special():
    """``kbm cycle sedf -p mu=0.1 -p beta=1 -p lam=1 -p Delta=1``: its first-order rates hold
    Bessel functions (``scipy.special.jv``); the warm run reads the KBM guess kept in the
    model card (:func:`numerics.cycles.guess.kbm_guess`) and imports no scipy, sympy or
    (where the flows are built ahead of time) numba; the output is the first run's."""
    env = {**os.environ, "PYTHONPATH": str(ROOT), "KBM_COMPILE_NOTICE": "0", "KBM_AOT": "1"}
    args = ("sedf", "-p", "mu=0.1", "-p", "beta=1", "-p", "lam=1", "-p", "Delta=1")
    first, _ = _modules_of_cycle(env, args)
    _modules_of_cycle(env, args)  # the first warm run keeps the guess in the card
    out, modules = _modules_of_cycle(env, args)
    assert out == first and b'"period"' in out
    assert not [m for m in modules if m.startswith(("scipy", "sympy"))], modules
    if shutil.which("cc") or shutil.which("gcc"):
        assert not [m for m in modules if m.startswith("numba")], modules


@pytest.mark.slow
def test_the_warm_branch_is_numbas_to_the_byte():
    """The warm ``kbm branch`` of issue 39 with the corrector built ahead of time and with
    numba's just-in-time code alone (``KBM_AOT=0``): the same JSON, byte for byte (the
    two codes' corrector is compared bit for bit in ``tests/test_flow_aot.py``)."""
    env = {**os.environ, "PYTHONPATH": str(ROOT), "KBM_COMPILE_NOTICE": "0", "KBM_AOT": "1"}
    _modules_of_branch(env)
    out, _ = _modules_of_branch(env)
    jit, jit_modules = _modules_of_branch({**env, "KBM_AOT": "0"})
    assert jit == out and b'"branches"' in out and "numba" in jit_modules


def _cli(args: list[str], env) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "numerics.cli", *args], capture_output=True,
                          cwd=ROOT, env=env, timeout=600)


#: input that is refused, each with the card of ``-p mu=1`` (vdp) or of the valid SEDF
#: values stored: an unknown name, a flag of --rhs with a built-in, a value that is not
#: finite, a scaled and a physical value of one parameter, a wavelength of zero
REFUSED = [["cycle", "vdp", "-p", "mu=1", "-p", "Mu=2"],
           ["cycle", "--rhs", "(1 - x**2)*xdot", "-p", "mu=1", "-p", "c=2"],
           ["cycle", "vdp", "-p", "mu=1", "--omega0", "2"],
           ["cycle", "vdp", "-p", "mu=nan"],
           ["cycle", "sedf", "-p", "mu=0.1", "-p", "beta=1", "-p", "lam=1", "-p", "Delta=1",
            "-p", "delta=3"],
           ["cycle", "sedf", "-p", "mu=0.1", "-p", "beta=1", "-p", "lam=0", "-p", "Delta=1"]]


def test_the_warm_cycle_of_a_user_model_imports_no_sympy():
    """``kbm cycle --rhs "(c - x**2)*xdot" --omega0 2`` (van der Pol's form with a
    parameter ``c``): the warm run reads the model card of the user's model, imports no
    sympy (where the flows are built ahead of time) and prints the first run's bytes."""
    env = {**os.environ, "PYTHONPATH": str(ROOT), "KBM_COMPILE_NOTICE": "0", "KBM_AOT": "1"}
    args = ("--rhs", "(c - x**2)*xdot", "--omega0", "2", "-p", "mu=0.5", "-p", "c=2")
    first, _ = _modules_of_cycle(env, args)
    out, modules = _modules_of_cycle(env, args)
    assert out == first and b'"period"' in out
    if shutil.which("cc") or shutil.which("gcc"):
        assert not [m for m in modules if m.startswith("sympy")], modules


VALID = [["cycle", "vdp", "-p", "mu=1"],
         ["cycle", "sedf", "-p", "mu=0.1", "-p", "beta=1", "-p", "lam=1", "-p", "Delta=1",
          "--json"]]


def _same_refusals_with_cards(refused, valid, zero: bool, rounds: int = 2) -> None:
    """Each refused input, run before and after the valid runs stored their model cards (and
    twice after): exit status 2, nothing on standard output, and the same one-line message;
    the valid runs give the same bytes cold and warm; with ``zero``, ``-p mu=0`` gives the
    same refusal (``x'' + x = 0`` is conservative: no isolated cycle) from the card's record
    that the acceleration holds ``mu``."""
    env = {**os.environ, "PYTHONPATH": str(ROOT), "KBM_COMPILE_NOTICE": "0"}
    before = [_cli(a, env) for a in refused]
    runs = [[_cli(a, env).stdout for _ in range(2)] for a in valid]
    assert all(r[0] == r[1] and r[0] for r in runs)
    for _ in range(rounds):
        after = [_cli(a, env) for a in refused]
        for b, a in zip(before, after):
            assert (b.returncode, b.stdout, b.stderr) == (a.returncode, a.stdout, a.stderr)
            assert a.returncode == 2 and not a.stdout
            assert len(a.stderr.decode().strip().splitlines()) == 1, a.stderr
    if zero:
        z = [_cli(["cycle", "vdp", "-p", "mu=0"], env) for _ in range(2)]
        assert z[0].stderr == z[1].stderr and b"conservative" in z[0].stderr
        assert z[0].returncode == z[1].returncode == 2


def test_refused_input_gives_the_same_message_with_the_cards_stored():
    """All of :data:`REFUSED` and both valid runs (text and ``--json``), and ``-p mu=0``
    (slow: 24 processes; the default run has the sibling below)."""
    _same_refusals_with_cards(REFUSED, VALID, zero=True)


def test_an_unknown_name_and_a_nan_are_refused_alike_with_the_card_stored():
    """The default run's sibling of the test above: an unknown name and ``mu=nan`` on vdp,
    before and once after ``kbm cycle vdp -p mu=1`` stored its card."""
    _same_refusals_with_cards([REFUSED[0], REFUSED[3]], VALID[:1], zero=False, rounds=1)


def test_the_card_key_changes_with_the_name_and_the_values():
    """A card is named by the built-in name and the values as given (their types too), and
    there is none for a model object or a value of another type."""
    from numerics.flow.card import card_key, use_cards

    use_cards(False)
    assert card_key("vdp", {"mu": "1"}) is None  # a library call: no cards
    use_cards()
    keys = {card_key("vdp", {"mu": "1"}), card_key("vdp", {"mu": 1}),
            card_key("vdp", {"mu": 1.0}), card_key("rayleigh", {"mu": "1"}),
            card_key("vdp", {"mu": "1.0"}), card_key("vdp", {})}
    assert len(keys) == 6 and None not in keys, keys
    assert card_key("vdp", {"mu": "1"}) == card_key("vdp", {"mu": "1"})
    assert card_key(object(), {"mu": "1"}) is None
    assert card_key("vdp", {"mu": np.float64(1)}) is None
    use_cards(False)


def test_the_cycle_from_a_card_equals_the_cycle_bound_anew(tmp_path, monkeypatch):
    """:func:`numerics.limit_cycle` of ``vdp``, ``mu = 1`` from the model card (written by
    the first call, read by the second) equals the cycle bound and compiled anew, to the
    last bit; a damaged card is bound anew (same numbers).  The period is van der Pol's
    known period at ``mu = 1``, 6.6632868593 (the value of ``kbm``'s own docstring example
    and of the published continuations of the van der Pol cycle)."""
    from numerics import limit_cycle
    from numerics._memo import clear_caches
    from numerics.flow import card

    from numerics.flow.numba_cache import cache_dir

    for p in cache_dir().iterdir():  # the compiled flows, so that only the card is cold
        if p.name.startswith(("kbm_flow_", "kbm_src_", "kbm_aot_")) or p.name == "__pycache__":
            (shutil.copytree if p.is_dir() else shutil.copy2)(p, tmp_path / p.name)
    monkeypatch.setenv("KBM_CACHE_DIR", str(tmp_path))
    monkeypatch.setattr(card, "_ON", [True])  # as the command line turns them on
    clear_caches()
    cold = limit_cycle("vdp", {"mu": "1"})
    assert card.card_model("vdp", {"mu": "1"}) is not None
    clear_caches()
    warm = limit_cycle("vdp", {"mu": "1"})
    path, = tmp_path.glob("kbm_card_*.json")
    path.write_text("{not json")
    clear_caches()
    anew = limit_cycle("vdp", {"mu": "1"})
    for c in (warm, anew):
        assert json.dumps(c.to_json()) == json.dumps(cold.to_json())
        assert np.array_equal(c.x, cold.x) and np.array_equal(c.harmonics, cold.harmonics)
    assert abs(cold.period - 6.6632868593) < 1e-9
    clear_caches()
