"""The measured default step of the Langevin integrator (:func:`measured_step`, the step
pilot that :func:`numerics.thermal.stationary.default_times` runs after
:func:`numerics.noise.langevin.natural_step`): the scheme at ``h`` and ``h/2`` on one
Brownian path, the bias by Richardson, and the test whether the pilot can resolve its
tolerance within its budget (:func:`reachable_stderr`)."""

from __future__ import annotations

import math

import numpy as np

__all__ = ["measured_step", "reachable_stderr", "BIAS_TOLERANCE", "PILOT_FLOOR"]

#: the relative bias of the stationary <x^2> and <a^2> that the measured step allows
#: (:func:`measured_step`): 0.15 standard errors of a 1000-trajectory default run
BIAS_TOLERANCE = 2e-4

#: the fewest trajectories whose spread the step pilot's test trusts (:func:`measured_step`)
PILOT_FLOOR = 32


def measured_step(system, h0: float, *, tolerance: float = BIAS_TOLERANCE,
                  trajectories: int = 256, seed: int = 0, rounds: int = 3,
                  budget: float = 1e7) -> tuple[float, dict]:
    """The step whose measured bias of the stationary ``<x^2>`` and ``<a^2>`` stays below
    ``tolerance`` (relative), starting from ``h0``
    (:func:`numerics.noise.langevin.natural_step`).

    A pilot ensemble (``trajectories`` trajectories, ``10/mu`` burn-in and ``40/mu`` of
    averaging) runs at ``h`` and at ``h/2`` on the same Brownian path
    (``step_pair_stats``: Gaussian increments, the two fine ones summing to the coarse one),
    so the per-trajectory difference of the two time averages has a small variance.  The
    scheme is of weak order 2, so the bias at ``h`` is ``b(h) = (4/3) (E_h - E_{h/2})``
    (Richardson); with its standard error ``se``, the step is accepted unless ``|b| >
    tolerance |E| + 2 se`` for one of the moments (a bias measured beyond the tolerance),
    else shrunk to ``0.9 h sqrt(tolerance |E|/|b|)`` (at most by 2) and measured again,
    ``rounds`` times at most.  The paths at ``h`` and ``h/2`` drift apart in phase (and
    between wells), so ``se`` does not vanish with ``h``: the pilot shrinks the step only
    on a bias it resolves.  The pilot measures the Gaussian scheme's bias; the stationary
    ensembles run four-point Gauss-Hermite increments (``stationary_stats4``), whose moments
    are the Gaussian's up to the seventh, so that their ``h^2`` coefficient is the one the
    pilot measures (the three-point increments' is about 1.5 times it: BAOAB on ``x'' + x =
    -x' - x^3 + sqrt(2) xi``, -7.55e-3 against -4.86e-3 at h = 0.4;
    ``tests/test_noise_extrapolation.py``).  The heating rule of
    :func:`numerics.noise.langevin.natural_step` bounds the linear part only: van der Pol
    at mu = 0.3 (its nonlinear damping) was 0.56 % low at its step.

    The pilot spends at most ``budget`` steps (``h`` and ``h/2`` together) when the budget
    affords :data:`PILOT_FLOOR` trajectories, the fewest whose spread the test above
    trusts.  When it affords fewer (low friction: the pilot's length grows like
    ``1/(mu h)``), a probe of the trajectories the budget affords measures the spread
    first, and the pilot runs on :data:`PILOT_FLOOR` only if it can resolve its
    tolerance within the budget: the standard error it can reach there,
    :func:`reachable_stderr` (the probe's spread at its lower 95 % confidence bound over
    the square root of the trajectories the budget affords), at most half the tolerance
    for one of the moments (a bias of the tolerance two standard errors away).  Else, and
    when the budget affords fewer than two trajectories (no standard error at all), the
    step is ``h0``, unmeasured (``resolved`` false).  SEDF at rest, Delta = 3, D = mu/2:
    at mu = 0.01 the 32-trajectory pilot took 13.3 s, 20 times its budget, for a
    standard error of 3.3 % against the tolerance 2e-4, and accepted ``h0``; the budget
    affords one trajectory there.  At mu = 0.015 to 0.05 the probes (2 to 13
    trajectories, 0.5 to 0.7 s) reach 1.6 % to 4 % at best, and the 32-trajectory pilots
    (2 to 8 s) had accepted ``h0`` with 2.7 % to 3.6 %.  The probe's trajectories are the
    pilot's first ones, so a pilot that runs gives the same step.

    Returns
    -------
    (float, dict)
        The step and the last pilot's ``{"h", "bias_x2", "bias_a2", "stderr_x2",
        "stderr_a2", "accepted"}`` (relative values), with ``resolved`` (whether the
        standard error resolves the tolerance: ``2 se <= tolerance`` for one moment),
        ``outcome`` (``"accepted"``: the first step, no bias measured beyond the
        tolerance; ``"shrunk"``; ``"unresolved"``: the step ``h0`` unmeasured, the pilot
        could not resolve its tolerance within its budget),
        ``trajectories`` (of the last round or the probe), ``steps`` (all the pilot's
        integration steps), ``budget``, ``tolerance``, and after a probe ``probe`` (its
        trajectories) and ``reachable_stderr_x2``, ``reachable_stderr_a2``.
    """
    from .seeds import trajectory_states as _states

    mu = abs(system.bound.mu or 0.0)
    if mu == 0 or system.D == 0:
        return h0, _pilot_record({"h": h0, "accepted": True, "resolved": False,
                                  "trajectories": 0}, 0, budget, tolerance, {}, "not run")
    p = system._p()
    if system.scheme == "baoab":  # one force evaluation per step: the same work as KP at h0
        h0 = h0 / 2
    # the pilot's steps (h and h/2: three per coarse step) stay within the budget
    per = 3 * 50 / mu / h0
    afford = int(budget // per)
    trajectories = int(min(trajectories, max(PILOT_FLOOR, afford)))
    y0 = np.zeros((trajectories, 2))
    states = _states(seed, 0, trajectories, stream=(2**31 - 1,))
    h = float(h0)
    spent = 0
    extra: dict = {}

    def pair_rows(h, first, count):
        nonlocal spent
        n_burn = max(1, math.ceil(10 / mu / h))
        n_run = max(1, math.ceil(40 / mu / h))
        spent += 3 * (n_burn + n_run) * count
        return system.kernels.step_pair_stats(p, system.sigma, y0[first:first + count], 0.0,
                                              h, n_burn, n_run, states[first:first + count],
                                              system.omega0)

    rows = None
    if afford < 2:  # no standard error within the budget
        info = {"h": h, "accepted": True, "resolved": False, "trajectories": 0}
        return h, _pilot_record(info, spent, budget, tolerance, {
            "probe": 0, "reachable_stderr_x2": None, "reachable_stderr_a2": None},
            "unresolved")
    if afford < PILOT_FLOOR:  # the probe: can the pilot resolve its tolerance?
        probe = afford
        rows = pair_rows(h, 0, probe)
        if np.all(np.isfinite(rows)):
            info = dict(_pilot_bias(rows), h=h)
            reach = {k: reachable_stderr(rows, c, f, max(afford, probe))
                     for k, c, f in (("x2", 0, 2), ("a2", 1, 3))}
            extra = {"probe": probe, "reachable_stderr_x2": reach["x2"],
                     "reachable_stderr_a2": reach["a2"]}
            if min(reach.values()) > tolerance / 2:
                info.update(accepted=True, resolved=False, trajectories=probe)
                return h, _pilot_record(info, spent, budget, tolerance, extra, "unresolved")
            rows = np.vstack([rows, pair_rows(h, probe, trajectories - probe)])
        else:
            rows = None
    info: dict = {}
    for _ in range(rounds):
        if rows is None:
            rows = pair_rows(h, 0, trajectories)
        if not np.all(np.isfinite(rows)):
            h /= 4
            rows = None
            continue
        info = dict(_pilot_bias(rows), h=h)
        worst = 0.0
        for name in ("x2", "a2"):
            b, se = info[f"bias_{name}"], info[f"stderr_{name}"]
            if abs(b) > tolerance + 2 * se:
                worst = max(worst, abs(b) / tolerance)
        info["accepted"] = worst == 0.0
        info["resolved"] = min(info["stderr_x2"], info["stderr_a2"]) <= tolerance / 2
        info["trajectories"] = trajectories
        rows = None
        if info["accepted"]:
            break
        h *= max(0.5, 0.9 / math.sqrt(worst))
    return h, _pilot_record(info, spent, budget, tolerance, extra,
                            "accepted" if h == h0 else "shrunk")


def _pilot_bias(rows: np.ndarray) -> dict:
    """The relative bias ``(4/3) (E_h - E_{h/2})/E_{h/2}`` of ``<x^2>`` and ``<a^2>`` and
    its standard error from the rows of ``step_pair_stats``."""
    out = {}
    # finite rows whose squares overflow (D = 1e300) give an infinite standard error, an
    # unresolved bias, without a RuntimeWarning on stderr
    with np.errstate(over="ignore", invalid="ignore"):
        for name, c, f in (("x2", 0, 2), ("a2", 1, 3)):
            d = 4.0 / 3.0 * (rows[:, c] - rows[:, f])
            ref = float(np.mean(rows[:, f]))
            out[f"bias_{name}"] = float(np.mean(d)) / ref
            out[f"stderr_{name}"] = float(np.std(d, ddof=1) / math.sqrt(d.size)) / ref
    return out


def _pilot_record(info: dict, spent: int, budget: float, tolerance: float, extra: dict,
                  outcome: str) -> dict:
    """The pilot's record (:func:`measured_step`'s second value)."""
    return {**info, "outcome": outcome, "steps": spent, "budget": budget,
            "tolerance": tolerance, **extra}


def reachable_stderr(rows: np.ndarray, coarse: int, fine: int, count: int) -> float:
    """The smallest relative standard error of the step's bias that ``count`` trajectories
    can reach, judged from the probe's ``rows`` (columns ``coarse`` and ``fine`` of
    ``step_pair_stats``): the lower 95 % confidence bound of the per-trajectory spread
    (``s ((n - 1)/chi2_{0.975, n-1})^(1/2)``, ``n`` the probe's trajectories) over
    ``count^(1/2)``."""
    from scipy.stats import chi2

    with np.errstate(over="ignore", invalid="ignore"):  # as _pilot_bias: inf, unresolved
        d = 4.0 / 3.0 * (rows[:, coarse] - rows[:, fine])
        n = d.size
        low = float(np.std(d, ddof=1)) * math.sqrt((n - 1) / chi2.ppf(0.975, n - 1))
        return low / math.sqrt(count) / abs(float(np.mean(rows[:, fine])))
