"""The guide's "no hidden global state, no caches that change results" (issue 35), checked.

- Every process-wide memo of ``kbm/`` (``functools.lru_cache``/``cache``, found by scanning
  the source) is listed here and documented as a pure-function memo; a representative run
  (the paper's corrected formulas, an exact coupled derivation, a forced 1:3 jet expansion)
  calls each one, and for every call its arguments are immutable values, its value is
  immutable, and the cached value equals a fresh computation, bit for bit.
- What is computed from one :class:`kbm.KBMResult` (its compiled functions, its averaged
  rates, the paper's corrected formulas) is kept on that result, outside its fields: equality,
  hash, repr, ``to_json``, pickling and ``dataclasses.replace`` do not see it, and two equal
  results compile their own functions (no process-wide cache), to the same bits.
- numerics' memos of derivations (``prediction.derived``, the bifurcation kit's
  ``_derivatives``) give what a fresh call gives.
"""

from __future__ import annotations

import ast
import copy
import dataclasses
import importlib
import inspect
import pickle
import types
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

import kbm
from kbm import averaged_rates, derive
from kbm.parameters.values import FrozenMap

KBM = Path(kbm.__file__).parent

#: every process-wide memo of kbm/: (module, name) -> why its cached value cannot differ
#: from a fresh one (each also says "Pure-function memo" in its docstring)
MEMOS = {
    ("kbm.algebra.multi_angle", "_sum_difference"): "integer tuples to integer tuples",
    ("kbm.backend.jets", "_lattice"): "frozen resonances to a lattice with its own pure memo",
    ("kbm.backend.jets", "_slow_terms"): "integer tuples to read-only arrays",
    ("kbm.backend.jets", "_table"): "an expression to a table with its own pure memo",
    ("kbm.backend.jets", "symbolic_rhs"): "a frozen model to tuples of expressions",
    ("kbm.algebra.coupled_jets", "torus"): "integers to read-only arrays",
    ("kbm.algebra.coupled_jets", "_harmonics"): "frequencies to read-only arrays",
    ("kbm.algebra.coupled_jets", "_mode_table"): "frequencies, resonances to read-only arrays",
    ("kbm.expansion.resonance", "_independent"): "integer tuples to a bool",
    ("kbm.expansion.resonance", "_coords"): "integer tuples to integer tuples or None",
    ("kbm.output.paper", "engine_expansion"):
        "no argument: the fixed derivation of the built-in sedf",
}

#: values that hold a memo of their own, a function of what they were built from (their
#: answers are compared below, not their internal dictionaries)
SELF_MEMOISING = ("SlowLattice", "TaylorTable")


def _is_cache(node: ast.expr) -> bool:
    if isinstance(node, ast.Call):
        node = node.func
    name = node.attr if isinstance(node, ast.Attribute) else getattr(node, "id", None)
    return name in ("lru_cache", "cache")


def _scan() -> set[tuple[str, str]]:
    """``(module, name)`` of every function of kbm/ memoised by ``functools``."""
    found = set()
    for path in sorted(KBM.rglob("*.py")):
        module = ".".join(path.relative_to(KBM.parent).with_suffix("").parts)
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                if any(_is_cache(d) for d in node.decorator_list):
                    found.add((module, node.name))
            elif isinstance(node, ast.Assign) and isinstance(node.value, ast.Call):
                if _is_cache(node.value.func) or _is_cache(node.value):
                    found.update((module, t.id) for t in node.targets
                                 if isinstance(t, ast.Name))
    return found


def test_every_kbm_memo_is_listed_and_documented_as_pure():
    assert _scan() == set(MEMOS)
    for module, name in MEMOS:
        fn = getattr(importlib.import_module(module), name)
        assert hasattr(fn, "cache_info") and hasattr(fn, "__wrapped__"), (module, name)
        assert "Pure-function memo" in " ".join((fn.__doc__ or "").split()), (module, name)


