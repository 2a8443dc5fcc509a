"""The stored forms of issue 39's warm ``kbm branch`` against what they stand for: a line
card (:mod:`numerics.flow.line_card`) against the line bound from the symbolic model
(:class:`kbm.parameters.bound.ParameterLine`, :class:`numerics.flow.CompiledLine`), and the stored
seeds of :func:`numerics.cycles.limit_cycles` (:mod:`numerics.cycles.seeds`) against the
energy-balance prediction computed anew.  The slow route is the reference: the same exact
rationals, the same floats, the same cycles."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from numerics.flow import card
from numerics.flow.line_card import CardLine, compiled_line, line_key, read_line

ROOT = Path(__file__).resolve().parents[1]

CASES = [
    ("sedf", {"mu": "0.1", "beta": "1", "lam": "1"}, "Delta", 0.0),  # delta = Delta/mu
    ("sedf", {"mu": "0.1", "beta": "1", "lam": "1", "Delta": "2"}, "mu", 0.1),  # 1/mu
    ("sedf", {"mu": "0.1", "beta": "1", "lam": "1", "Delta": "2"}, "beta", 1.0),
    ("vdp", {"mu": "0.5"}, "mu", 0.5),
]


@pytest.fixture
def cards(tmp_path, monkeypatch):
    """The cards on (as ``kbm branch`` turns them on) in a cache folder of the test's own,
    holding the compiled flows of the shared one (so that only the cards are cold)."""
    from numerics._memo import clear_caches
    from numerics.flow.numba_cache import cache_dir

    for p in cache_dir().iterdir():
        if p.name.startswith(("kbm_src_", "kbm_aot_")):  # the flows built ahead of time
            (shutil.copytree if p.is_dir() else shutil.copy2)(p, tmp_path / p.name)
    monkeypatch.setenv("KBM_CACHE_DIR", str(tmp_path))
    monkeypatch.setattr(card, "_ON", [True])
    clear_caches()
    yield tmp_path
    clear_caches()


@pytest.mark.parametrize("model, params, vary, at", CASES)
def test_the_line_from_its_card_is_the_bound_line(cards, model, params, vary, at):
    """A line built (and its card stored) and the line read from the card: at 25 values of
    the parameter the same float values, rates, parameter vectors and flows' values, and
    no symbolic line built for them; the card names the flows of the template."""
    cold = compiled_line(model, params, vary, at)
    assert cold.card_key == line_key(model, params, vary, at) and read_line(cold.card_key)
    warm = compiled_line(model, params, vary, at)
    assert isinstance(warm.line, CardLine)
    for p in np.linspace(at, at + 3.7, 25):
        p = float(p)
        assert warm.line.floats(p) == cold.line.floats(p)
        assert warm.line.rates(p) == cold.line.rates(p)
        a, b = warm(p), cold(p)
        assert a.pvec == b.pvec
        assert np.array_equal(a.jac(0.0, (1.3, -0.4)), b.jac(0.0, (1.3, -0.4)))
        assert a.acc(0.0, 1.3, -0.4) == b.acc(0.0, 1.3, -0.4)
        assert np.array_equal(warm.rates(p), cold.rates(p))
    assert warm.line.affine == cold.line.affine and warm.line.changed == cold.line.changed
    assert "_line" not in warm.line.__dict__  # the symbolic line was never needed


@settings(max_examples=60, deadline=None)
@given(value=st.floats(-50.0, 50.0).filter(lambda v: abs(v) > 1e-9))
def test_card_rationals_are_the_lines_for_any_value(value):
    """``delta = Delta/mu`` (paper eq. 3) from the card's stored expression tree in exact
    rationals (:mod:`kbm.parameters.rational_values`) equals
    :meth:`kbm.parameters.bound.ParameterLine.floats` and sympy's own exact rational of the
    expression (a second method), correctly rounded, for any ``Delta``, and ``mu`` varied
    (``delta = Delta/mu`` with ``Delta = 2``) too."""
    import sympy as sp

    from kbm.parameters.bound import ParameterLine
    from kbm.parameters.rational_values import rational_tree, tree_value
    from fractions import Fraction

    for params, vary in (({"mu": "0.1", "beta": "1", "lam": "1"}, "Delta"),
                         ({"mu": "0.1", "beta": "1", "lam": "1", "Delta": "2"}, "mu")):
        line = ParameterLine("sedf", params, vary, 1.0)
        env = dict(line._fractions)
        env[vary] = Fraction(repr(value))
        for scaled, expr, _ in line._derived:
            exact = expr.xreplace({sp.Symbol(n): sp.Rational(v.numerator, v.denominator)
                                   for n, v in env.items()})
            assert float(tree_value(rational_tree(expr), env)) == line.floats(value)[scaled]
            assert line.floats(value)[scaled] == float(exact)


def test_a_damaged_line_card_is_built_anew(cards):
    """A card whose template record is gone or whose content is not a card: the line is
    bound from the symbolic model, with the same values."""
    good = compiled_line("sedf", CASES[0][1], "Delta", 0.0)
    key = good.card_key
    path, = cards.glob(f"kbm_line_{key}.json")
    path.write_text("{not json")
    again = compiled_line("sedf", CASES[0][1], "Delta", 0.0)
    assert not isinstance(again.line, CardLine)
    assert again(1.7).pvec == good(1.7).pvec


@pytest.fixture
def shared_cards(monkeypatch):
    """The cards on in the shared cache folder (its compiled flows are there already)."""
    from numerics._memo import clear_caches

    monkeypatch.setattr(card, "_ON", [True])
    clear_caches()
    yield
    clear_caches()


def test_the_stored_seeds_are_the_prediction(shared_cards):
    """:func:`numerics.cycles.limit_cycles` with the cards on (the seeds computed and stored
    on the first call, read on the second) finds the cycles it finds with the cards off, to the last bit, and
    the stored seeds are the energy-balance prediction's ``(x_max, period)``
    (:func:`numerics.energy.predict_cycles`, computed anew)."""
    from kbm.parameters.bound import bind
    from numerics._memo import clear_caches
    from numerics.cycles import limit_cycles
    from numerics.cycles.seeds import StoredPrediction
    from numerics.energy import predict_cycles

    params = {"mu": "0.1", "beta": "1", "lam": "1", "Delta": "1.5"}
    cold = limit_cycles("sedf", params)
    clear_caches()
    warm = limit_cycles("sedf", params)
    card._ON[0] = False
    clear_caches()
    plain = limit_cycles("sedf", params)
    card._ON[0] = True
    for cs in (cold, warm):
        assert [(c.amplitude_max, c.period) for c in cs] == \
            [(c.amplitude_max, c.period) for c in plain]
    b = bind("sedf", params)
    pred = predict_cycles(b.model, dict(b.values))
    stored = [p for p in warm._predicted if isinstance(p, StoredPrediction)]
    assert stored and {(p.amplitude_max, p.period) for p in stored} <= \
        {(p.amplitude_max, p.period) for p in pred.cycles}
    assert warm.predictions.cycles[0].amplitude_max == pred.cycles[0].amplitude_max


#: a refused ``kbm branch`` (an unknown name), and the valid one of issue 39 whose cards
#: would skip the checks of a warm run
REFUSED = ["branch", "sedf", "-p", "mu=0.1", "-p", "beta=1", "-p", "lam=1", "-p", "Mu=3",
           "--vary", "Delta=0:4", "--orders", "none", "--no-energy", "--json"]
VALID = ["branch", "sedf", "-p", "mu=0.1", "-p", "beta=1", "-p", "lam=1", "--vary",
         "Delta=0:4", "--orders", "none", "--no-energy", "--json"]


def test_refused_branch_input_is_refused_alike_with_the_cards_stored():
    """An unknown name before and after the valid branch stored its cards: exit 2, nothing
    on standard output, the same one-line message (the checks are skipped only for the
    exact model, values and ``--vary`` a run checked)."""
    env = {**os.environ, "PYTHONPATH": str(ROOT), "KBM_COMPILE_NOTICE": "0"}

    def cli(args):
        return subprocess.run([sys.executable, "-m", "numerics.cli", *args],
                              capture_output=True, cwd=ROOT, env=env, timeout=600)
    before = cli(REFUSED)
    assert cli(VALID).returncode == 0
    after = cli(REFUSED)
    assert (before.returncode, before.stdout, before.stderr) == \
        (after.returncode, after.stdout, after.stderr)
    assert after.returncode == 2 and not after.stdout
    assert len(after.stderr.decode().strip().splitlines()) == 1
