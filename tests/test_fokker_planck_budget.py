"""``kbm escape --fp-budget`` bounds every solve of the escape rate's ladders (issue 35).

The Hermite and Chebyshev ladders (:func:`numerics.fokker_planck._ladder.
hermite_chebyshev_ladder`) are driven here by a rate that never converges
(``1 + 1/n + 1/nc``, so that they climb as far as the budget lets them): no solve may cost
more than the budget, and a budget below the first two rungs or the first grid check is
refused before anything is solved.  On the command line the refusal is one line with the
costs, exit status 2, in about a second (no Kramers solve runs).
"""

from __future__ import annotations

import re

import pytest

from numerics.cli import main
from numerics.errors import BudgetError
from numerics.fokker_planck._ladder import budget_to_give, hermite_chebyshev_ladder
from numerics.fokker_planck._problem import hermite_ladder


def _climb(budget: float) -> tuple[list, dict]:
    solved: list = []

    def solve(n, nc, sharp=1):
        solved.append((n, nc))
        return 1.0 + 1.0 / n + 1.0 / nc

    def cost(n, nc):
        return n * nc * nc

    out = hermite_chebyshev_ladder(solve, hermite_ladder, lambda n, nc: cost(n, nc) <= budget,
                                   start=16, n_cheb=100, tol=1e-12, max_hermite=4096,
                                   max_cheb=720, cost=cost, budget=budget)
    return solved, out


def test_no_solve_exceeds_the_budget():
    """Before the bound, two of the twelve solves went over a budget of 1.5e6: 128 functions
    on 120 intervals (1.84e6) and the finer grid's forced rung, 90 on 144 (1.87e6)."""
    budget = 1.5e6
    solved, out = _climb(budget)
    assert max(n * nc * nc for n, nc in solved) <= budget
    assert len(solved) > 4 and out["chebyshev_error"] > 0  # it climbed, and says how far


def test_first_rungs_above_the_budget_are_refused_before_solving():
    """16 and 22 functions on 100 intervals, the grid's check 16 on 120: 2.3e5 at most."""
    with pytest.raises(BudgetError, match=r"cost 2\.3e\+05 at least .* above --fp-budget "
                                          r"2e\+05; raise --fp-budget to 2\.4e\+05"):
        _climb(2e5)
    solved, _ = _climb(2.4e5)
    assert solved


def test_budget_to_give_is_never_below_the_cost():
    for cost in (1.07e6, 1.04e6, 1e6, 9.99e6, 123.0, 29999999.0):
        assert cost <= float(budget_to_give(cost)) <= 1.1 * cost


def test_kbm_escape_refuses_a_small_budget_in_one_line(capsys):
    """The CDC at mu = 0.02 (folded orthonormal functions: 2 n (nc/2 + 1)^2 numbers, a third
    of them the cost) needs 64 x 315 points for its first grid check, 1.07e6."""
    argv = ["escape", "cdc", "-p", "mu=0.02", "-p", "Delta=3", "-p", "D=0.007", "--method",
            "fokker-planck", "--no-simulation", "--fp-budget", "1e5"]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    assert "above --fp-budget 1e+05; raise --fp-budget to 1.1e+06 or more" in err[0], err[0]
    for n, points, said in re.findall(r"(\d+) x (\d+) \(([0-9.e+]+)\)", err[0]):
        nc = int(points) - 1
        assert float(said) == pytest.approx(2 * int(n) * (nc // 2 + 1) ** 2 / 3, rel=5e-3)