def _immutable(v) -> bool:
    """Whether ``v`` cannot be changed in place (numbers, strings, sympy's immutable
    objects, read-only arrays, and tuples, frozensets, read-only mappings (``FrozenMap``, the
    models' hashable mapping) and frozen dataclasses of them)."""
    if v is None or isinstance(v, (bool, int, float, complex, str, bytes, np.generic)):
        return True
    if isinstance(v, sp.MatrixBase):
        return isinstance(v, sp.ImmutableMatrix)
    if isinstance(v, sp.Basic):
        return True
    if isinstance(v, np.ndarray):
        return not v.flags.writeable and v.dtype != object
    if isinstance(v, (tuple, frozenset)):
        return all(_immutable(x) for x in v)
    if isinstance(v, (types.MappingProxyType, FrozenMap)):
        return all(_immutable(k) and _immutable(x) for k, x in v.items())
    if dataclasses.is_dataclass(v) and v.__dataclass_params__.frozen:
        return all(_immutable(getattr(v, f.name)) for f in dataclasses.fields(v))
    return type(v).__name__ in SELF_MEMOISING


def _same(x, y) -> bool:
    """Equal values, arrays to the bit; a lattice or a table by its answers."""
    if type(x) is not type(y):
        return False
    if isinstance(x, np.ndarray):
        return x.shape == y.shape and x.dtype == y.dtype and x.tobytes() == y.tobytes()
    if isinstance(x, (tuple, list)):
        return len(x) == len(y) and all(_same(a, b) for a, b in zip(x, y))
    if type(x).__name__ == "SlowLattice":
        ks = [(1, -1), (3, -1), (2, 0), (1, -3), (0, 0)]
        ks = [k + (0,) * (x.dof - 2) for k in ks]
        return x.generators == y.generators and [x.coords(k) for k in ks] == [
            y.coords(k) for k in ks]
    if type(x).__name__ == "TaylorTable":
        n = len(x.variables)
        betas = [(0,) * n] + [tuple(int(i == j) * m for i in range(n))
                              for j in range(n) for m in (1, 2)]
        return (x.F == y.F and x.variables == y.variables and x.extra == y.extra
                and all(x.expr(*b) == y.expr(*b) for b in betas))
    return x == y


@pytest.fixture
def recorded(monkeypatch):
    """The arguments of every call of each memo of :data:`MEMOS` during a representative run:
    the paper's corrected eq. 6 (the order-2 sedf expansion), the exact order-2 coupled van
    der Pol expansion (multi-angle Fourier series) and the order-2 jets of the forced 1:3
    Duffing pair (every memo of the numeric coupled backend)."""
    calls: dict = {key: [] for key in MEMOS}
    for (module, name) in MEMOS:
        mod = importlib.import_module(module)
        memo = getattr(mod, name)

        def spy(*args, _memo=memo, _key=(module, name)):
            calls[_key].append(args)
            return _memo(*args)
        spy.__wrapped__ = memo  # type: ignore[attr-defined]
        monkeypatch.setattr(mod, name, spy)
    from kbm.output import paper
    from kbm.expansion.coupled import derive_coupled
    from kbm.model.coupled_builtins import get_coupled_model
    from kbm.backend.jets import jet_expansion

    paper.corrected("6")
    derive_coupled(get_coupled_model("coupled-vdp"), 2)
    vals = {"zeta1": 0.1, "zeta2": 0.2, "alpha1": 1, "alpha2": 0.5, "k": 1.5, "h": 2,
            "sigma": 0.3}
    jet_expansion(get_coupled_model("duffing-1-3"), vals, 2, (0.8, 0.5), (0.3, 0.2))
    return calls


