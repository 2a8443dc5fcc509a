"""The gap between an averaged number and its simulated estimate, in standard errors, and
the flag ``|z| > Z_FLAG`` that ``kbm noise`` and ``kbm spectrum`` report (issue 36:
validity in every output).

Under the null hypothesis that the averaged value is the ensemble's mean, the simulated
estimate is a mean over many independent trajectories, asymptotically normal (central
limit theorem), so ``z = (averaged - simulated)/stderr`` is standard normal and
``|z| > 4`` happens by chance with probability 6e-5: a flagged gap is the averaging's
error (or a run too short for its standard error to be trusted), not the statistics.

:func:`averaged_error` is the rule by which each averaged number states its expected error
(``kbm noise``'s moments, :mod:`numerics.thermal.averaged_error`; ``kbm spectrum``'s line
width and line centre, :func:`numerics.spectrum.result.line_errors`), from the best
reference the run has, in this order:

1. ``"fokker-planck"``: a solution that owes nothing to averaging, ``|averaged - FP| + e
   |FP|`` with ``e`` its stated relative error (``kbm noise``'s stationary Kramers
   solution), unless ``e |FP|`` exceeds the next source's estimate (a reference less
   certain than the error it would measure);
2. ``"next order"``: at first order, where the second order applies, the size of the next
   order's correction ``|X_2 - X_1|`` (the error of an asymptotic series is about its first
   omitted term);
3. ``"simulation"``: ``|averaged - simulated| + 2 stderr``, a bound at two standard errors
   of the ensemble (a Monte Carlo statement);
4. ``None`` with the source ``"none"``: no reference, said so rather than guessed.

``kbm spectrum``'s order-2 line width and line centre add ``"true cycle"`` (the error of
their small-noise part against the true cycle's phase response and frequency, where larger
than the simulation's bound; without a simulation plus the whole noise-induced part; :func:`numerics.spectrum.result.line_errors`): no averaged
term states the size of their next-order error.

How close each estimate came to the true error is measured where it is used: the module
docstrings of :mod:`numerics.thermal.averaged_error` and :mod:`numerics.spectrum.result`.

:func:`validity_entry` builds the ``validity`` entry of every output (``kbm noise``, ``kbm
spectrum``'s line, response spectra and phase slips, ``kbm escape``), and
:func:`joined_validity` the one entry of several runs; only the advice differs.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence

__all__ = ["Z_FLAG", "gap_z", "validity_entry", "joined_validity", "averaged_error",
           "ERROR_SOURCES"]

#: a gap |averaged - simulated|/stderr above this is flagged
Z_FLAG = 4.0
#: how the text output names each source of :func:`averaged_error`
ERROR_SOURCES = {"fokker-planck": "against the Fokker-Planck solution",
                 "next order": "the next order's correction",
                 "simulation": "|averaged - simulated| + 2 stderr",
                 "true cycle": "against the true cycle; without a simulation plus the "
                               "noise-induced part"}


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


def validity_entry(z, flagged, advice: str | Callable[[], str] = "", *, key: str = "z",
                   **extra) -> dict:
    """The ``validity`` entry of an output: ``{key: z, "flagged", "threshold", "advice",
    **extra}`` in this order, ``advice`` (called if callable) where ``flagged`` is truthy
    (the flagged names, or a bool), else ``""``; ``z`` is :func:`gap_z`'s gaps, one of
    them, or (``key="z_rms"``) a root mean square over a spectrum's bins.

    Examples
    --------
    >>> validity_entry(*gap_z({"rate": {"averaged": 2.0, "simulated": 1.0, "stderr": 0.2}}),
    ...                lambda: "a smaller mu")
    {'z': {'rate': 5.0}, 'flagged': True, 'threshold': 4.0, 'advice': 'a smaller mu'}
    """
    return {key: z, "flagged": bool(flagged), "threshold": Z_FLAG,
            "advice": (advice() if callable(advice) else advice) if flagged else "", **extra}


def joined_validity(checks: Sequence[Mapping], z, key: str = "z") -> dict:
    """One :func:`validity_entry` for several runs' (``checks``, each a validity entry): the
    gaps ``z`` as the caller lists them, flagged where any run is, with the first flagged
    run's advice."""
    flagged = [v for v in checks if v["flagged"]]
    return validity_entry(z, flagged, lambda: flagged[0]["advice"], key=key)


def averaged_error(moment: Mapping, fp_change: float | None = None,
                   next_order: float | None = None) -> tuple[float | None, str]:
    """``(error, source)``: the expected absolute error of ``moment["averaged"]`` and where
    it comes from (the module docstring's rule).

    Parameters
    ----------
    moment : mapping
        ``averaged`` and, where the run has them, ``simulated`` and ``stderr`` (a simulated
        estimate comparable with the averaged one: a scheme's known bias already removed)
        and ``fokker_planck``.
    fp_change : float, optional
        The Fokker-Planck solution's stated relative error (``None``: not measured).
    next_order : float, optional
        The same number at the next order of the averaging (``None``: not available).

    Returns
    -------
    tuple
        The error (``None`` without a reference) and its source: ``"fokker-planck"``,
        ``"next order"``, ``"simulation"`` or ``"none"``.  The Fokker-Planck reference is
        passed over when its own error ``fp_change |FP|`` exceeds the next source's estimate.

    Examples
    --------
    >>> averaged_error({"averaged": 1.0, "fokker_planck": 1.25}, 0.0)
    (0.25, 'fokker-planck')
    >>> averaged_error({"averaged": 1.0, "simulated": 1.5, "stderr": 0.125})
    (0.75, 'simulation')
    >>> averaged_error({"averaged": 1.0, "fokker_planck": 1.25, "simulated": 1.0,
    ...                 "stderr": 0.125}, 0.5)
    (0.25, 'simulation')
    >>> averaged_error({"averaged": 1.0, "simulated": 1.5, "stderr": 0.125}, None, 0.875)
    (0.125, 'next order')
    """
    avg = moment.get("averaged")
    if avg is None:
        return None, "none"
    other = (None, "none")
    sim, se = moment.get("simulated"), moment.get("stderr")
    if next_order is not None and math.isfinite(next_order):
        other = abs(next_order - avg), "next order"
    elif sim is not None and se is not None and math.isfinite(se):
        other = abs(avg - sim) + 2.0 * se, "simulation"
    fp = moment.get("fokker_planck")
    if fp is not None and fp_change is not None and math.isfinite(fp_change) \
            and (other[0] is None or fp_change * abs(fp) <= other[0]):
        return abs(avg - fp) + fp_change * abs(fp), "fokker-planck"
    return other
