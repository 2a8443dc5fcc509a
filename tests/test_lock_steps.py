"""``kbm lock``'s follow of the locked state in steps scaled to the interval, its amplitude
death's ``checked_at``, and which names are couplings (numerics.locking.start,
numerics.locking.mutual), against independent references.

- ``coupled-vdp`` at first order: the phase equation ``gamma' = mu (sigma - c sin gamma)``
  (equal amplitudes) locks for ``|sigma| <= c`` exactly (``c < 1``), the closed-form tongue;
- for ``c > 1`` the locked state dies into the origin before: the first-order
  linearisation at the origin ``(mu/2) [[1 - c, c], [c, 1 - c + 2 i sigma]]`` (Aronson,
  Ermentrout & Kopell 1990) has eigenvalues ``(mu/2)(1 - c + i sigma +- sqrt(c^2 -
  sigma^2))``, whose larger real part is 0 at ``sigma^2 = 2c - 1``: the order-1 edge is
  ``|sigma| = sqrt(2c - 1)`` (3 at ``c = 5``).  Before, Newton past that point converged to
  amplitudes of 1e-40 (the origin) and the edge was put at 3.0635 (3.1115 with larger
  steps).
"""

from __future__ import annotations

import json
import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import numerics.locking.mutual as locking
from kbm.model.coupled_builtins import get_coupled_model
from numerics.cli import main
from numerics.cli.lock import _split
from numerics.cli.params.values import parse_vary
from numerics.locking.start import follow_steps
from numerics.locking.mutual import averaged_edges, coupling_names


def test_steps_of_the_unit_span_are_the_absolute_steps_of_before():
    """``--vary sigma=-1:1`` from 0 (a span of 1 on a side): 0.02, 0.1 and 1e-3, the
    absolute steps the follow had, so its edges are unchanged (the reference case's JSON is
    byte-identical but for the new ``checked_at``)."""
    assert follow_steps(1.0) == (0.02, 0.1, 1e-3)
    assert follow_steps(math.inf) == follow_steps(0.0) == follow_steps(1.0)


@settings(max_examples=30, deadline=None)
@given(st.floats(1e-6, 1e6))
def test_steps_scale_with_the_span(span):
    first, largest, smallest = follow_steps(span)
    assert first == pytest.approx(0.02 * span) and largest == pytest.approx(0.1 * span)
    assert smallest == pytest.approx(min(1e-3, 0.02 * span)) and smallest <= first < largest
    assert largest < span


def _count_calls(monkeypatch, module, name: str) -> list:
    """A list that grows by one at each call of ``module.name`` (the call itself unchanged)."""
    calls = []
    real = getattr(module, name)

    def counted(*a, **k):
        calls.append(1)
        return real(*a, **k)

    monkeypatch.setattr(module, name, counted)
    return calls


@pytest.mark.parametrize("width", [1.0, 10.0, 100.0])
def test_order1_edges_are_the_closed_form_tongue_whatever_the_width(width, monkeypatch):
    """|sigma| = c (c = 0.2) from intervals of every width, in a bounded number of steps."""
    calls = _count_calls(monkeypatch, locking, "_newton")
    edges = averaged_edges("coupled-vdp", {"mu": 0.08, "c": 0.2}, 1, "sigma",
                           limits={-1: width, 1: width})
    assert sorted(e.sigma for e in edges) == pytest.approx([-0.2, 0.2], abs=1e-9)
    assert len(calls) < 120


def test_order1_edge_where_the_locked_state_dies_into_the_origin(monkeypatch):
    """c = 5: the edge is |sigma| = sqrt(2c - 1) = 3 (the origin's first-order eigenvalue
    through 0), reached from sigma=-40:40 in fewer slow-flow solves than the absolute steps
    took (0.02 growing to 0.1: over 30 per side before the bracket)."""
    calls = _count_calls(monkeypatch, locking, "_newton")
    edges = averaged_edges("coupled-vdp", {"mu": 0.08, "c": 5.0}, 1, "sigma",
                           limits={-1: 4.0, 1: 4.0})
    assert sorted(e.sigma for e in edges) == pytest.approx([-3.0, 3.0], abs=1e-6)
    few = len(calls)
    averaged_edges("coupled-vdp", {"mu": 0.08, "c": 5.0}, 1, "sigma",
                   limits={-1: 40.0, 1: 40.0})
    assert len(calls) - few < 2 * 60


