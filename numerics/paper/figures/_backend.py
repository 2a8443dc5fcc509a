"""What every figure module shares: pyplot on the Agg backend (imported on first use, never
by :mod:`kbm`) and the writer of a figure as PNG and PDF without timestamps."""

from __future__ import annotations

from pathlib import Path


def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def save_png_pdf(fig, path: Path) -> list[Path]:
    """Write ``fig`` as ``path`` with the suffixes ``.png`` and ``.pdf`` (130 dpi, no
    creation date or software stamp: the same bytes for the same figure); closes it."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    out = []
    for ext in ("png", "pdf"):
        p = path.with_suffix(f".{ext}")
        fig.savefig(p, dpi=130, bbox_inches="tight", metadata={"CreationDate": None}
                    if ext == "pdf" else {"Software": None})
        out.append(p)
    _plt().close(fig)
    return out
