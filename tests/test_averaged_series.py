"""kbm.slowflow.averaged (numerical cycles of the averaged equations), kbm.slowflow.series (their
exact mu-series), the internal entry kbm.expansion.one_dof.run_recursion, and the errors they
raise: each condition its own kbm error, every message in API terms (no command-line flags)."""

from __future__ import annotations

import re

import pytest
import sympy as sp

from kbm import (AveragedRates, KBMError, KBMResult, OrderError, ParameterError,
                 averaged_cycles, averaged_rates, custom_model, derive, limit_cycle_series)
from kbm.expansion.one_dof import RawExpansion, run_recursion
from kbm.errors import AveragedCycleError, ExpansionError, SeriesTruncationError
from kbm.symbols import a, psi

CLI_FLAG = re.compile(r"(^|\s|\()--[a-z]")


def _message(excinfo) -> str:
    msg = str(excinfo.value)
    assert not CLI_FLAG.search(msg), msg
    return msg


# ----------------------------------------------------------------------------- run_recursion
def test_run_recursion_is_derive_before_display():
    """run_recursion gives the algebra's own coefficients; displayed, they are derive()'s."""
    raw = run_recursion("vdp", 3)
    assert isinstance(raw, RawExpansion) and raw.exact and raw.order == 3
    assert len(raw.A) == len(raw.B) == len(raw.u) == 3
    res = derive("vdp", 3)
    for n in range(1, 4):
        assert raw.algebra.coef_expr(raw.A[n - 1]) == res.A[n]
        assert raw.algebra.series_expr(raw.u[n - 1]) == res.u[n]
    assert len(run_recursion("vdp", 3, last_u=False).u) == 2
    assert not run_recursion("sedf", 1).exact


# ----------------------------------------------------------------------------- averaged
def test_averaged_rates_reuse_and_order():
    rates = averaged_rates(derive("vdp", 2), order=1)
    assert isinstance(rates, AveragedRates) and rates.order == 1
    (c,) = rates.cycles({"mu": 0.2})
    assert c.amplitude == pytest.approx(2.0, abs=1e-12) and c.stable
    with pytest.raises(OrderError):
        averaged_rates(derive("vdp", 2), order=3)


def test_averaged_cycles_parameter_errors_speak_api():
    res = derive(custom_model("(1 - beta*x**2)*xdot"), 1)
    with pytest.raises(ParameterError) as e:
        averaged_cycles(res, {"mu": 0.1})
    assert "values={'beta': 1}" in _message(e)
    with pytest.raises(ParameterError, match="mu"):
        averaged_cycles(res, {"beta": 1})
    with pytest.raises(ParameterError, match="unknown parameter"):
        averaged_cycles(res, {"mu": 0.1, "beta": 1, "gamma": 2})


def test_averaged_cycles_not_finite_is_a_parameter_error():
    res = derive(custom_model("(1 - x**2/c)*xdot"), 1)
    with pytest.raises(ParameterError, match="not finite") as e:
        averaged_cycles(res, {"mu": 0.1, "c": 0})
    _message(e)


# ----------------------------------------------------------------------------- series
def test_series_order_zero_is_the_first_order_cycle():
    s = limit_cycle_series("vdp", 0)
    assert s.amplitude == (2,) and s.omega == (1,)


@pytest.mark.parametrize("model, kwargs, error, needle", [
    ("duffing", {}, AveragedCycleError, "A_1 = 0"),
    (custom_model("(64 - 80*x**2 + 8*x**4)*xdot"), {}, AveragedCycleError, "2 positive roots"),
    (custom_model("(1 - x**2)**2*xdot"), {}, AveragedCycleError, "has no positive root"),
    (custom_model("(1 - beta*x**2)*xdot"), {}, ParameterError, "substitute({'beta': 1})"),
    ("vdp", {"root": 3}, ParameterError, "not a root"),
    ("sedf", {}, OrderError, "polynomial"),
])
def test_series_errors(model, kwargs, error, needle):
    with pytest.raises(error) as e:
        limit_cycle_series(model, 2, **kwargs)
    assert needle in _message(e)


def test_series_non_hyperbolic_cycle():
    """F = (16 - 32 x^2 + 8 x^4) x': A_1 = a (a^2 - 4)^2/2 has the double root a0 = 2,
    where A_1'(a0) = 0."""
    model = custom_model("(16 - 32*x**2 + 8*x**4)*xdot")
    assert sp.factor(derive(model, 1).A[1]) == a * (a - 2)**2 * (a + 2)**2 / 2
    with pytest.raises(AveragedCycleError, match="not hyperbolic") as e:
        limit_cycle_series(model, 2)
    _message(e)


def test_series_with_given_root_and_parameters_substituted():
    s = limit_cycle_series("vdp", 2, root=2)
    assert s.omega == (1, 0, sp.Rational(-1, 16))
    s = limit_cycle_series(custom_model("(1 - beta*x**2)*xdot").substitute({"beta": 4}), 2)
    assert s.amplitude[0] == 1


# ----------------------------------------------------------------------------- result errors
def test_kbm_result_invariants_raise_a_kbm_error():
    res = derive("vdp", 1)
    with pytest.raises(ExpansionError, match="order \\+ 1"):
        KBMResult(model=res.model, order=2, A=res.A, B=res.B, u=res.u)
    with pytest.raises(ExpansionError, match="first harmonic"):
        KBMResult(model=res.model, order=1, A=res.A, B=res.B, u=(res.u[0], a * sp.cos(psi)))
    with pytest.raises(ValueError):  # still a ValueError for callers that catch that
        KBMResult(model=res.model, order=2, A=res.A, B=res.B, u=res.u)


def test_unknown_backend_is_a_parameter_error():
    with pytest.raises(ParameterError, match="backend"):
        derive("vdp", 1).functions("torch")


def test_every_error_is_a_kbm_error():
    for cls in (AveragedCycleError, ExpansionError, SeriesTruncationError):
        assert issubclass(cls, KBMError)
    import kbm
    assert kbm.SeriesTruncationError is SeriesTruncationError
