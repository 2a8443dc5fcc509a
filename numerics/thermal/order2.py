"""The second-order amplitude averaging in the stationary report (``kbm noise --order 2``).

:mod:`kbm.noise.stochastic_order2` expands the stationary Fokker-Planck equation in ``mu`` at fixed
``D/mu``; this module puts its moments and density where :func:`numerics.thermal.stationary.
noise_report` reports the first-order ones, so that the validity flag, the figure and the
JSON all speak of the order that is reported (``averaged_order``).
"""

from __future__ import annotations

import numpy as np

from .averaged import AMPLITUDE

__all__ = ["second_order", "order2_bins"]


def second_order(model, params: dict, D: float, avg) -> tuple[object | None, dict, str]:
    """The second-order averaging of ``model`` at ``params`` (``D`` apart), or why not.

    Parameters
    ----------
    model : str or kbm.model.builtins.Oscillator
    params : dict
        The model's parameters, without ``D``.
    D : float
        The noise intensity.
    avg : numerics.thermal.averaged.AveragedStationary or None
        The first-order result (order 2 applies where it is the amplitude averaging).

    Returns
    -------
    tuple
        ``(so, values, message)``: the :class:`kbm.noise.stochastic_order2.SecondOrderAveraging`
        and the parameter values it is evaluated at, or ``None`` with the reason the first
        order is kept.
    """
    from kbm.errors import KBMError
    from kbm.noise.stochastic_order2 import stochastic_average_order2

    if avg is None:
        return None, {}, "no averaged prediction to correct"
    if avg.method != AMPLITUDE:
        return None, {}, "--order 2 applies to the amplitude averaging only: first order given"
    values = {**params, "D": D}
    try:
        so = stochastic_average_order2(model, dict(params))
        so.moment(2, values)  # evaluable at these values (raises what is missing)
    except KBMError as exc:
        return None, {}, f"no second-order averaging ({exc}): first order given"
    return so, values, ""


def order2_bins(so, values: dict, edges) -> list[float]:
    """The second-order amplitude density averaged over each bin of ``edges`` (16-point
    Gauss-Legendre per bin)."""
    edges = np.asarray(edges, float)
    g, w = np.polynomial.legendre.leggauss(16)
    # all bins' nodes in one call (the support and normalisation found once)
    dens = so.density(edges[:-1, None] + np.diff(edges)[:, None] * (g + 1) / 2, values)
    return [float(np.sum(w * row) / 2) for row in np.asarray(dens)]