def test_couplings_of_each_model():
    """The sliders' k = 2 pi/lam is a scaled parameter (their wavenumber), no coupling;
    duffing-1-3's k is its coupling."""
    assert coupling_names(get_coupled_model("sedf-dimer")) == ("kappa",)
    assert coupling_names(get_coupled_model("coupled-vdp")) == ("c",)
    assert coupling_names(get_coupled_model("duffing-1-3")) == ("k",)


def test_sliders_k_is_followed_like_lam():
    """``--vary k=5:7 --vary kappa=0.1,0.2`` on sedf-dimer: k is the followed axis and kappa
    the coupling (before: 'at most one --vary for the coupling (c, k, kappa)', exit 2)."""
    dimer = get_coupled_model("sedf-dimer")
    det, cpl = _split([parse_vary("k=5:7"), parse_vary("kappa=0.1,0.2")], dimer)
    assert (det.name, cpl.name) == ("k", "kappa")
    det, cpl = _split([parse_vary("lam=0.9:1.1")], dimer)
    assert det.name == "lam" and cpl is None


@pytest.mark.slow  # 4-8 s; kept out of the default run (five-minute rule)
def test_amplitude_death_says_where_it_was_checked(capsys):
    """Each ``amplitude_death`` entry's ``checked_at``: the start of the follow (sigma = 0,
    the interval holds it) and the coupling; the eigenvalues there are those of
    ``amplitude_death`` at these values (recomputed)."""
    assert main(["lock", "coupled-vdp", "-p", "mu=0.08", "--vary", "sigma=-1:1", "--vary",
                 "c=0.2,0.4", "--order", "1", "--tol", "1e-5", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    got = [x["checked_at"] for x in d["amplitude_death"]]
    assert got == [{"sigma": 0.0, "c": 0.2}, {"sigma": 0.0, "c": 0.4}]
    for x in d["amplitude_death"]:
        ref = locking.amplitude_death("coupled-vdp", {"mu": 0.08, **x["checked_at"]})
        assert x["eigenvalues"] == ref["eigenvalues"] and x["dead"] == ref["dead"]


def test_true_edge_from_a_wide_interval_is_the_scipy_fold():
    """The locked cycle followed over sigma in [-20, 20] with no estimate of the edge (the
    first step 0.4, growing to 2): its upper edge is the fold of
    ``tests/test_shooting_acceptance.py`` (scipy DOP853 with variational equations,
    0.20160636567730025) within the stated error and 1e-11."""
    from numerics.locking.fold import true_edges

    fold = 0.20160636567730025
    edge = true_edges("coupled-vdp", {"mu": 0.08, "c": 0.2}, tol=1e-9,
                      limits={-1: 20.0, 1: 20.0})[1]
    assert abs(edge.sigma - fold) < 1e-11
    assert abs(edge.sigma - fold) <= edge.error + 1e-12


def test_true_follow_across_a_wide_locked_interval_in_few_shots(monkeypatch):
    """c = 5, sigma in [-2.5, 2.5]: the cycle stays locked over the whole interval (its
    folds at -2.66 and 3.38, ``kbm lock ... --vary sigma=-4:4``), and no averaged edge lies
    in it to guess from.  The follow crosses it in steps growing to 0.25: 26 shots, where
    the absolute 0.02 took 250."""
    import numerics.locking.fold as fold

    shots = _count_calls(monkeypatch, fold, "_shoot")
    edges = fold.true_edges("coupled-vdp", {"mu": 0.08, "c": 5.0}, tol=1e-7,
                            limits={-1: 2.5, 1: 2.5})
    assert [e.sigma for e in edges] == [-math.inf, math.inf]
    assert len(shots) < 60
