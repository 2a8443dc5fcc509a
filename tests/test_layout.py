"""The layout of ``kbm`` shows its architecture (issue 35): its folders are named after the
pieces (the model family, the parameter layer, the expansion with its one recursion, the
algebras, the numeric backend, what is done with a slow flow, noise, output, the command
line), not after cases (coupled, forced); no module is longer than about 400 lines; the
top level holds only the package's entry and what every piece shares.  A store of finished
points written before a move refuses to resume with a message that says what to do.
"""

from __future__ import annotations

import ast
import pickle
from pathlib import Path

import pytest

from numerics.store import PointStore, StoreError

KBM = Path(__file__).resolve().parents[1] / "kbm"

#: the folders of kbm, named after the pieces of the toolkit
PIECES = {"model", "parameters", "expansion", "algebra", "backend", "slowflow", "noise",
          "output", "cli"}

#: the modules kept at the top level: the entry, the lazy names, the version, the
#: exceptions and the symbols every piece uses
TOP_LEVEL = {"__init__.py", "_lazy.py", "_version.py", "errors.py", "symbols.py"}

#: the cases the folders are not named after
CASES = {"coupled", "forced", "one_dof", "oscillator", "oscillators"}

MAX_LINES = 400


def _folders() -> list[Path]:
    return sorted(p for p in KBM.rglob("*") if p.is_dir() and p.name != "__pycache__")


def test_no_folder_is_named_after_a_case():
    named = [str(p.relative_to(KBM)) for p in _folders() if p.name in CASES]
    assert not named, f"folders named after a case: {named}"


def test_the_folders_are_the_pieces():
    top = {p.name for p in KBM.iterdir() if p.is_dir() and p.name != "__pycache__"}
    assert top == PIECES
    nested = [str(p.relative_to(KBM)) for p in _folders() if p.parent != KBM]
    assert not nested, f"folders below the pieces: {nested}"


def test_the_top_level_holds_only_what_every_piece_shares():
    assert {p.name for p in KBM.glob("*.py")} == TOP_LEVEL


def test_no_module_is_longer_than_400_lines():
    long = {str(p.relative_to(KBM)): n for p in sorted(KBM.rglob("*.py"))
            if (n := len(p.read_text(encoding="utf-8").splitlines())) > MAX_LINES}
    assert not long, f"modules over {MAX_LINES} lines: {long}"


@pytest.mark.parametrize("piece", sorted(PIECES - {"cli"}))
def test_each_piece_lists_its_modules(piece):
    """A package's docstring names each of its modules (the map of the layout)."""
    doc = ast.get_docstring(ast.parse((KBM / piece / "__init__.py").read_text())) or ""
    missing = [p.stem for p in sorted((KBM / piece).glob("*.py"))
               if p.name != "__init__.py" and f"kbm.{piece}.{p.stem}`" not in doc]
    assert not missing, f"kbm.{piece}'s docstring does not name {missing}"


def test_a_store_written_before_a_move_asks_for_a_new_run(tmp_path):
    """A chunk pickled with a class at a module path that is gone (``kbm.strict_json``, moved
    to ``kbm.output.strict_json``) is a StoreError saying to run again, not a traceback."""
    path = tmp_path / "points.sqlite"
    with PointStore(path) as store:
        store.run("a run", 1).save(0, [1.0])
        # protocol 0 by hand: a global of the old module path, as an old pickle holds it
        store._db.execute("UPDATE chunks SET payload = ?", (b"ckbm.strict_json\nRendered\n.",))
    with PointStore(path, resume=True) as store:
        with pytest.raises(StoreError, match="without --resume, into a new store file"):
            store.run("a run", 1).load()
    with PointStore(tmp_path / "new.sqlite") as store:  # a store of this version loads
        store.run("a run", 1).save(0, [pickle.loads(pickle.dumps(2.0))])
    with PointStore(tmp_path / "new.sqlite", resume=True) as store:
        assert store.run("a run", 1).load() == {0: [2.0]}
