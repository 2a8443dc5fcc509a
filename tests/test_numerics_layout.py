"""The layout of :mod:`numerics` shows its architecture (issue 35): its folders are named
after the pieces (the flow, the one shooting and continuation code, locking, comparison, the
parameter layer of the command line, ...), none after a case of the model family (coupled
or forced systems are cases of the one ``2N``-dimensional code, not folders of their own),
and no module is longer than about 400 lines (the project's standard)."""

from __future__ import annotations

from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
NUMERICS = ROOT / "numerics"

#: the cases of the one model family that once had folders of their own
CASES = {"coupled", "forced"}

#: the project's standard: small modules, about 400 lines at most
MAX_LINES = 400


def _folders() -> list[Path]:
    return sorted(p.parent for p in NUMERICS.rglob("__init__.py"))


def test_no_folder_named_after_a_case():
    """No package of numerics is named ``coupled`` or ``forced``: their modules live in
    the pieces they are cases of (:mod:`numerics.flow`, :mod:`numerics.shooting`,
    :mod:`numerics.locking`, ...)."""
    bad = [str(p.relative_to(ROOT)) for p in _folders() if p.name in CASES]
    assert not bad, bad
    # a folder of modules without __init__.py (a namespace package); the __pycache__ a
    # checkout keeps of the old folders is no module
    stray = [str(p.relative_to(ROOT)) for p in NUMERICS.rglob("*") if p.is_dir()
             and p.name in CASES and any(p.glob("*.py"))]
    assert not stray, f"folders of modules without __init__.py: {stray}"


def test_every_module_at_most_400_lines():
    """Every module of numerics has at most :data:`MAX_LINES` lines."""
    long = {str(p.relative_to(ROOT)): n for p in sorted(NUMERICS.rglob("*.py"))
            if (n := len(p.read_text().splitlines())) > MAX_LINES}
    assert not long, f"modules longer than {MAX_LINES} lines: {long}"


def test_the_pieces_are_packages():
    """The pieces the issue names are packages of numerics, each with a docstring that
    lists its modules: the one shooting and continuation code (the acceptance standard, the
    continuation driver and the cases ``N`` coupled and forced), the locking, and the one
    parameter and option layer of the command line."""
    pieces = {
        "shooting": ("acceptance", "orbit", "continuation", "arclength", "coupled_orbit",
                     "coupled_branch", "forced_orbit", "forced_branch", "planar"),
        "flow": ("coupled_flow", "forced_system"),
        "locking": ("mutual", "start", "fold", "slow_flow", "entrainment"),
        "cli/params": ("values", "options", "forced", "plane"),
    }
    for folder, modules in pieces.items():
        init = NUMERICS / folder / "__init__.py"
        assert init.is_file(), folder
        doc = init.read_text()
        dotted = "numerics." + folder.replace("/", ".")
        for m in modules:
            assert (NUMERICS / folder / f"{m}.py").is_file(), (folder, m)
            assert f"{dotted}.{m}" in doc, f"{init.relative_to(ROOT)} does not list {m}"
