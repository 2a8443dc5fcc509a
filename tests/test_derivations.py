"""derivations/ is generated: committed files equal a fresh regeneration, byte for byte,
whatever PYTHONHASHSEED (issue 6)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DERIV = ROOT / "derivations"


def _regenerate(out: Path, seed: str) -> dict[str, bytes]:
    env = dict(os.environ, PYTHONHASHSEED=seed)
    subprocess.run([sys.executable, "-m", "numerics.cli", "derivations", "--out", str(out)],
                   check=True, capture_output=True, env=env, timeout=900, cwd=ROOT)
    return {p.name: p.read_bytes() for p in sorted(out.glob("*.tex"))}


@pytest.fixture(scope="module")
def fresh(tmp_path_factory):
    return _regenerate(tmp_path_factory.mktemp("deriv0"), "0")


def test_committed_derivations_equal_fresh_regeneration(fresh):
    """Every committed .tex file equals the regenerated one, and no file is missing or extra:
    a change in the engine that changes a formula shows up as a diff in derivations/."""
    committed = {p.name: p.read_bytes() for p in sorted(DERIV.glob("*.tex"))}
    assert sorted(committed) == sorted(fresh)
    for name in fresh:
        assert committed[name] == fresh[name], f"derivations/{name} is stale: run " \
                                               "`kbm derivations --out derivations`"


def test_regeneration_is_independent_of_hash_seed(fresh, tmp_path):
    """Set and dict order must not leak into the output: another PYTHONHASHSEED, same bytes."""
    other = _regenerate(tmp_path / "seed", "12345")
    assert other == fresh


def test_every_file_has_the_banner(fresh):
    """Each generated file starts with a banner naming the command that regenerates it."""
    for name, data in fresh.items():
        head = data.decode().splitlines()[:2]
        assert any("kbm derivations --out derivations" in ln for ln in head), name
