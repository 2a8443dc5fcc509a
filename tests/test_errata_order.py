"""Same input, same bytes: the errata evidence does not depend on what ran before it.

:func:`numerics.paper.errata.errata_evidence` (the paper's eqs. 6-10 as printed, as the engine
corrects them, and on the true cycle) gave, before the derivations' compiled functions were
kept on the result, a "corrected" eq. 10 value for the paper's Fig. 3 case that depended in
its 17th digit on whether the small-Delta case ran first in the same process
(0.11242551688761435 after it, 0.11242551688761417 alone).

Where that state lives: sympy's global counter of ``Dummy`` symbols.
:func:`kbm.output.evaluate.numpy_function` stands a ``Dummy`` in for each infinite Bessel sum; a
``Dummy`` argument makes ``lambdify`` rename every argument ``Dummy_<counter>`` and print the
terms of a sum in the order of those names as strings, so the order in which the sums of
``u_2`` are added (``Dummy_97 + ... + Dummy_103`` against ``Dummy_100 + ... + Dummy_99``) follows
how many ``Dummy`` symbols the process had made before.  Running another case first moved the
counter across a power of ten.  Now each case's expansion is derived and compiled at the
same point of a fresh process whatever the order of the cases (the paper's derivation is one
constant, :func:`kbm.output.paper.engine_expansion`, its functions kept on it); the dependence of
``numpy_function`` on the counter itself is the last test (it failed, strictly, until
``kbm.output.evaluate`` named the sums' stand-ins and the summation indices with fixed names).
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

ROOT = Path(__file__).resolve().parents[1]

SCRIPT = """
import json, sys
from kbm.output.paper import ERRATA_CASES
from numerics.paper.errata import errata_evidence
rows = errata_evidence([ERRATA_CASES[int(i)] for i in sys.argv[1].split(",")])
for name, _ in ERRATA_CASES:
    print(json.dumps([r.to_json() for r in rows if r.case == name], sort_keys=True))
"""


def _evidence(order: str) -> subprocess.Popen:
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(
        [str(ROOT)] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p])}
    return subprocess.Popen([sys.executable, "-c", SCRIPT, order], cwd=ROOT, env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)


@pytest.mark.slow  # two processes, 10 s of CPU; in the default run: the test below, and
# tests/test_memo_purity.py (the values kept on a result, equal results compiled alike)
def test_errata_evidence_bytes_do_not_depend_on_the_order_of_the_cases():
    """The evidence of the paper's Fig. 3 case (paper eqs. 6-10: printed, corrected, true), in
    fresh processes, after the small-Delta case (as ``kbm compare --errata`` runs them) and
    alone: the same JSON bytes."""
    runs = [_evidence("0,1"), _evidence("1")]
    (both, err1), (alone, err2) = (p.communicate(timeout=600) for p in runs)
    assert [p.returncode for p in runs] == [0, 0], (err1 + err2).decode()[-2000:]
    both, alone = both.splitlines(), alone.splitlines()
    assert alone[0] == b"[]" and b'"equation": "10"' in alone[1]
    assert both[1] == alone[1]


def test_numpy_function_does_not_depend_on_sympys_dummy_counter():
    """``u_2`` of the paper's sedf expansion (seven infinite Bessel sums, eq. 9's corrected
    form) compiled with sympy's ``Dummy`` counter at different values, among them some at
    which the names of its arguments cross a power of ten: the same values, bit for bit."""
    from kbm.output import paper
    from kbm.output.evaluate import numpy_function

    res = paper.engine_expansion()
    args = (paper.a, paper.psi, *(sp.Symbol(p) for p in res.params))
    a = np.linspace(0.2, 2.5, 24)[:, None]
    psi = np.linspace(0.0, 2 * np.pi, 32, endpoint=False)[None, :]
    pars = [{"beta": 1.0, "delta": 15.0, "k": 2 * np.pi, "Omega": 1.0}[p] for p in res.params]

    def values() -> bytes:
        return numpy_function(res.u[2], args)(a, psi, *pars).tobytes()

    first = values()
    for below in range(6, 24, 3):  # the counter this far below the next power of ten
        power = 10 ** len(str(sp.Dummy._count + 100))
        sp.Dummy._count = power - below  # only ever forwards
        assert values() == first, below