def test_kbm_memos_are_pure_functions_of_immutable_arguments(recorded):
    for (module, name), calls in recorded.items():
        assert calls, f"{module}.{name} was not called by the representative run"
        memo = getattr(importlib.import_module(module), name)
        seen = []
        for args in calls:
            if args in seen:
                continue
            seen.append(args)
            assert _immutable(args), (module, name, args)
            cached = memo(*args)
            assert memo(*args) is cached, (module, name)
            assert _immutable(cached), (module, name)
            assert _same(cached, memo.__wrapped__(*args)), (module, name, args)
            if len(seen) == 3:
                break


def _lambdified_source(f) -> str:
    return inspect.getsource(f)


def test_numerics_derivation_memos_equal_a_fresh_call():
    """``numerics.comparison.prediction.derived`` (kbm.derive; the paper's sedf to order 2 the
    errata's object) and the bifurcation kit's ``_derivatives`` (the derivatives of the
    acceleration): a cached value equals a fresh one, the functions with the same code."""
    from numerics.bifurcation import autonomous
    from numerics.comparison import prediction
    from numerics.flow import model_template

    res = prediction.derived("vdp", 2)
    assert prediction.derived(kbm.get_model("vdp"), 2) is res
    assert res == derive("vdp", 2)
    assert prediction.derived("sedf", 2) is importlib.import_module(
        "kbm.output.paper").engine_expansion()
    tpl = model_template("sedf")
    d, f_rest, odd = autonomous._derivatives(tpl.model, tpl.names)
    d2, f_rest2, odd2 = autonomous._derivatives.__wrapped__(tpl.model, tpl.names)
    assert isinstance(d, types.MappingProxyType) and odd is odd2 is True
    assert d.keys() == d2.keys()
    for key in d:
        assert _lambdified_source(d[key]) == _lambdified_source(d2[key])
    assert _lambdified_source(f_rest) == _lambdified_source(f_rest2)


# -- values kept on a result ----------------------------------------------------------------
def test_a_results_computed_values_stay_outside_its_fields():
    """The compiled functions and averaged rates live on the result: a second call gives the
    same object; ``==``, ``hash``, ``repr``, ``to_json``, pickling, copying and
    ``dataclasses.replace`` see only the fields."""
    res = derive("vdp", 2)
    before = (repr(res), hash(res), res.to_json(), pickle.dumps(res))
    fns, rates = res.functions("numpy"), averaged_rates(res, order=1)
    assert res.functions("numpy") is fns and averaged_rates(res, order=1) is rates
    assert res.functions("mpmath") is not fns and averaged_rates(res) is not rates
    assert (repr(res), hash(res), res.to_json(), pickle.dumps(res)) == before
    again = pickle.loads(pickle.dumps(res))
    assert again == res and "_computed" not in vars(again)
    assert "_computed" not in vars(copy.deepcopy(res))
    assert "_computed" not in vars(dataclasses.replace(res))
    assert not hasattr(type(res), "__slots__")


def test_equal_results_compile_their_own_functions_to_the_same_bits():
    """No process-wide cache: two equal derivations each compile their functions (the
    functions of one are not the other's), and they agree to the bit (van der Pol to order 3:
    the limit cycle a = 2 of every order's averaged equation)."""
    r1, r2 = derive("vdp", 3), derive("vdp", 3)
    assert r1 == r2 and r1 is not r2
    f1, f2 = r1.functions("numpy"), r2.functions("numpy")
    assert f1 is not f2
    a, psi = np.linspace(0.1, 3.0, 11), np.linspace(0.0, 6.0, 11)
    for name in ("amplitude_rate", "phase_rate"):
        v1, v2 = getattr(f1, name)(a, 0.2), getattr(f2, name)(a, 0.2)
        assert v1.tobytes() == v2.tobytes()
    assert f1.displacement(a, psi, 0.2).tobytes() == f2.displacement(a, psi, 0.2).tobytes()
    assert averaged_rates(r1) is not averaged_rates(r2)
    (c1,), (c2,) = (averaged_rates(r, order=1).cycles({"mu": 0.2}) for r in (r1, r2))
    assert c1 == c2 and abs(c1.amplitude - 2.0) < 1e-12
