"""The gap between an averaged number and its simulated estimate, in standard errors, and
the flag ``|z| > Z_FLAG`` that ``kbm noise`` and ``kbm spectrum`` report (issue 36:
validity in every output).

Under the null hypothesis that the averaged value is the ensemble's mean, the simulated
estimate is a mean over many independent trajectories, asymptotically normal (central
limit theorem), so ``z = (averaged - simulated)/stderr`` is standard normal and
``|z| > 4`` happens by chance with probability 6e-5: a flagged gap is the averaging's
error (or a run too short for its standard error to be trusted), not the statistics.
"""

from __future__ import annotations

from collections.abc import Mapping

__all__ = ["Z_FLAG", "gap_z"]

#: a gap |averaged - simulated|/stderr above this is flagged
Z_FLAG = 4.0


def gap_z(entries: Mapping[str, Mapping]) -> tuple[dict, list[str]]:
    """The gap ``(averaged - simulated)/stderr`` of each entry and the entries beyond
    :data:`Z_FLAG`.

    Parameters
    ----------
    entries : mapping
        Name to a mapping with ``averaged``, ``simulated`` and ``stderr`` (any may be
        ``None``; a zero ``stderr`` gives no gap either).

    Returns
    -------
    z : dict
        Name to the gap, ``None`` where a number is missing.
    flagged : list of str
        The names with ``|z| > Z_FLAG``, in the order of ``entries``.
    """
    z = {}
    for key, m in entries.items():
        ok = m.get("averaged") is not None and m.get("simulated") is not None and m.get(
            "stderr")
        z[key] = (m["averaged"] - m["simulated"]) / m["stderr"] if ok else None
    return z, [k for k, v in z.items() if v is not None and abs(v) > Z_FLAG]
