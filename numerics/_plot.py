"""The figures' plumbing: matplotlib's pyplot on the Agg backend, imported only when a
figure is drawn (never by :mod:`kbm`), and the writing of a finished figure (PNG, or PNG and
PDF without time stamps, so that the same input gives the same bytes)."""

from __future__ import annotations

from pathlib import Path

__all__ = ["pyplot", "save", "save_png_pdf"]


def pyplot():
    """``matplotlib.pyplot`` on the Agg backend."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def save(fig, ax, path: Path) -> Path:
    """Legend, layout, write ``path`` (its folder made), close."""
    ax.legend(fontsize=8)
    fig.tight_layout()
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=120)
    pyplot().close(fig)
    return path


def save_png_pdf(fig, path: Path) -> list[Path]:
    """``path`` as ``.png`` and ``.pdf`` (its folder made, tight box, no time stamps), closed."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    out = []
    for ext in ("png", "pdf"):
        p = path.with_suffix(f".{ext}")
        fig.savefig(p, dpi=130, bbox_inches="tight", metadata={"CreationDate": None}
                    if ext == "pdf" else {"Software": None})
        out.append(p)
    pyplot().close(fig)
    return out
