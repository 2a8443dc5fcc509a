"""All figures of the project, by name: the paper's Figs. 2-6, the KBM comparison and the
map of where classical KBM and the energy method hold (``methods_map``, the headline;
``validity_map`` is kept), and the friction laws and maps of the sliders.

``FIGURES`` maps a name to a function ``f(out_dir) -> list[Path]``;
:func:`write_figures` runs them (all, or those named).  matplotlib is imported
lazily inside the drawing modules (Agg backend), never by :mod:`kbm`.

The figures of forced oscillators (``docs/forced.rst``: response curves, Mathieu tongues,
entrainment) are :mod:`numerics.paper.figures.forced`, written by
``python -m numerics.paper.figures.forced DIR``; its
:func:`~numerics.paper.figures.forced.plot_response` and
:func:`~numerics.paper.figures.forced.plot_convergence` draw ``kbm response --out``.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from pathlib import Path

from kbm.errors import KBMError

__all__ = ["FIGURES", "write_figures"]


def _figure(module: str, name: str) -> Callable[[Path], list[Path]]:
    """``f(out_dir)``: ``name`` of :mod:`numerics.paper.figures.<module>`, imported when run."""
    def run(out_dir: Path) -> list[Path]:
        import importlib

        return getattr(importlib.import_module(f"numerics.paper.figures.{module}"),
                       name)(Path(out_dir))
    run.__doc__ = f"numerics.paper.figures.{module}.{name}"
    return run


#: every figure by name
FIGURES: dict[str, Callable[[Path], list[Path]]] = {
    "fig2_potential": _figure("paper", "fig2_potential"),
    "fig3_phase_portraits": _figure("paper", "fig3_phase_portraits"),
    "fig4_sliding": _figure("paper", "fig4_sliding"),
    "fig5_sedf_vs_cdc": _figure("paper", "fig5_sedf_vs_cdc"),
    "fig6_kinetic_friction": _figure("paper", "fig6_kinetic_friction"),
    "methods_map": _figure("methods", "methods_figure"),
    "fixed_delta_convergence": _figure("methods", "fixed_delta_figure"),
    "convergence": _figure("comparison", "convergence_figure"),
    "validity_map": _figure("comparison", "validity_figure"),
    "phase_fig3_kbm": _figure("comparison", "phase_fig3_figure"),
    "phase_small_kbm": _figure("comparison", "phase_small_figure"),
    "sedf_branches": _figure("branches", "sedf_branches"),
    "friction": _figure("friction", "friction_figures"),
}


def write_figures(out_dir: str | Path, only: Iterable[str] | None = None,
                  progress: Callable[[str], None] | None = None) -> list[Path]:
    """Write the figures named in ``only`` (default: all) into ``out_dir``.

    Raises
    ------
    kbm.errors.KBMError
        For an unknown figure name (the known names are listed).
    """
    names = list(FIGURES) if only is None else list(only)
    unknown = [n for n in names if n not in FIGURES]
    if unknown:
        raise KBMError(f"unknown figure(s) {', '.join(unknown)}; the figures are "
                       f"{', '.join(FIGURES)}")
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    paths: list[Path] = []
    for n in names:
        if progress:
            progress(n)
        paths.extend(FIGURES[n](out))
    return paths
