"""The ``--vary`` axes of ``kbm friction``: the grammar of :mod:`numerics.cli._params` with
the sliders' checks of each axis (:func:`numerics.sliding.maps.axis_values`), and the
output of a map and its ``--against`` one (:func:`print_tables`, :func:`emit_maps`)."""

from __future__ import annotations

import numpy as np

from numerics.cli._params import MAX_POINTS, parse_vary

__all__ = ["MAX_POINTS", "parse_axis", "print_tables", "emit_maps"]


def parse_axis(text: str) -> tuple[str, np.ndarray]:
    """``"v=1e-3:3:log24"`` -> ``("v", 24 log-spaced values)``; ``"Delta=0.5:3:6"``,
    ``"beta=0.5,1,2"``, ``"v=0.1"`` likewise (:func:`numerics.cli._params.parse_vary`).

    Raises
    ------
    kbm.errors.ParameterError
        Saying the forms --vary takes.
    """
    from numerics.sliding.maps import axis_values

    vary = parse_vary(text)
    return vary.name, axis_values(vary.name, vary.values())


def print_tables(first, second, printer) -> None:
    """``printer`` of the map and of the ``--against`` one (``second``, or ``None``), with a
    blank line between the two tables and none before the first."""
    for i, m in enumerate((first, second) if second is not None else (first,)):
        if i:
            print()
        printer(m)


def emit_maps(args, first, second, printer, figures, ratios=None) -> int:
    """A map and its ``--against`` one (``second``, or ``None``) as the command line asks:
    ``--json`` the first's JSON with the second's under ``against`` (and the keys of
    ``ratios(first, second)``), else the tables of ``printer``; ``--out DIR`` the paths of
    ``figures(first, second, DIR)`` named (on standard error with ``--json``, so that
    standard output holds the JSON only).  Returns the exit status 0."""
    import sys
    from pathlib import Path

    if args.json:
        from kbm.cli._common import emit_json

        data = first.to_json()
        if second is not None:
            data["against"] = second.to_json()
            data.update(ratios(first, second) if ratios else {})
        emit_json(data)
    else:
        print_tables(first, second, printer)
    if args.out:
        for path in figures(first, second, Path(args.out)):
            print(f"wrote {path}", file=sys.stderr if args.json else sys.stdout)
    return 0
