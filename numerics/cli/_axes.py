"""The ``--vary NAME=FROM:TO[:N|:logN]`` axes of ``kbm friction`` (one and many sliders)."""

from __future__ import annotations

import math

import numpy as np

#: the largest grid one command computes
MAX_POINTS = 100_000


def parse_axis(text: str) -> tuple[str, np.ndarray]:
    """``"v=1e-3:3:log24"`` -> ``("v", 24 log-spaced values)``; ``"Delta=0.5:3:6"``,
    ``"beta=0.5,1,2"``, ``"v=0.1"`` likewise.

    Raises
    ------
    kbm.errors.ParameterError
        Saying the forms --vary takes.
    """
    from kbm.errors import ParameterError
    from numerics.sliding.maps import axis_values

    usage = ("--vary takes NAME=FROM:TO[:N] (N equally spaced, default 8), NAME=FROM:TO:logN "
             "(N log-spaced) or NAME=A,B,C")
    name, sep, spec = text.partition("=")
    name, spec = name.strip(), spec.strip()
    if not (sep and name and spec):
        raise ParameterError(f"{usage}; got {text!r}")
    parts = spec.split(":")
    try:
        if len(parts) == 1:
            listed = np.array([float(x) for x in spec.split(",")])
        elif len(parts) not in (2, 3):
            raise ValueError
        else:
            lo, hi = float(parts[0]), float(parts[1])
            count = parts[2].strip() if len(parts) == 3 else "8"
            log = count.lower().startswith("log")
            n = int(count[3:] if log else count)
    except ValueError:
        raise ParameterError(f"{usage}; got {text!r}") from None
    if len(parts) == 1:
        return name, axis_values(name, listed)
    if not 1 <= n <= MAX_POINTS:
        raise ParameterError(f"--vary {name}: the number of values must be between 1 and "
                             f"{MAX_POINTS}, got {n}")
    if not (math.isfinite(lo) and math.isfinite(hi)):
        raise ParameterError(f"--vary {name}: FROM and TO must be finite, got {spec!r}")
    if log and (lo <= 0 or hi <= 0):
        raise ParameterError(f"--vary {name}: a log range needs FROM, TO > 0, got {spec!r}")
    values = np.geomspace(lo, hi, n) if log else np.linspace(lo, hi, n)
    return name, axis_values(name, values)
