"""Output folders and files: an unwritable path is a :class:`kbm.errors.OutputError`, not a
traceback (the message names the argument, the path and the reason)."""

from __future__ import annotations

from pathlib import Path

from ..errors import OutputError

__all__ = ["output_folder", "check_folder", "write_file"]


def output_folder(path: str | Path, argument: str = "out") -> Path:
    """The folder ``path``, created if missing.

    Parameters
    ----------
    path
        The folder.
    argument
        The name of the argument (or command-line flag) that gave it, for the message.

    Raises
    ------
    kbm.errors.OutputError
        If ``path`` is a file, or the folder cannot be created or written to.
    """
    folder = Path(path)
    if folder.exists() and not folder.is_dir():
        raise OutputError(f"{argument} = {str(folder)!r} is a file, not a folder; name a "
                          "folder (it is created if missing)")
    try:
        folder.mkdir(parents=True, exist_ok=True)
        probe = folder / ".kbm-write-probe"
        probe.write_bytes(b"")
        probe.unlink()
    except OSError as exc:
        raise OutputError(f"cannot write to {argument} = {str(folder)!r}: "
                          f"{exc.strerror or exc}; name a writable folder") from None
    return folder


def check_folder(path: str | Path, argument: str = "out") -> None:
    """Refuse, before any work and without creating anything, a folder ``path`` that
    :func:`output_folder` could not make: a file, a path under a file, or one whose nearest
    existing ancestor takes no new file (the commands wrote their ``--out`` after the whole
    computation, and failed only then: ``kbm diagram ... --out /proc/x`` after minutes).

    Raises
    ------
    kbm.errors.OutputError
        As :func:`output_folder`.
    """
    import tempfile

    folder = Path(path)
    if folder.exists() and not folder.is_dir():
        raise OutputError(f"{argument} = {str(folder)!r} is a file, not a folder; name a "
                          "folder (it is created if missing)")
    base = folder.absolute()
    while not base.exists():
        base = base.parent
    try:
        if not base.is_dir():
            raise NotADirectoryError(20, f"{str(base)!r} is a file")
        with tempfile.TemporaryFile(dir=base):
            pass
    except OSError as exc:
        raise OutputError(f"cannot write to {argument} = {str(folder)!r}: "
                          f"{exc.strerror or exc}; name a writable folder") from None


def write_file(path: str | Path, data: str | bytes) -> Path:
    """Write ``data`` (text as UTF-8) to ``path``; returns the path.

    Raises
    ------
    kbm.errors.OutputError
        If the file cannot be written (with the reason).
    """
    p = Path(path)
    try:
        p.write_bytes(data.encode("utf-8") if isinstance(data, str) else data)
    except OSError as exc:
        raise OutputError(f"cannot write {str(p)!r}: {exc.strerror or exc}") from None
    return p
