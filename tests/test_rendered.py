"""The one JSON layer of results (:mod:`kbm.strict_json`, issue 35): its rules give strict JSON
that reads back to itself, and :class:`~kbm.strict_json.Rendered` renders a result as the
branch records' own layout renderer does (numerics.shooting.branch_result), so that one can
become the other."""

from __future__ import annotations

import json
from dataclasses import dataclass

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from kbm.strict_json import Rendered, complex_json, json_fields, jsonable
from numerics.shooting import branch_result
from numerics.shooting.branch_result import Branch, BranchPoint, SpecialPoint
from numerics.shooting.orbit import multiplier_json

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


@given(st.complex_numbers(allow_nan=False, allow_infinity=False))
def test_complex_json_is_the_multipliers_rendering(z):
    assert complex_json(z) == multiplier_json(z)


_point = st.builds(BranchPoint, _floats, _floats, _floats, _floats,
                   st.tuples(st.complex_numbers(allow_nan=False, allow_infinity=False),
                             st.complex_numbers(allow_nan=False, allow_infinity=False)),
                   st.booleans(), _floats)


@given(st.lists(_point, max_size=3),
       st.dictionaries(st.sampled_from(["mu", "beta", "Delta", "c"]), _floats))
def test_rendered_renders_a_branch_as_the_branch_layouts_do(points, params):
    """Branch, BranchPoint and SpecialPoint through kbm.strict_json's rules give the JSON of
    their own to_json (mappings as floats by sorted key, multipliers by multiplier_json)."""
    special = (SpecialPoint("fold", 0.5, float("nan"), 6.3, "bisected"),)
    br = Branch("m", "nu", (0.0, 1.0), tuple(points), special, ("end",), 7, params=params)
    theirs = json.dumps(br.to_json())
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(branch_result.Rendered, "to_json", Rendered.to_json)
        mp.setattr(branch_result.Rendered, "mappings_as_given", False, raising=False)
        assert json.dumps(br.to_json()) == theirs


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
