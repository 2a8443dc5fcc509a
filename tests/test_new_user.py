"""What a new user meets on the command line (issue 24): series in ascending powers, a
version, help texts that list what exists, grammatical messages."""

from __future__ import annotations

import re

import pytest

from kbm.model.builtins import model_names
from numerics.cli import main


def _out(argv, capsys):
    try:
        code = main(argv)
    except SystemExit as exc:
        code = exc.code
    out = capsys.readouterr()
    return code, out.out, out.err


def test_series_prints_ascending_powers_of_mu(capsys):
    """van der Pol's frequency 1 - mu^2/16 + 17 mu^4/3072 + ... (Andersen & Geer 1982) is
    printed as a series is read, lowest power first."""
    code, out, _ = _out(["series", "vdp", "--order", "6"], capsys)
    assert code == 0
    line = out.splitlines()[0]
    assert line.startswith("omega* = 1 - mu**2/16 + 17*mu**4/3072")
    powers = [int(p) for p in re.findall(r"mu\*\*(\d+)", line)]
    assert powers == sorted(powers)


def test_float_series_header_names_the_powers_of_mu(capsys):
    code, out, _ = _out(["series", "vdp", "--order", "10", "--float"], capsys)
    assert code == 0
    assert "mu**2^k" not in out
    assert "c_0, c_2, c_4, ... (odd powers vanish) = 1.0, -6.25e-2" in out


def test_version(capsys):
    code, out, _ = _out(["--version"], capsys)
    assert code == 0 and re.fullmatch(r"kbm \S+\n", out)


def test_derive_help_lists_every_built_in_model(capsys):
    code, out, _ = _out(["derive", "--help"], capsys)
    text = " ".join(out.split())
    for name in model_names():
        assert name in text


def test_figures_help_has_a_description(capsys):
    _, out, _ = _out(["figures", "--help"], capsys)
    assert "Write the paper's Figs." in " ".join(out.split())


@pytest.mark.parametrize("argv", [["cycle", "vdp"]])
def test_missing_values_message_is_grammatical(argv, capsys):
    code, _, err = _out(argv, capsys)
    assert code == 2
    assert "model 'vdp' needs values for mu" in err and "functions needs" not in err


def test_result_objects_print_in_one_short_line():
    """Issue 24 item 9: ``print(limit_cycle(...))`` dumped ~3 KB of sample arrays.  The
    cycle, a sweep point, a comparison and its predictions, a friction point and map print
    in one line of a few hundred characters, and a notebook gets an HTML table."""
    import numerics
    from numerics.sliding.maps import friction_map

    cyc = numerics.limit_cycle("vdp", {"mu": 1})
    assert cyc.x.size >= 512
    text = repr(cyc)
    assert len(text) < 200 and "\n" not in text
    assert f"T={cyc.period:.10g}" in text and "stable" in text
    assert cyc._repr_html_().startswith("<table>")
    comp = numerics.compare("vdp", {"mu": 0.1})
    fmap = friction_map("cdc", {"Delta": 3, "mu": 0.1, "lam": 1}, {"v": [0.5, 1.0]},
                        workers=1, progress=False)
    swept = numerics.sweep("vdp", numerics.grid(mu=[0.5]), workers=1)[0]
    for obj in (comp, comp.predictions[0], fmap, fmap.points[0], swept):
        text = repr(obj)
        assert len(text) < 300 and "\n" not in text and "array(" not in text, text


def test_comparison_table_columns_never_run_together():
    """Issue 24 item 8: ``0.002160121066 ( 1.7e-03)-0.0001828501289 ( 1.5e-04)`` — a long
    negative value touched the previous column.  Every entry is now separated by at least
    two spaces, whatever its length."""
    import numerics

    table = numerics.compare("sedf", {"mu": 0.05, "Delta": 0.1, "beta": 1, "lam": 1},
                             orders=(1, 2)).table()
    body = table.splitlines()[2:-2]
    assert body and not any(re.search(r"\)\S", line) for line in body), table


def test_reproduce_prints_one_screen_not_the_whole_summary():
    from numerics.paper.reproduce import screen_summary

    summary = ["# kbm", "", "## Errata", *["row"] * 300, "## The paper's claims", "", "x"]
    claims = "| claim | paper | measured | verdict |\n|---|---|---|---|\n| A | b | c | holds |\n"
    text = screen_summary(summary, claims)
    assert len(text.splitlines()) < 15 and "Errata" in text and "A: holds" in text


def test_classical_kbm_far_outside_its_range_says_so(capsys):
    """Issue 24 item 2: at the paper's strong potential (mu = 0.1, Delta = 3) order-2 KBM
    lists 12 cycles (the true dynamics has one, ``kbm cycle --all``) with multipliers up
    to 1e100.  Each carries its term size (corrections against leading terms) and the list
    a warning; at Delta = 0.1, where KBM is right to 1e-4, neither."""
    import json

    from numerics.comparison.predict import KBM_TERM_LIMIT

    strong = ["predict", "sedf", "-p", "mu=0.1", "-p", "Delta=3", "-p", "beta=1", "-p", "lam=1",
              "--order", "2", "--method", "kbm"]
    code, out, _ = _out(strong + ["--json"], capsys)
    data = json.loads(out)
    assert code == 0 and data["method"] == "classical KBM"
    assert len(data["cycles"]) == 12 and "outside its range for 12 of 12" in data["warning"]
    assert all(c["term_size"] > KBM_TERM_LIMIT for c in data["cycles"])
    assert data["params_given"] == {"mu": "0.1", "Delta": "3", "beta": "1", "lam": "1"}
    code, text, _ = _out(strong, capsys)
    assert "WARNING: classical KBM is outside its range" in text
    assert "Delta=3" in text and "delta = Delta/mu = 30" in text and "k = 2*pi/lam" in text
    weak = ["predict", "sedf", "-p", "mu=0.1", "-p", "Delta=0.1", "-p", "beta=1", "-p",
            "lam=1", "--order", "2", "--method", "kbm", "--json"]
    code, out, _ = _out(weak, capsys)
    data = json.loads(out)
    assert "warning" not in data and data["cycles"][0]["term_size"] < KBM_TERM_LIMIT


def test_cycle_output_speaks_in_the_users_names_and_states_eq_11(capsys):
    code, out, _ = _out(["cycle", "sedf", "-p", "mu=0.1", "-p", "Delta=1.5", "-p", "beta=1.3",
                         "-p", "lam=1"], capsys)
    assert code == 0
    assert out.startswith("limit cycle of sedf (mu=0.1, Delta=1.5, beta=1.3, lam=1; derived: "
                          "delta = Delta/mu = 15")
    assert "= 1.3 Gamma+ - Gamma- (eq. 11;" in out
