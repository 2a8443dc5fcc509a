"""The ``--vary`` axes of ``kbm friction``: the grammar of :mod:`numerics.cli._params` with
the sliders' checks of each axis (:func:`numerics.sliding.maps.axis_values`), and the
tables of a map and its ``--against`` one (:func:`print_tables`)."""

from __future__ import annotations

import numpy as np

from numerics.cli._params import MAX_POINTS, parse_vary

__all__ = ["MAX_POINTS", "parse_axis", "print_tables"]


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
