"""The comparison figures (issue 4) are written to a chosen folder, as non-empty PNG files."""

from __future__ import annotations

import pytest

from numerics.paper.figures import FIGURES
from numerics.paper.figures.comparison import (convergence_figure, phase_fig3_figure,
                                               phase_small_figure, validity_figure)

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
#: the comparison figures and the files they write
DRAWINGS = {convergence_figure: "kbm_convergence", validity_figure: "kbm_validity",
            phase_fig3_figure: "kbm_phase_fig3", phase_small_figure: "kbm_phase_small"}


def test_comparison_figures_written(tmp_path):
    """Every comparison figure (convergence, validity map, phase portraits of the paper's
    Fig. 3 and of small-Delta cases) is a non-empty PNG in the folder asked for, and each
    is one of the project's figures (numerics.paper.figures.FIGURES)."""
    out = tmp_path / "figs"
    for draw, stem in DRAWINGS.items():
        (p,) = draw(out, quick=True)
        assert p.parent == out and p.stem == stem
        data = p.read_bytes()
        assert data[:8] == PNG_MAGIC and len(data) > 10_000, p
    registered = {f.__doc__ for f in FIGURES.values()}
    assert {f"numerics.paper.figures.comparison.{d.__name__}" for d in DRAWINGS} <= registered


@pytest.mark.slow
def test_comparison_figures_full(tmp_path):
    """The full-size figures (validity grid of numerics.paper.validity.DEFAULT_GRID)."""
    for draw in DRAWINGS:
        assert all(p.stat().st_size > 10_000 for p in draw(tmp_path))
