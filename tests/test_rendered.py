"""The one JSON layer of results (:mod:`kbm.output.strict_json`, issue 35): its rules give strict
JSON that reads back to itself, and :class:`~kbm.output.strict_json.Rendered` renders the branch
records (numerics.shooting.branch_result) by their layouts."""

from __future__ import annotations

import json
from dataclasses import dataclass

import numpy as np
from hypothesis import given
from hypothesis import strategies as st

from kbm.output.strict_json import Rendered, json_fields, jsonable
from numerics.shooting.branch_result import Branch, BranchPoint, SpecialPoint

_floats = st.floats(allow_nan=True, allow_infinity=True)
_leaves = st.one_of(_floats, st.integers(-10**6, 10**6), st.text(max_size=5), st.booleans(),
                    st.none(), st.complex_numbers(allow_nan=False, allow_infinity=False,
                                                  max_magnitude=1e6))
_values = st.recursive(_leaves, lambda inner: st.one_of(
    st.lists(inner, max_size=4), st.lists(inner, max_size=4).map(tuple),
    st.dictionaries(st.one_of(st.text(max_size=4), st.integers(0, 9)), inner, max_size=4),
    st.lists(_floats, max_size=4).map(np.array)), max_leaves=20)


@given(_values)
def test_jsonable_is_strict_json_that_reads_back_to_itself(value):
    """No NaN or infinity survives (``allow_nan=False`` accepts the dump), and the dump reads
    back to the same value: every mapping key a string, every sequence a list."""
    out = jsonable(value)
    assert json.loads(json.dumps(out, allow_nan=False)) == out
    assert jsonable(out) == out


_point = st.builds(BranchPoint, _floats, _floats, _floats, _floats,
                   st.tuples(st.complex_numbers(allow_nan=False, allow_infinity=False),
                             st.complex_numbers(allow_nan=False, allow_infinity=False)),
                   st.booleans(), _floats)


def _reference(value):
    """The branch records' JSON rules written out here (the reference): a mapping as floats by
    sorted key, a real multiplier a number and a complex one ``[re, im]``, NaN as None."""
    if isinstance(value, dict):
        return {k: _reference(float(v)) for k, v in sorted(value.items())}
    if isinstance(value, (tuple, list)):
        return [_reference(v) for v in value]
    if isinstance(value, complex):
        return _reference(value.real) if value.imag == 0 else [value.real, value.imag]
    if isinstance(value, float) and not np.isfinite(value):
        return None
    return value


@given(st.lists(_point, max_size=3),
       st.dictionaries(st.sampled_from(["mu", "beta", "Delta", "c"]), _floats))
def test_rendered_renders_a_branch_in_its_layouts(points, params):
    """Branch, BranchPoint and SpecialPoint (numerics.shooting.branch_result) through
    kbm.output.strict_json.Rendered give their layouts' keys in order, by the rules written out in
    :func:`_reference` (mappings as floats by sorted key, multipliers as numbers or pairs)."""
    special = (SpecialPoint("fold", 0.5, float("nan"), 6.3, "bisected"),)
    br = Branch("m", "nu", (0.0, 1.0), tuple(points), special, ("end",), 7, params=params)
    out = br.to_json()
    assert list(out) == list(Branch.layout)
    assert json.dumps(out["params"]) == json.dumps(_reference(dict(params)))
    for pt, got in zip(points, out["points"]):
        assert list(got) == list(BranchPoint.layout)
        want = {k: _reference(getattr(pt, k)) for k in BranchPoint.layout}
        assert json.dumps(got) == json.dumps(want)
    assert out["special"] == [{"kind": "fold", "parameter": 0.5, "amplitude": None,
                               "period": 6.3, "message": "bisected"}]


def test_an_empty_layout_is_every_field_and_mappings_as_given_keep_their_order():
    @dataclass
    class Record(Rendered):
        params: dict
        window: tuple
        note: str = ""
        mappings_as_given = True

    r = Record({"mu": 1, "Delta": float("inf")}, (np.float64(0.5), 2))
    assert r.to_json() == {"params": {"mu": 1, "Delta": None}, "window": [0.5, 2], "note": ""}
    assert json_fields(r, "window", extra=1) == {"window": [0.5, 2], "extra": 1}
