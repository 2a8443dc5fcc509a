"""The methods map and fixed-Delta convergence figures are registered by name and written
as non-empty PNG files."""

from __future__ import annotations

from numerics.paper.figures import FIGURES
from numerics.paper.figures.methods import fixed_delta_figure, methods_figure

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def test_methods_figures_registered_and_written(tmp_path):
    """'methods_map' (the headline map, next to the kept 'validity_map') and
    'fixed_delta_convergence' are in the registry; their quick versions write PNGs of
    more than 10 kB into the folder asked for."""
    assert {"methods_map", "fixed_delta_convergence", "validity_map"} <= set(FIGURES)
    paths = methods_figure(tmp_path, quick=True) + fixed_delta_figure(tmp_path, quick=True)
    assert [p.name for p in paths] == ["methods_map.png", "fixed_delta_convergence.png"]
    for p in paths:
        assert p.parent == tmp_path
        data = p.read_bytes()
        assert data[:8] == PNG_MAGIC and len(data) > 10_000, p
