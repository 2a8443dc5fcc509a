"""The comparison figures (issue 4) are written to a chosen folder, as non-empty PNG files."""

from __future__ import annotations

import pytest

from numerics.paper.figures.comparison import COMPARISON_FIGURES, comparison_figures

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def test_comparison_figures_written(tmp_path):
    """Every registered comparison figure (convergence, validity map, phase portraits of the
    paper's Fig. 3 and of small-Delta cases) is a non-empty PNG in the folder asked for."""
    out = tmp_path / "figs"
    paths = comparison_figures(out, quick=True)
    assert {p.stem for p in paths} == set(COMPARISON_FIGURES)
    for p in paths:
        assert p.parent == out
        data = p.read_bytes()
        assert data[:8] == PNG_MAGIC and len(data) > 10_000, p


@pytest.mark.slow
def test_comparison_figures_full(tmp_path):
    """The full-size figures (validity grid of numerics.paper.validity.DEFAULT_GRID)."""
    paths = comparison_figures(tmp_path)
    assert all(p.stat().st_size > 10_000 for p in paths)
