"""Convergence at fixed physical Delta (numerics.comparison.fixed_delta): the energy
method's errors fall at the predicted rates, classical KBM's do not fall."""

from __future__ import annotations

import json

import numpy as np
import pytest

from numerics.comparison.fixed_delta import FixedDeltaConvergence, fixed_delta_study
from numerics.paper.figures import FIGURES
from numerics.paper.figures.methods import fixed_delta_figure

EPS = (0.1, 0.05, 0.025, 0.0125)


@pytest.fixture(scope="module")
def study():
    return fixed_delta_study(1.5, 1.0, EPS, energy_orders=(1, 2))


def test_energy_period_slopes_match_predicted_orders(study):
    """SEDF, Delta = 1.5, beta = 1 (h odd in x'): the frequency error of the energy
    method falls as mu**2 at order 1 and mu**4 at order 2 (fitted slopes within 0.2),
    and so do max x and the first-harmonic amplitude; the Floquet exponent as mu**3, mu**5."""
    for row, even, odd in (("energy order 1", 2, 3), ("energy order 2", 4, 5)):
        for key in ("frequency", "amplitude_max", "amplitude"):
            assert study.predicted[(row, key)] == even
            assert abs(study.slopes[(row, key)] - even) < 0.2, (row, key)
        assert study.predicted[(row, "floquet_exponent")] == odd
        assert abs(study.slopes[(row, "floquet_exponent")] - odd) < 0.25


def test_classical_kbm_does_not_converge_at_fixed_delta(study):
    """At fixed Delta = 1.5 (delta = Delta/mu grows) the relative errors of classical KBM
    orders 1 and 2 in frequency and max x stay above 1 % down to mu = 0.0125 (slope ~ 0),
    while the energy method's order 2 is below 1e-8 there."""
    for N in (1, 2):
        for key in ("frequency", "amplitude_max"):
            rel = study.relative[(f"KBM order {N}", key)]
            assert np.all(rel > 0.01), (N, key)
            assert abs(study.slopes[(f"KBM order {N}", key)]) < 0.2
            assert study.predicted[(f"KBM order {N}", key)] is None
    assert study.relative[("energy order 2", "frequency")][-1] < 1e-8


def test_no_true_cycle_is_reported():
    """Delta = 3, beta = 1, mu = 0.2: the motion settles on an equilibrium of the
    potential; the study says so for that mu and fits the others."""
    s = fixed_delta_study(3.0, 1.0, (0.2, 0.1, 0.05), energy_orders=(1,), kbm_orders=(1,))
    assert "no true cycle" in s.messages[0] and not any(s.messages[1:])
    assert np.isnan(s.errors[("energy order 1", "frequency")][0])
    assert np.isfinite(s.slopes[("energy order 1", "frequency")])
    text = json.dumps(s.to_json(), allow_nan=False)
    assert "no true cycle" in text and "Delta = 3" in s.table()


@pytest.mark.slow  # the whole study again through the command line (24 s); the study
# itself is checked above, the flags below
def test_cli_fixed_delta_json(capsys):
    """``kbm compare --fixed-delta`` prints strict JSON with one study per beta."""
    import json

    from numerics.cli import main

    assert main(["compare", "--fixed-delta", "1.5", "--json"]) == 0
    out = json.loads(capsys.readouterr().out, parse_constant=lambda t: 1 / 0)
    assert len(out["studies"]) == 3


def test_cli_fixed_delta_and_methods_map_flags(capsys):
    """A wrong value or a flag the study would ignore is a one-line error with exit
    status 2."""
    from numerics.cli import main

    for argv in (["compare", "--fixed-delta", "x"], ["compare", "vdp", "--fixed-delta", "1.5"],
                 ["compare", "--methods-map", "--paper"]):
        assert main(argv) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and err[0].startswith("kbm compare: error:")


@pytest.mark.slow  # 3-4 s; kept out of the default run (five-minute rule)
def test_fixed_delta_figure_registered_and_written(study, tmp_path):
    """'fixed_delta_convergence' is in the figure registry; drawn from a computed study (as
    ``kbm reproduce`` draws it: the module's study, its errors checked above) it is a PNG of
    more than 10 kB in the folder asked for.  (It was drawn from a second study of three of
    these mu in tests/test_paper_methods_figures.py.)"""
    assert "fixed_delta_convergence" in FIGURES
    paths = fixed_delta_figure(tmp_path, conv=FixedDeltaConvergence((study,)))
    assert [p.name for p in paths] == ["fixed_delta_convergence.png"]
    for p in paths:
        assert p.parent == tmp_path
        data = p.read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 10_000, p
