"""The one continuation driver (numerics.shooting.continuation) and the one branch result
(numerics.shooting.branch_result), issue 35.

- The fold of cycles of x'' + x = mu (-q + x^2 - x^4) x' (mu = 0.1): the averaged amplitude
  equation r' = (mu r/2)(-q + r^2/4 - r^4/8) has its fold where dq/d(r^2) = 0, at
  r^2 = 1, q = 1/8 (Krylov-Bogoliubov, first order; the true fold is within O(mu) of it).
  The two cases of the one driver locate it on two different branch problems: the
  one-degree-of-freedom one with the section xdot = 0 eliminated (continue_cycles) and the
  2N one with all multipliers (continue_coupled, the model as N = 1); both must give the
  same fold (a second method) and both near 1/8.
- The JSON layouts: every key of both renderings, in order (the keys are a contract).
"""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from kbm.model.coupled_builtins import coupled_custom
from kbm.model.user_model import custom_model
from numerics.shooting.branch_result import (Branch, BranchPoint, CoupledBranch,
                                             CoupledBranchPoint, CoupledSpecialPoint,
                                             OrbitBranch, SpecialPoint)
from numerics.shooting.coupled_branch import CoupledContinuation, continue_coupled
from numerics.cycles.continuation import CycleContinuation, continue_cycles
from numerics.shooting.continuation import Continuation

RHS = "(-q + x**2 - x**4)*xdot"


@pytest.fixture(scope="module")
def folds():
    one = continue_cycles(custom_model(RHS), {"mu": 0.1, "q": 0.12}, "q", (0.12, 0.13))
    two = continue_coupled(coupled_custom(["(-q + x1**2 - x1**4)*xdot1"], [1.0]),
                           {"mu": 0.1, "q": 0.12}, "q", (0.12, 0.13))
    return one, two


def test_both_cases_are_the_one_driver_and_result(folds):
    assert issubclass(CycleContinuation, Continuation)
    assert issubclass(CoupledContinuation, Continuation)
    one, two = folds
    assert isinstance(one, OrbitBranch) and isinstance(two, OrbitBranch)


def test_the_fold_of_cycles_by_both_cases(folds):
    """The same fold from both branch problems (to the accuracy of the location), near the
    first-order KBM value 1/8."""
    one, two = folds
    (f1,) = one.folds()
    (f2,) = two.folds()
    assert f1.parameter == pytest.approx(f2.parameter, abs=1e-9)
    assert f1.parameter == pytest.approx(1 / 8, abs=0.1 * 1 / 8)
    assert f1.period == pytest.approx(f2.period, rel=1e-9)


_floats = st.floats(allow_nan=True, allow_infinity=True, width=64)


@settings(max_examples=50, deadline=None)
@given(p=_floats, x=_floats, re=_floats, im=st.floats(-2, 2).filter(lambda v: v != 0))
def test_the_renderings_keep_their_keys_and_strict_json(p, x, re, im):
    """Both layouts keep every key in its order; NaN and infinities become null, a real
    multiplier a number and a complex one [re, im]."""
    bp = BranchPoint(p, x, 6.28, x, (1 + 0j, complex(re, im)), True, 1e-12)
    sp = SpecialPoint("fold", p, x, 6.28, "m")
    br = Branch("m", "nu", (0.0, 1.0), (bp,), (sp,), ("r",), 3, params={"mu": 0.1})
    d = br.to_json()
    assert list(d) == ["model", "parameter", "params", "bounds", "points", "special",
                       "reasons", "evaluations", "dropped"]
    assert list(d["points"][0]) == ["parameter", "amplitude_max", "period", "stable",
                                    "multipliers", "x0", "residual"]
    assert list(d["special"][0]) == ["kind", "parameter", "amplitude", "period", "message"]
    assert d["params"] == {"mu": 0.1} and d["dropped"] == 0
    want = p if math.isfinite(p) else None
    assert d["points"][0]["parameter"] == want and d["special"][0]["parameter"] == want
    m = d["points"][0]["multipliers"]
    assert m[0] == 1.0 and m[1] == [re if math.isfinite(re) else None, im]
    cp = CoupledBranchPoint(p, 6.28, (x, 0.0), (1.0, 2.0), (1 + 0j, -0.5 + 0j), True, 0.0)
    cs = CoupledSpecialPoint("fold", p, 6.28, (1.0,), (1 + 0j,), (p, p), (x,))
    cb = CoupledBranch("m", "c", (0.0, 1.0), (cp,), (cs,), ("r",), 3, forced=False, dof=2)
    d = cb.to_json()
    assert list(d) == ["model", "parameter", "bounds", "forced", "dof", "points", "special",
                       "reasons", "evaluations"]
    assert list(d["points"][0]) == ["parameter", "period", "state", "amplitudes",
                                    "floquet_multipliers", "stable", "residual"]
    assert list(d["special"][0]) == ["kind", "parameter", "period", "amplitudes",
                                     "floquet_multipliers", "bracket", "state"]
    assert d["points"][0]["floquet_multipliers"] == [1.0, -0.5]
    assert d["points"][0]["state"] == [x if math.isfinite(x) else None, 0.0]
